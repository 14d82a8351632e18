//! The work of a whole command, estimated before any work and said up front when it is long.
//!
//! Its terms: growing grains (the power diagram's neighbours, `domains.pattern = "grains"`,
//! and the parent grains of correlated orientations), once a command; and each frame's rays:
//! the path tracer's samples (pixels × `integrator.spp`), the lobe integrator's and the
//! stored method's camera rays (one through every pixel, `spp − 1` more where needed), the
//! light rays of the paper's two passes. Their costs are processor seconds measured with
//! `/usr/bin/time` (user time, release build) on the 2-core development machine and rounded
//! up. 2026-12-06: 250 000 grains took 14.3 s (57 µs a grain), 31 000 grains 1.74 s (56 µs);
//! the black opal path-traced at 64 × 48 took 1.9 s at 1 and 14.5 s at 8 samples per pixel
//! (580 µs a pixel's sample; the harlequin 300 µs). The lobe integrator and the others,
//! 2026-12-06 (load about 10), differences between renders of one scene at two sizes or
//! sample counts: `BENCHMARKS.md`, "The work estimate's costs".
//! The estimate divides by the worker threads; a busy machine takes longer.

use opalray::scene::{Method, OrientationLaw, Pattern};
use opalray::Scene;

/// Processor seconds to grow one grain (its neighbours found along 64 rays).
const GRAIN_CPU_S: f64 = 60e-6;
/// Processor seconds of one path-traced sample of one pixel of a gem (the black opal).
const PATH_SAMPLE_CPU_S: f64 = 600e-6;
/// Processor seconds of the lobe integrator's ray through a pixel's centre, in a gem's frame
/// (the black opal 22 µs; with [`LOBE_RAY_CPU_S`] 96 µs a pixel at 4 rays, where the ribbon,
/// the dearest opaque preset, takes about 105 µs).
const LOBE_PIXEL_CPU_S: f64 = 30e-6;
/// Processor seconds of each further lobe ray, `integrator.spp − 1` a pixel, averaged over
/// the frame (they are cast only where a pixel differs from its neighbours: the black opal
/// 17 µs).
const LOBE_RAY_CPU_S: f64 = 22e-6;
/// The lobe rays' cost in a clear stone (its potch passing more than 1/e through the dome,
/// `potch_extinction_per_mm × dome_height_mm < 1`), where every ray walks the whole stone:
/// the crystal 100 µs a centre ray and 67 µs a further one, 4.5 and 3.9 times the black opal's.
const LOBE_CLEAR_FACTOR: f64 = 4.0;
/// Processor seconds of the stored method's first camera ray of a pixel (the paper's stone
/// at 640 × 480, 3 µs) and of each further one (0.43 µs).
const STORED_PIXEL_CPU_S: f64 = 4e-6;
const STORED_RAY_CPU_S: f64 = 0.5e-6;
/// Processor seconds of a pixel of the paper's two passes (0.36 µs) and of one of their light
/// rays (`light.rays`, 1.4 µs), the paper's scene.
const TWO_PASS_PIXEL_CPU_S: f64 = 0.5e-6;
const LIGHT_RAY_CPU_S: f64 = 2e-6;
/// Work said up front when the estimate is over this, seconds.
pub const ANNOUNCE_OVER_S: f64 = 60.0;

/// The work of rendering a scene `frames` times (a stone grown once), by its terms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Work {
    /// Grains grown (and parent grains of correlated orientations).
    pub grains: f64,
    /// Path-traced samples, pixels × samples per pixel × frames.
    pub samples: f64,
    /// Camera rays of the lobe integrator or the stored method, at most pixels × `spp` ×
    /// frames, or the pixels of the two passes.
    pub rays: f64,
    /// Light rays of the two passes, `light.rays` × frames.
    pub light_rays: f64,
    /// Processor seconds of the whole.
    pub cpu_s: f64,
}

impl Work {
    /// The work of `scene` rendered `frames` times.
    pub fn of(scene: &Scene, frames: u64) -> Work {
        let method = scene.integrator.method();
        let grains = if method != Method::TwoPass {
            grains(scene)
        } else {
            0.0
        };
        let frames = frames as f64;
        let pixels = f64::from(scene.render.width) * f64::from(scene.render.height) * frames;
        let spp = f64::from(scene.integrator.spp().unwrap_or(1));
        let mut work = Work {
            grains,
            samples: 0.0,
            rays: 0.0,
            light_rays: 0.0,
            cpu_s: grains * GRAIN_CPU_S,
        };
        match method {
            Method::Path => {
                work.samples = pixels * spp;
                work.cpu_s += work.samples * PATH_SAMPLE_CPU_S;
            }
            Method::Lobe => {
                let b = &scene.body;
                let clear = b.potch_extinction_per_mm * b.dome_height_mm < 1.0;
                let factor = if clear { LOBE_CLEAR_FACTOR } else { 1.0 };
                work.rays = pixels * spp;
                work.cpu_s += factor * pixels * (LOBE_PIXEL_CPU_S + (spp - 1.0) * LOBE_RAY_CPU_S);
            }
            Method::Stored => {
                work.rays = pixels * spp;
                work.cpu_s += pixels * (STORED_PIXEL_CPU_S + (spp - 1.0) * STORED_RAY_CPU_S);
            }
            Method::TwoPass => {
                work.rays = pixels;
                work.light_rays = scene.light.rays as f64 * frames;
                work.cpu_s += pixels * TWO_PASS_PIXEL_CPU_S + work.light_rays * LIGHT_RAY_CPU_S;
            }
        }
        work
    }

    /// Estimated seconds on `threads` worker threads.
    pub fn seconds(&self, threads: usize) -> f64 {
        self.cpu_s / threads.max(1) as f64
    }
}

/// The grains `scene` grows (and the parent grains of correlated orientations), 0 for the
/// paper's balls.
fn grains(scene: &Scene) -> f64 {
    if scene.domains.pattern != Pattern::Grains {
        return 0.0;
    }
    let axes = scene.body.box_semi_axes(scene.structure.semi_axes_mm);
    let mut grains = scene.domains.grain_count(axes);
    if scene.domains.orientation == OrientationLaw::Correlated {
        let parents = opalray::scene::DomainsConfig {
            grain_size_mm: scene.domains.correlation_mm,
            stretch: [1.0; 3],
            boundary_roughness: 0.0,
            ..scene.domains.clone()
        };
        grains += parents.grain_count(axes);
    }
    grains
}

/// Say up front, on stderr, how long `scene` rendered `frames` times will take when the
/// estimate is over [`ANNOUNCE_OVER_S`], and what bounds it (`--time-limit`).
pub fn announce(scene: &Scene, frames: u64) {
    let work = Work::of(scene, frames);
    let threads = rayon::current_num_threads();
    let seconds = work.seconds(threads);
    if seconds <= ANNOUNCE_OVER_S {
        return;
    }
    let mut parts = Vec::new();
    if work.grains > 0.0 {
        parts.push(format!("{:.0} grains to grow", work.grains));
    }
    if work.samples > 0.0 {
        parts.push(format!("{:.2e} path samples", work.samples));
    }
    if work.rays > 0.0 {
        let kind = scene.integrator.method().name();
        parts.push(format!(
            "{:.2e} camera rays of the {kind} method",
            work.rays
        ));
    }
    if work.light_rays > 0.0 {
        parts.push(format!("{:.2e} light rays", work.light_rays));
    }
    crate::stdio::note(format_args!(
        "note: about {} of work by the estimate ({}) on {threads} worker thread{}; \
         --time-limit SECONDS bounds it",
        super::common::duration_words(seconds),
        parts.join(", "),
        if threads == 1 { "" } else { "s" }
    ));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_documented_largest_path_traced_image_is_hours_and_a_small_one_seconds() {
        let mut scene = opalray::scene::preset("black-opal").unwrap();
        scene.integrator = scene.integrator.switched(Method::Path);
        scene.render.width = 8;
        scene.render.height = 6;
        let small = Work::of(&scene, 1).seconds(2);
        assert!(small < 5.0, "{small}");
        scene.render.width = 16384;
        scene.render.height = 16384;
        // 2.7e8 pixels × spp samples × 600 µs on 2 threads: days.
        let large = Work::of(&scene, 1).seconds(2);
        assert!(large > 24.0 * 3600.0, "{large}");
    }

    #[test]
    fn grains_near_the_limit_are_tens_of_seconds_on_one_thread() {
        // The review's 25–56 s for grains near `MAX_GRAINS` (250 000): 15 s of processor
        // time at 60 µs a grain, more on a busy machine.
        let text = "[integrator]\nmethod = \"lobe\"\n[domains]\npattern = \"grains\"\n\
                    grain_size_mm = 0.24";
        let mut scene = Scene::from_toml_str(text, "t").unwrap();
        // An image of a few pixels: the grains alone.
        scene.render.width = 8;
        scene.render.height = 6;
        let work = Work::of(&scene, 1);
        assert!((2.0e5..2.5e5).contains(&work.grains), "{work:?}");
        let seconds = work.seconds(1);
        assert!((12.0..15.0).contains(&seconds), "{seconds}");
    }

    #[test]
    fn the_lobe_estimate_covers_the_renders_measured_and_not_by_much() {
        // Processor seconds measured (`/usr/bin/time`, user, 2026-12-06; BENCHMARKS.md):
        // the black opal at 640 × 480, 4 rays, 22.2 s; at 320 × 240, 16 rays, 23.4 s; the
        // crystal (a clear stone) at 320 × 240, 4 rays, 23.6 s; the harlequin 2.7 s.
        let measured = [
            ("black-opal", 640, 480, 4, 22.2),
            ("black-opal", 320, 240, 16, 23.4),
            ("crystal", 320, 240, 4, 23.6),
        ];
        for (preset, width, height, spp, cpu_s) in measured {
            let mut scene = opalray::scene::preset(preset).unwrap();
            scene.render.width = width;
            scene.render.height = height;
            scene.integrator.set_spp(spp);
            let estimate = Work::of(&scene, 1).seconds(1);
            assert!(
                (cpu_s..1.5 * cpu_s).contains(&estimate),
                "{preset} {width}×{height} at {spp}: {estimate} s, measured {cpu_s} s"
            );
        }
    }

    #[test]
    fn every_method_counts_its_rays_per_frame() {
        let mut scene = opalray::scene::preset("paper").unwrap();
        scene.render.width = 100;
        scene.render.height = 10;
        let one = Work::of(&scene, 1);
        let three = Work::of(&scene, 3);
        assert_eq!(
            (one.rays, one.light_rays),
            (1000.0, scene.light.rays as f64)
        );
        assert_eq!(
            (three.rays, three.light_rays),
            (3.0 * one.rays, 3.0 * one.light_rays)
        );
        assert!((three.cpu_s - 3.0 * one.cpu_s).abs() < 1e-12);
        scene.integrator = scene.integrator.switched(Method::Stored);
        scene.integrator.set_spp(4);
        assert_eq!(Work::of(&scene, 2).rays, 8000.0);
    }
}

//! The work of a whole command, estimated before any work and said up front when it is long.
//!
//! Its terms: growing grains (the power diagram's neighbours, `domains.pattern = "grains"`,
//! and the parent grains of correlated orientations), once a command, for a method that
//! renders the stone model; and each frame's rays, as the scene's method estimates them
//! (`Integrator::work`: the path tracer's samples, the lobe integrator's and the stored
//! method's camera rays, the light rays of the paper's two passes). Their costs are processor
//! seconds measured with `/usr/bin/time` (user time, release build) on the 2-core development
//! machine and rounded up. 2026-12-06: 250 000 grains took 14.3 s (57 µs a grain), 31 000
//! grains 1.74 s (56 µs); each method's costs are beside its estimate, in its folder.
//! The estimate divides by the worker threads; a busy machine takes longer.

use opalray::scene::{OrientationLaw, Pattern};
use opalray::Scene;

/// Processor seconds to grow one grain (its neighbours found along 64 rays).
const GRAIN_CPU_S: f64 = 60e-6;
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
        let integrator = opalray::integrator::of(scene.integrator.method());
        // Every method builds the stone's grains (the two passes read them as cells).
        let grains = grains(scene);
        let method = integrator.work(scene, frames as f64);
        Work {
            grains,
            samples: method.samples,
            rays: method.rays,
            light_rays: method.light_rays,
            cpu_s: grains * GRAIN_CPU_S + method.cpu_s,
        }
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
    use opalray::scene::Method;

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
        // Processor seconds (`/usr/bin/time`, user): measured on the development machine
        // before the edges' rays read back their centre's reflections (2026-12-06 15:34 UTC,
        // load 6; BENCHMARKS.md, "The lobe estimate by stone"), times the ratio of the time
        // after to the time before on another machine (2026-12-07, two runs of each,
        // alternating, five of the black opal, the crystal and the doublet at 4; BENCHMARKS.md,
        // 2026-12-07 second session): the black opal at
        // 160 × 120 and 4 and 16 rays, the crystal (a clear stone), the harlequin, the
        // doublet and the white at 4.
        let measured = [
            ("black-opal", 4, 1.08 * 0.68),
            ("black-opal", 16, 2.66 * 0.486),
            ("crystal", 4, 3.48 * 0.735),
            ("harlequin", 4, 0.52 * 0.695),
            ("doublet", 4, 0.48 * 0.663),
            ("white", 4, 2.01 * 0.710),
        ];
        for (preset, spp, cpu_s) in measured {
            let mut scene = opalray::scene::preset(preset).unwrap();
            scene.render.width = 160;
            scene.render.height = 120;
            scene.integrator.set_spp(spp);
            let estimate = Work::of(&scene, 1).seconds(1);
            eprintln!("{preset} at {spp}: estimate {estimate:.3} s, measured {cpu_s:.3} s");
            assert!(
                (0.8 * cpu_s..1.5 * cpu_s).contains(&estimate),
                "{preset} at {spp}: {estimate} s, measured {cpu_s} s"
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

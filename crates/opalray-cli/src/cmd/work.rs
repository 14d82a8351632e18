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
//! (580 µs a pixel's sample; the harlequin 300 µs). The stored method and the two passes,
//! 2026-12-06 (load about 10), differences between renders of one scene at two sizes or
//! sample counts: `BENCHMARKS.md`, "The work estimate's costs"; the lobe integrator's, by
//! stone ([`lobe_factor`]): "The lobe estimate by stone".
//! The estimate divides by the worker threads; a busy machine takes longer.

use opalray::scene::{Backing, Cut, Method, OrientationLaw, Pattern};
use opalray::Scene;

/// Processor seconds to grow one grain (its neighbours found along 64 rays).
const GRAIN_CPU_S: f64 = 60e-6;
/// Processor seconds of one path-traced sample of one pixel of a gem (the black opal).
const PATH_SAMPLE_CPU_S: f64 = 600e-6;
/// Processor seconds of the lobe integrator's ray through a pixel's centre in the black opal
/// (8.9 µs at 160 × 120, 2026-12-06 afternoon, after the integrator's speed-up; BENCHMARKS.md,
/// "The lobe estimate by stone"); [`lobe_factor`] scales it to another stone.
const LOBE_PIXEL_CPU_S: f64 = 10e-6;
/// Processor seconds of each further lobe ray, `integrator.spp − 1` a pixel, averaged over
/// the frame (they are cast only where a pixel differs from its neighbours: the black opal
/// 8.0 µs at 4 rays, 7.1 µs at 16).
const LOBE_RAY_CPU_S: f64 = 8e-6;
/// Processor seconds of a lobe frame's set-up (its backing and potch tables; the black opal
/// at 8 × 6 less its grains: 0.21 s).
const LOBE_FRAME_CPU_S: f64 = 0.2;
/// The lobe rays' cost in a clear stone (its potch passing more than 1/e through the dome,
/// `potch_extinction_per_mm × dome_height_mm < 1`), where every ray walks the whole stone:
/// the crystal 48 µs a centre ray and 43 µs a further one, 5.4 times the black opal's.
const LOBE_CLEAR_FACTOR: f64 = 5.5;
/// The black opal's grain size and opal depth (`domains.grain_size_mm`, `body.dome_height_mm`),
/// mm: the lobe costs above are its, [`lobe_factor`] scales them to another opaque stone.
const LOBE_GRAIN_MM: f64 = 2.0;
const LOBE_DEPTH_MM: f64 = 4.0;
/// The black opal's `domains.boundary_roughness`, and the cost of roughness: a ray's cost in
/// the domains grows by `1 + LOBE_ROUGH_COST × roughness` (the black opal's centre rays at
/// 160 × 120: 534 ms at 0.4, 336 ms at 0: 1.59 = 1 + 0.4 × 1.47).
const LOBE_ROUGHNESS: f64 = 0.4;
const LOBE_ROUGH_COST: f64 = 1.5;
/// The lobe rays' cost in an opaque stone with no backing (`body.backing = "none"`, a
/// cabochon's default: the white opal), whose rays pass its polished back and walk on: the
/// white opal's scaled cost is 3.9 times the same stone's on a black backing (1.77 s against
/// 0.46 s of processor time at 160 × 120, less grains and set-up).
const LOBE_UNBACKED_FACTOR: f64 = 4.0;
/// The part of an opaque stone's lobe cost that does not scale with its domains (the walk to
/// the stone, the potch, the backing, the colour): fitted to the triplet and the boulder.
const LOBE_FIXED_SHARE: f64 = 0.2;
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
                let factor = lobe_factor(scene);
                work.rays = pixels * spp;
                work.cpu_s += frames * LOBE_FRAME_CPU_S
                    + factor * pixels * (LOBE_PIXEL_CPU_S + (spp - 1.0) * LOBE_RAY_CPU_S);
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

/// The lobe integrator's cost per ray in `scene` relative to the black opal's. In a clear
/// stone every ray walks the whole stone ([`LOBE_CLEAR_FACTOR`]). In an opaque one a ray's
/// cost goes with the domain boundaries it meets, and is [`LOBE_UNBACKED_FACTOR`] times more
/// where the back has no backing: with the domains along it (the opal's depth,
/// `body.dome_height_mm`, a triplet's `body.slice_mm`, at most the black opal's 4 mm) over
/// their size (`domains.grain_size_mm`; the centre rays at 160 × 120 took 678, 336 and 150 ms
/// at 1, 2 and 4 mm) and with their roughness (`domains.boundary_roughness`), above a fixed
/// share ([`LOBE_FIXED_SHARE`]). Measured against it: `BENCHMARKS.md`, "The lobe estimate
/// by stone".
pub fn lobe_factor(scene: &Scene) -> f64 {
    let b = &scene.body;
    if b.potch_extinction_per_mm * b.dome_height_mm < 1.0 {
        return LOBE_CLEAR_FACTOR;
    }
    let depth_mm = match b.cut {
        Cut::Triplet => b.slice_mm,
        Cut::Ellipsoid => 2.0 * scene.structure.semi_axes_mm[2],
        Cut::Cabochon | Cut::Doublet => b.dome_height_mm,
    };
    let depth = (depth_mm / LOBE_DEPTH_MM).min(1.0);
    let d = &scene.domains;
    let size = match d.pattern {
        Pattern::Grains => LOBE_GRAIN_MM / d.grain_size_mm,
        // The paper's balls: taken as the black opal's grains.
        _ => 1.0,
    };
    let rough =
        (1.0 + LOBE_ROUGH_COST * d.boundary_roughness) / (1.0 + LOBE_ROUGH_COST * LOBE_ROUGHNESS);
    let backed = if b.backing() == Backing::None {
        LOBE_UNBACKED_FACTOR
    } else {
        1.0
    };
    backed * (LOBE_FIXED_SHARE + (1.0 - LOBE_FIXED_SHARE) * depth * size * rough)
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
        // Processor seconds measured (`/usr/bin/time`, user, 2026-12-06 15:34 UTC, load 6;
        // BENCHMARKS.md, "The lobe estimate by stone"): the black opal at 160 × 120 and 4 and
        // 16 rays, the crystal (a clear stone), the harlequin and the doublet at 4.
        let measured = [
            ("black-opal", 4, 1.08),
            ("black-opal", 16, 2.66),
            ("crystal", 4, 3.48),
            ("harlequin", 4, 0.52),
            ("doublet", 4, 0.48),
            ("white", 4, 2.01),
        ];
        for (preset, spp, cpu_s) in measured {
            let mut scene = opalray::scene::preset(preset).unwrap();
            scene.render.width = 160;
            scene.render.height = 120;
            scene.integrator.set_spp(spp);
            let estimate = Work::of(&scene, 1).seconds(1);
            assert!(
                (0.8 * cpu_s..1.5 * cpu_s).contains(&estimate),
                "{preset} at {spp}: {estimate} s, measured {cpu_s} s"
            );
        }
    }

    #[test]
    fn the_lobe_cost_follows_the_domains_a_ray_meets() {
        let factor = |preset: &str, change: &dyn Fn(&mut Scene)| {
            let mut scene = opalray::scene::preset(preset).unwrap();
            change(&mut scene);
            lobe_factor(&scene)
        };
        let same = |_: &mut Scene| {};
        // The black opal is the reference; a clear stone walks the whole stone.
        assert_eq!(factor("black-opal", &same), 1.0);
        assert_eq!(factor("crystal", &same), LOBE_CLEAR_FACTOR);
        // The harlequin: 3 mm grains, smooth: 0.2 + 0.8 × (2/3) / 1.6.
        assert!((factor("harlequin", &same) - (0.2 + 0.8 * (2.0 / 3.0) / 1.6)).abs() < 1e-12);
        // The doublet: 1.5 mm of opal of the black opal's 4: 0.2 + 0.8 × 0.375.
        assert!((factor("doublet", &same) - 0.5).abs() < 1e-12);
        // Halving the grains (at most the black opal's depth counts) doubles the part that
        // scales; rougher boundaries cost more.
        let half = factor("black-opal", &|s| s.domains.grain_size_mm = 1.0);
        assert!((half - (0.2 + 0.8 * 2.0)).abs() < 1e-12);
        let deep = factor("black-opal", &|s| s.body.dome_height_mm = 8.0);
        assert_eq!(deep, 1.0);
        let smooth = factor("black-opal", &|s| s.domains.boundary_roughness = 0.0);
        assert!((smooth - (0.2 + 0.8 / 1.6)).abs() < 1e-12);
        // The white opal, with no backing, is four times the same stone on black.
        let white = factor("white", &same);
        let on_black = factor("white", &|s| s.body.backing = Some(Backing::Black));
        assert_eq!(white, LOBE_UNBACKED_FACTOR * on_black);
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

//! The work of a whole command, estimated before any work and said up front when it is long.
//!
//! Two terms dominate every long run measured: growing grains (the power diagram's
//! neighbours, `domains.pattern = "grains"`, and the parent grains of correlated
//! orientations) and the path tracer's samples (pixels × `integrator.spp`). Their costs are
//! processor seconds measured with `/usr/bin/time` (user time, release build) on the 2-core
//! development machine, 2026-12-06, and rounded up: 250 000 grains took 14.3 s (57 µs a
//! grain), 31 000 grains 1.74 s (56 µs); the black opal path-traced at 64 × 48 took 1.9 s at
//! 1 and 14.5 s at 8 samples per pixel (580 µs a pixel's sample; the harlequin 300 µs).
//! The estimate divides by the worker threads; a busy machine takes longer.

use opalray::scene::{Method, OrientationLaw, Pattern};
use opalray::Scene;

/// Processor seconds to grow one grain (its neighbours found along 64 rays).
const GRAIN_CPU_S: f64 = 60e-6;
/// Processor seconds of one path-traced sample of one pixel of a gem (the black opal).
const PATH_SAMPLE_CPU_S: f64 = 600e-6;
/// Work said up front when the estimate is over this, seconds.
pub const ANNOUNCE_OVER_S: f64 = 60.0;

/// The work of rendering `scene` `frames` times (a stone grown once), by its dominant terms.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Work {
    /// Grains grown (and parent grains of correlated orientations).
    pub grains: f64,
    /// Path-traced samples, pixels × samples per pixel × frames.
    pub samples: f64,
}

impl Work {
    /// The work of `scene` rendered `frames` times.
    pub fn of(scene: &Scene, frames: u64) -> Work {
        let mut grains = 0.0;
        let stone_built = scene.integrator.method() != Method::TwoPass;
        if stone_built && scene.domains.pattern == Pattern::Grains {
            let axes = scene.body.box_semi_axes(scene.structure.semi_axes_mm);
            grains = scene.domains.grain_count(axes);
            if scene.domains.orientation == OrientationLaw::Correlated {
                let parents = opalray::scene::DomainsConfig {
                    grain_size_mm: scene.domains.correlation_mm,
                    stretch: [1.0; 3],
                    boundary_roughness: 0.0,
                    ..scene.domains.clone()
                };
                grains += parents.grain_count(axes);
            }
        }
        let samples = if scene.integrator.method() == Method::Path {
            let pixels = f64::from(scene.render.width) * f64::from(scene.render.height);
            pixels * f64::from(scene.integrator.spp().unwrap_or(1)) * frames as f64
        } else {
            0.0
        };
        Work { grains, samples }
    }

    /// Estimated seconds on `threads` worker threads.
    pub fn seconds(&self, threads: usize) -> f64 {
        (self.grains * GRAIN_CPU_S + self.samples * PATH_SAMPLE_CPU_S) / threads.max(1) as f64
    }
}

/// Say up front, on stderr, how long `scene` rendered `frames` times will take when the
/// estimate is over [`ANNOUNCE_OVER_S`], and what bounds it (`--time-limit` where the command
/// has it).
pub fn announce(scene: &Scene, frames: u64, has_time_limit_flag: bool) {
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
    let bound = if has_time_limit_flag {
        "; --time-limit SECONDS bounds it"
    } else {
        "; fewer --frames, a smaller image or fewer --spp shorten it"
    };
    crate::stdio::note(format_args!(
        "note: about {} of work by the estimate ({}) on {threads} worker thread{}{bound}",
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
        let scene = Scene::from_toml_str(text, "t").unwrap();
        let work = Work::of(&scene, 1);
        assert!((2.0e5..2.5e5).contains(&work.grains), "{work:?}");
        let seconds = work.seconds(1);
        assert!((12.0..15.0).contains(&seconds), "{seconds}");
    }
}

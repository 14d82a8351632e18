//! The lobe integrator's work estimate (the CLI's, said up front when a render is long):
//! its camera rays and their processor seconds, measured with `/usr/bin/time` (user time,
//! release build) on the 2-core development machine and rounded up, scaled from the black
//! opal to another stone by [`lobe_factor`] (`BENCHMARKS.md`, "The lobe estimate by stone").

use crate::integrator::{pixels, Work};
use crate::scene::{Backing, Cut, Pattern, Scene};

/// Processor seconds of the lobe integrator's ray through a pixel's centre in the black opal
/// (8.9 µs at 160 × 120, 2026-12-06 afternoon, after the integrator's speed-up; BENCHMARKS.md,
/// "The lobe estimate by stone"); [`lobe_factor`] scales it to another stone.
const LOBE_PIXEL_CPU_S: f64 = 10e-6;
/// Processor seconds of each further lobe ray, `integrator.spp − 1` a pixel, averaged over
/// the frame (they are cast only where a pixel differs from its neighbours, and read back the
/// reflections the centre's ray followed out: about 2 µs in the black opal at 16 rays,
/// BENCHMARKS.md, 2026-12-07 second session; more in a clear stone, whose further rays go
/// on through the stone where their pixel's centre did not, at the rim).
const LOBE_RAY_CPU_S: f64 = 3e-6;
/// Processor seconds of a lobe frame's set-up (its backing and potch tables; the black opal
/// at 8 × 6 less its grains: 0.17 s).
const LOBE_FRAME_CPU_S: f64 = 0.17;
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
/// The lobe integrator's work for `scene` rendered `frames` times: a ray through every
/// pixel's centre, `spp − 1` more where a pixel differs from its neighbours, and each frame's
/// set-up.
pub(super) fn work(scene: &Scene, frames: f64) -> Work {
    let spp = f64::from(scene.integrator.spp().unwrap_or(1));
    let pixels = pixels(scene, frames);
    let factor = lobe_factor(scene);
    Work {
        rays: pixels * spp,
        cpu_s: frames * LOBE_FRAME_CPU_S
            + factor * pixels * (LOBE_PIXEL_CPU_S + (spp - 1.0) * LOBE_RAY_CPU_S),
        ..Work::default()
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_lobe_cost_follows_the_domains_a_ray_meets() {
        let factor = |preset: &str, change: &dyn Fn(&mut Scene)| {
            let mut scene = crate::scene::preset(preset).unwrap();
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
}

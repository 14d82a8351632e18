//! The cull's early stop against the full sum it stands for.

use super::*;
use crate::film::SpectralSampler;
use crate::lights::Environment;
use crate::lobe::fixture::eight_by_eight;
use crate::sampling::Rng;
use crate::scene::preset;

/// For `preset`'s stone and environment, [`Tracer::reaches_cut`] against `weight ×`
/// [`Tracer::seen_out`] `≥ CUT` at random points of the opal, directions, lobe widths and
/// weights (most within a factor of two of the cut, some exactly at it): `(kept, culled)`.
fn cull_agrees_with_the_full_sum(preset_name: &str) -> (usize, usize) {
    let scene = preset(preset_name).unwrap();
    let stone = Stone::new(&scene).unwrap();
    let env = Environment::new(&scene.environment, scene.render.background as f32).unwrap();
    let sampler = SpectralSampler::new(scene.light.illuminant, &scene.spectrum, 4);
    let setup = eight_by_eight(&env, &sampler);
    let colours = LineColours::new(&sampler);
    let irradiance = Irradiance::new(&env);
    let tracer = Tracer::new(&stone, &setup, &colours, &irradiance, Lit::default());
    let axes = stone.shape.semi_axes();
    let mut rng = Rng::new(7, 0, 0);
    let (mut kept, mut culled) = (0, 0);
    for _ in 0..20_000 {
        let u = Vec3::new(rng.uniform_f32(), rng.uniform_f32(), rng.uniform_f32());
        let p = (2.0 * u - Vec3::ONE) * axes;
        if !stone.shape.contains(p) || stone.region_at(p) != Region::Opal {
            continue;
        }
        let dir = rng.unit_vector();
        let sigma = 0.002 + 0.05 * rng.uniform_f32();
        let bound = tracer.seen_out(p, dir, Region::Opal, sigma, MIN_WEIGHT);
        let near = if bound > 0.0 { CUT / bound } else { 1.0 };
        for weight in [near, near * (0.5 + 1.5 * rng.uniform_f32()), 1e-4, 1.0] {
            let full = weight * bound >= CUT;
            assert_eq!(
                tracer.reaches_cut(p, dir, sigma, weight),
                full,
                "{preset_name}: at {p} along {dir}, sigma {sigma}, weight {weight}, sum {bound}"
            );
            if full {
                kept += 1;
            } else {
                culled += 1;
            }
        }
    }
    (kept, culled)
}

#[test]
fn the_cull_stopped_early_keeps_the_lines_the_full_sum_keeps() {
    for name in ["black-opal", "triplet", "crystal"] {
        let (kept, culled) = cull_agrees_with_the_full_sum(name);
        // Both outcomes met many times: the comparison is not one-sided.
        assert!(
            kept > 1000 && culled > 1000,
            "{name}: {kept} kept, {culled} culled"
        );
    }
}

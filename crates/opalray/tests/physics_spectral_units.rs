//! The spectral image's units, as `docs/model.md` ("Output formats") states them: relative
//! spectral radiance per nm, normalised so that `∫ S(λ) ȳ(λ) dλ` over the range is the
//! pixel's luminance Y, so that white of Y = 1 under D65 reads D65(λ) / ∫ D65 ȳ dλ per nm
//! (about 0.0097 at 555 nm), not 1. Checked on the path tracer's view of the uniform white
//! environment (Y = 1), against the CIE tables in `data/cie` integrated here.

mod common;

use glam::Vec3;
use opalray::geometry::Camera;
use opalray::lights::Environment;
use opalray::path::{trace_paths, PathSetup, Sampling, SpectralSampler};
use opalray::scene::{Illuminant, Pattern, Scene};
use opalray::spectrum::WavelengthGrid;
use opalray::stone::Stone;

#[test]
fn white_under_d65_reads_the_illuminant_over_its_luminance_per_nm() {
    let mut scene = Scene::default();
    scene.domains.pattern = Pattern::Grains;
    scene.domains.void_fraction = 1.0;
    let stone = Stone::new(&scene).unwrap();
    let grid = WavelengthGrid {
        min_nm: 380.0,
        max_nm: 780.0,
        bins: 40,
    };
    let sampler = SpectralSampler::new(Illuminant::D65, &grid, 4);
    // Looking up, away from the stone: every pixel is the environment, white of Y = 1.
    let image = trace_paths(
        &stone,
        &PathSetup {
            camera: Camera::look_at(
                Vec3::new(0.0, 0.0, 100.0),
                Vec3::new(0.0, 0.0, 200.0),
                Vec3::Y,
                10.0,
                2,
                2,
            ),
            width: 2,
            height: 2,
            spp: 1,
            max_depth: 8,
            max_scatterings: 0,
            light: None,
            environment: Environment::uniform(),
            area_light: None,
            gloss: 1.0,
            seed: 1,

            sampling: Sampling::Sobol,
            spectral: &sampler,
        },
    );
    assert!(
        (f64::from(image.xyz[0][1]) - 1.0).abs() < 1e-4,
        "{:?}",
        image.xyz[0]
    );

    // D65 every 5 nm joined linearly; ȳ every nm; the luminance integral over the range.
    let d65 = common::cie_table("illuminant_d65_5nm.csv");
    let d65_at = |w: f64| common::linear_at(&d65, w);
    let ybar: Vec<(f64, f64)> = common::cie_table("cie1931_2deg_xyz_1nm.csv")
        .into_iter()
        .filter(|r| (380.0..=780.0).contains(&r.0))
        .map(|r| (r.0, r.2))
        .collect();
    let luminance: f64 = ybar
        .windows(2)
        .map(|p| 0.5 * (d65_at(p[0].0) * p[0].1 + d65_at(p[1].0) * p[1].1))
        .sum();
    let bins = grid.bins;
    let pixel = &image.spectral.data[..bins];
    for (b, &value) in pixel.iter().enumerate() {
        let (lo, hi) = grid.edges_nm(b);
        // The bin's mean of D65, over the luminance: per nm.
        let mean = (0..100)
            .map(|k| d65_at(lo + (hi - lo) * (f64::from(k) + 0.5) / 100.0))
            .sum::<f64>()
            / 100.0;
        let expected = mean / luminance;
        assert!(
            (f64::from(value) / expected - 1.0).abs() < 0.005,
            "bin {lo}–{hi} nm: {value} vs {expected}"
        );
        if (lo..hi).contains(&555.0) {
            assert!(
                (f64::from(value) - 0.0097).abs() < 0.0001,
                "555 nm: {value}"
            );
        }
    }
}

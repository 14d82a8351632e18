//! The potch's calibration checked as a chip is measured: a thick, flat slab of potch behind
//! the stone's polished surface, under uniform white light, viewed face-on with the surface's
//! own gloss off, shows its tone's Munsell value Y(V) (ASTM D1535: N9 0.767, N5 0.193,
//! N1 0.0118), rendered by the path tracer at its default depth.
//!
//! Flat, because the calibration's walk is a flat slab's: under a dome the light that spreads
//! sideways in the body (about 0.4 mm for N9) finds the surface curving towards it and more
//! of it leaves (`docs/model.md`, "The stone's body").

mod common;

use glam::Vec3;
use opalray::lights::Environment;
use opalray::path::{PathSetup, SpectralSampler};
use opalray::scene::{Cut, EnvironmentKind, Pattern, Scene};
use opalray::stone::body::munsell_y;
use opalray::stone::Stone;

/// A cabochon of potch only, 120 × 90 mm across and 8 mm high (radii of curvature 250 and
/// 450 mm at the apex: flat to a walk that spreads under a millimetre), a mean free path of
/// 20 µm (8 mm is a semi-infinite slab at any tone), under the uniform furnace.
fn flat_slab(tone: u8) -> Scene {
    let mut scene = Scene::default();
    scene.domains.pattern = Pattern::Grains;
    scene.domains.void_fraction = 1.0;
    scene.render.body_tone = tone;
    scene.environment.kind = EnvironmentKind::Uniform;
    scene.body.cut = Cut::Cabochon;
    scene.body.dome_height_mm = 8.0;
    scene.structure.semi_axes_mm = [60.0, 45.0, 4.0];
    scene.body.potch_extinction_per_mm = 50.0;
    scene
}

/// Mean Y over an 8 × 8 face-on image of the 2 mm square at the apex, gloss off, at the path
/// tracer's default depth, and its standard error.
fn body_y(stone: &Stone, scene: &Scene, spp: u32) -> (f64, f64) {
    let sampler = SpectralSampler::new(scene.light.illuminant, &scene.spectrum, 4);
    let top = Vec3::new(0.0, 0.0, 8.0);
    let fov = 2.0 * (1.0f32 / 100.0).atan().to_degrees();
    let view = common::view_from_above(&sampler, Environment::uniform(), top, 8, fov);
    let setup = PathSetup {
        spp,
        gloss: 0.0,
        ..view
    };
    common::mean_y(stone, &setup)
}

#[test]
fn a_flat_slab_of_potch_shows_its_tones_munsell_value_without_the_gloss() {
    // Within 0.004 (N9: about 3 standard errors of the render, and the stored albedos'
    // own error, 0.0006), N5 and N1 within 0.003.
    let mut failures = Vec::new();
    for (tone, spp, tolerance) in [(9u8, 256, 0.004), (5, 64, 0.003), (1, 16, 0.003)] {
        let scene = flat_slab(tone);
        let stone = Stone::new(&scene).unwrap();
        let (y, se) = body_y(&stone, &scene, spp);
        let expected = munsell_y(f64::from(tone));
        eprintln!("N{tone}: {y:.4} ± {se:.4} vs {expected:.4}");
        assert!(se < 0.0015, "N{tone}: noise {se} too high for the test");
        if (y - expected).abs() >= tolerance {
            failures.push(format!("N{tone}: {y} vs {expected}"));
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}

//! The path tracer's energy bookkeeping and the potch's calibration, checked through whole
//! renders against independent numbers: a lossless stone in a furnace shows the furnace's
//! value; a thick slab of potch shows its tone's Munsell value (ASTM D1535).

mod common;

use glam::Vec3;
use opalray::lights::Environment;
use opalray::path::{PathSetup, SpectralSampler};
use opalray::scene::{Cut, EnvironmentKind, PathConfig, Pattern, Scene};
use opalray::stone::body::munsell_y;
use opalray::stone::Stone;

/// A stone of potch only, lit by the furnace.
fn potch_scene(tone: u8) -> Scene {
    let mut scene = Scene::default();
    scene.domains.pattern = Pattern::Grains;
    scene.domains.grain_size_mm = 2.0;
    scene.domains.void_fraction = 1.0;
    scene.render.body_tone = tone;
    scene.environment.kind = EnvironmentKind::Uniform;
    scene
}

/// Mean Y over the central `frac` of an `n × n` face-on image of `stone`, and its standard
/// error.
fn face_y(
    stone: &Stone,
    scene: &Scene,
    n: usize,
    spp: u32,
    max_depth: u32,
    frac: f32,
) -> (f64, f64) {
    let sampler = SpectralSampler::new(scene.light.illuminant, &scene.spectrum, 4);
    // A 2 × frac mm square at the face's centre.
    let fov = 2.0 * (frac / 100.0).atan().to_degrees();
    let view = common::view_from_above(&sampler, Environment::uniform(), Vec3::ZERO, n, fov);
    let setup = PathSetup {
        spp,
        max_depth,
        ..view
    };
    common::mean_y(stone, &setup)
}

#[test]
fn a_lossless_potch_stone_in_a_furnace_shows_the_furnace() {
    // Albedo 1: whatever the paths do inside, every pixel must show 1 (the gloss F, the
    // refracted 1 − F, internal reflections and escapes, the n² of radiance inside).
    let scene = potch_scene(9);
    let mut stone = Stone::new(&scene).unwrap();
    stone.potch.albedo = 1.0;
    stone.potch.extinction_per_mm = 0.5;
    let (y, _) = face_y(&stone, &scene, 12, 16, 256, 6.0);
    assert!((y - 1.0).abs() < 0.01, "{y}");
}

#[test]
fn a_thick_slab_of_potch_shows_its_tones_munsell_value() {
    // Viewed face-on under diffuse white light: the gloss F₀ plus the body's Y(tone) (ASTM
    // D1535: N9 0.767, N5 0.193, N1 0.0118), rendered at the path tracer's default depth
    // (its scatterings in the body are not counted against it: a white body's walks are
    // long). Within 0.005, N9 within 0.01: under this dome (radii of curvature 7 and 12.5 mm
    // at the apex) N9 reads about 0.008 above a flat chip, the light it spreads sideways
    // (about 0.4 mm) leaving more readily where the surface curves towards it (the flat
    // chip, gloss off: `physics_body_flat.rs`).
    let mut failures = Vec::new();
    for (tone, spp, tolerance) in [(9u8, 256, 0.01), (5, 64, 0.005), (1, 16, 0.005)] {
        let mut scene = potch_scene(tone);
        scene.body.cut = Cut::Cabochon;
        scene.body.dome_height_mm = 8.0;
        scene.structure.semi_axes_mm = [10.0, 7.5, 4.0];
        // A mean free path of 20 µm: 8 mm of potch is a semi-infinite slab at any tone.
        scene.body.potch_extinction_per_mm = 50.0;
        let stone = Stone::new(&scene).unwrap();
        // Deeper than 0.1 mm no outside light is estimated (the stone's reach bound): the
        // body's light then comes from the escapes its deep scatterings draw.
        let deep = Vec3::new(0.0, 0.0, -1.0);
        assert!(
            stone.reach_bound(deep) < 0.01,
            "{}",
            stone.reach_bound(deep)
        );
        let n = stone.n_eff;
        let f0 = f64::from(((n - 1.0) / (n + 1.0)).powi(2));
        let start = std::time::Instant::now();
        let depth = PathConfig::default().max_depth;
        let (y, se) = face_y(&stone, &scene, 8, spp, depth, 1.0);
        let expected = f0 + munsell_y(f64::from(tone));
        eprintln!(
            "N{tone}: {y:.4} ± {se:.4} vs {expected:.4} ({:.1} s)",
            start.elapsed().as_secs_f64()
        );
        assert!(se < 0.0015, "N{tone}: noise {se} too high for the test");
        if (y - expected).abs() >= tolerance {
            failures.push(format!("N{tone}: {y} vs {expected}"));
        }
    }
    assert!(failures.is_empty(), "{failures:?}");
}

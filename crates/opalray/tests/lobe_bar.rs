//! The lobe integrator's body under a colour bar against independent numbers: the white
//! preset's stone with its bar's lines moved into the ultraviolet and its haze taken out (a
//! clear bar over white potch under a dome), in the uniform light (a furnace). Its potch
//! absorbs, so no pixel can show more than the furnace's 1, and the path tracer, which
//! follows every scattering and every internal reflection, gives the same mean.

use glam::Vec3;
use opalray::geometry::Camera;
use opalray::lights::Environment;
use opalray::lobe::{render_lobes, LobeSetup};
use opalray::path::{trace_paths, PathSetup, Sampling, SpectralSampler};
use opalray::scene::{preset, PathConfig, Scene};
use opalray::stone::body::munsell_y;
use opalray::stone::Stone;

/// Pixels across the face-on view of the stone's central `VIEW_MM` mm.
const N: usize = 12;
/// The width of the view, mm: the middle of the white preset's 20 × 15 mm stone, away from
/// the rim where the bar reaches the back.
const VIEW_MM: f32 = 8.0;

/// The white preset with its lines in the ultraviolet (`sphere_diameter_nm = 120`: the (111)
/// line at about 280 nm) and a clear bar 1.5 mm thick (the preset's is 0.5 mm; the thicker
/// bar returns more of the potch's light, where the double count showed most).
fn clear_bar() -> Scene {
    let mut scene = preset("white").unwrap();
    scene.crystal.sphere_diameter_nm = 120.0;
    scene.body.colour_bar_mm = 1.5;
    scene.body.domain_haze = 0.0;
    scene
}

fn camera() -> Camera {
    let fov = 2.0 * (0.5 * VIEW_MM / 100.0).atan().to_degrees();
    Camera::look_at(Vec3::new(0.0, 0.0, 100.0), Vec3::ZERO, Vec3::Y, fov, N, N)
}

/// Y of every pixel of the lobe integrator's image, gloss on.
fn lobe_y(stone: &Stone, scene: &Scene, sampler: &SpectralSampler) -> Vec<f64> {
    let env = Environment::uniform();
    let image = render_lobes(
        stone,
        &LobeSetup {
            camera: camera(),
            width: N,
            height: N,
            spp: 1,
            light: None,
            area_light: None,
            light_intensity: 0.0,
            environment: &env,
            gloss: 1.0,
            seed: 0,
            body_reflectance: munsell_y(f64::from(scene.render.body_tone)) as f32,
            spectral: sampler,
            trapped: false,
            reuse: true,
        },
    );
    image.xyz.iter().map(|v| f64::from(v[1])).collect()
}

/// The path tracer's mean Y over the same view and its standard error.
fn path_y(stone: &Stone, sampler: &SpectralSampler, spp: u32) -> (f64, f64) {
    let image = trace_paths(
        stone,
        &PathSetup {
            camera: camera(),
            width: N,
            height: N,
            spp,
            max_depth: PathConfig::default().max_depth,
            max_scatterings: PathConfig::default().max_scatterings,
            light: None,
            environment: Environment::uniform(),
            area_light: None,
            gloss: 1.0,
            seed: 7,

            sampling: Sampling::Sobol,
            spectral: sampler,
        },
    );
    let pixels = (N * N) as f64;
    let mean = image.xyz.iter().map(|v| f64::from(v[1])).sum::<f64>() / pixels;
    let variance = image.variance.iter().map(|v| f64::from(v[1])).sum::<f64>() / pixels;
    (mean, (variance / pixels).sqrt())
}

#[test]
fn a_white_body_under_a_clear_bar_in_a_furnace_shows_no_more_than_the_furnace() {
    // Each direction above the potch counted once: as light from outside, or as the body's
    // own light the dome sends back. Counted twice (the dome's return taken as a flat
    // surface's, the light it carries from elsewhere added), the body read 1.13 here.
    let scene = clear_bar();
    let stone = Stone::new(&scene).unwrap();
    let sampler = SpectralSampler::new(scene.light.illuminant, &scene.spectrum, 4);
    let lobe = lobe_y(&stone, &scene, &sampler);
    let brightest = lobe.iter().fold(0.0f64, |m, &y| m.max(y));
    let mean = lobe.iter().sum::<f64>() / lobe.len() as f64;
    let (path, se) = path_y(&stone, &sampler, 48);
    eprintln!("lobe mean {mean:.4} (brightest {brightest:.4}), path {path:.4} ± {se:.4}");
    assert!(
        brightest <= 1.0,
        "a pixel shows {brightest}, over the furnace's 1"
    );
    // The path tracer's mean within 5 % (its own error about 0.5 %).
    assert!(se < 0.01, "path tracer's noise {se} too high for the test");
    assert!(
        (mean / path - 1.0).abs() < 0.05,
        "lobe {mean} against path {path}"
    );
}

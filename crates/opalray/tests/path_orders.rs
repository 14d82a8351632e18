//! The path tracer's tally of its light by Bragg order (`opalray::path::orders`): the classes
//! hold all the stone's light and nothing else, and where the physics says which class the
//! light must be in, it is there.

mod common;

use glam::Vec3;
use opalray::integrator::Passes;
use opalray::lights::{AreaLight, Environment};
use opalray::path::SpectralSampler;
use opalray::path::{trace_passes, trace_paths, BraggOrders, PathImage, PathSetup};
use opalray::scene::{preset, EnvironmentConfig, EnvironmentKind, Scene};
use opalray::stone::Stone;

/// Index in [`BraggOrders::summary`] of each name (the JSON's `summary` keys, in order).
const BACKGROUND: usize = 0;
const GLOSS: usize = 1;
const BRAGG_0: usize = 2;
const BRAGG_1: usize = 3;
const BRAGG_2: usize = 4;
const BRAGG_3: usize = 5;
const AFTER_REFLECTION: usize = 6;
const BODY: usize = 7;

/// An `n × n` face-on view from 100 mm, `fov_deg` wide, under the environment `kind`.
fn setup(
    sampler: &SpectralSampler,
    kind: EnvironmentKind,
    n: usize,
    fov_deg: f32,
    spp: u32,
) -> PathSetup<'_> {
    let config = EnvironmentConfig {
        kind,
        ..EnvironmentConfig::default()
    };
    let environment = Environment::new(&config, 0.0).unwrap();
    PathSetup {
        spp,
        max_depth: 64,
        max_scatterings: 0,
        seed: 11,
        ..common::view_from_above(sampler, environment, Vec3::ZERO, n, fov_deg)
    }
}

/// The image's luminance summed over its stone pixels' means.
fn stone_luminance(image: &PathImage) -> f64 {
    image
        .xyz
        .iter()
        .zip(&image.on_stone)
        .filter(|(_, &on)| on)
        .map(|(v, _)| f64::from(v[1]))
        .sum()
}

/// The tally's shares must hold all of the image's light over the stone, and sum to 1.
fn assert_holds_the_image(image: &PathImage) -> BraggOrders {
    let orders = image
        .bragg_orders
        .expect("the path tracer tallies its light");
    let pixels = image.on_stone.iter().filter(|&&on| on).count();
    assert_eq!(orders.pixels, pixels);
    let total = orders.mean_luminance * pixels as f64;
    let seen = stone_luminance(image);
    assert!(
        (total - seen).abs() <= 1e-5 * seen,
        "the tally holds {total}, the image {seen}"
    );
    let sum: f64 = orders.classes.iter().map(|c| c.0).sum();
    assert!((sum - 1.0).abs() < 1e-9, "shares sum to {sum}");
    orders
}

#[test]
fn potch_alone_adds_no_bragg_light_and_the_tally_holds_the_image() {
    // The harlequin's cabochon with its domains taken out, under the studio: every path
    // crosses potch only, so no light can have met a Bragg line; the body scatters much.
    let mut scene = preset("harlequin").unwrap();
    scene.structure.seed = 1;
    scene.domains.void_fraction = 1.0;
    let stone = Stone::new(&scene).unwrap();
    let sampler = SpectralSampler::new(scene.light.illuminant, &scene.spectrum, 4);
    let image = trace_paths(
        &stone,
        &setup(&sampler, EnvironmentKind::Studio, 12, 12.0, 8),
    );
    let orders = assert_holds_the_image(&image);
    for k in [BRAGG_1, BRAGG_2, BRAGG_3] {
        assert_eq!(orders.summary[k].0, 0.0, "summary {k}");
    }
    assert!(orders.summary[BODY].0 > 0.05, "{:?}", orders.summary[BODY]);
    // With its domains the same stone's light is partly Bragg light.
    scene.domains.void_fraction = 0.0;
    let stone = Stone::new(&scene).unwrap();
    let image = trace_paths(
        &stone,
        &setup(&sampler, EnvironmentKind::Studio, 12, 12.0, 8),
    );
    let orders = assert_holds_the_image(&image);
    assert!(orders.summary[BRAGG_1].0 > 0.01, "{:?}", orders.summary);
}

#[test]
fn the_gloss_of_a_lossless_stone_in_the_furnace_is_fresnels_share() {
    // A clear stone without domains nor backing in the uniform environment shows 1 (the
    // furnace); seen face-on over the middle 2 mm of its face (normals within
    // ~1° of the view) its gloss is Fresnel's normal reflectance F₀ = ((n − 1)/(n + 1))²
    // (unpolarised; at 1° it differs by 10⁻⁵ of itself), so its share of the light is F₀.
    let mut scene = Scene::default();
    scene.domains.void_fraction = 1.0;
    let mut stone = Stone::new(&scene).unwrap();
    stone.back = None;
    stone.potch.albedo = 1.0;
    stone.potch.extinction_per_mm = 0.01;
    let sampler = SpectralSampler::new(scene.light.illuminant, &scene.spectrum, 4);
    let fov = 2.0 * 1f32.atan2(100.0).to_degrees();
    let image = trace_paths(
        &stone,
        &setup(&sampler, EnvironmentKind::Uniform, 8, fov, 8),
    );
    let orders = assert_holds_the_image(&image);
    let n = f64::from(stone.n_eff);
    let f0 = ((n - 1.0) / (n + 1.0)).powi(2);
    let (gloss, se) = orders.summary[GLOSS];
    eprintln!(
        "gloss {gloss:.5} ± {:.5}, F0 {f0:.5}, Y {:.4}",
        se.unwrap(),
        orders.mean_luminance
    );
    assert!((orders.mean_luminance - 1.0).abs() < 0.01);
    assert!(
        (gloss - f0).abs() < 0.01 * f0,
        "gloss share {gloss}, F0 {f0}"
    );
    assert_eq!(orders.summary[BACKGROUND].0, 0.0);
}

#[test]
fn a_single_crystals_flash_is_one_bragg_reflection() {
    // A perfect crystal whose (111) planes are tilted 5° from the top, seen straight down in
    // a dark room with a small ball at its mirror direction (physics_mirror.rs) and no gloss:
    // the eye ray reaches the ball only by one reflection off the planes (a second off the
    // same planes turns it back towards the eye; without them it leaves through the base into
    // the dark). So the light is one Bragg reflection's, less what reaches the ball after a
    // reflection at the surface (a few % by Fresnel, and most of that misses the ball).
    let tilt = 5f32.to_radians();
    let (scene, stone) = common::tilted_crystal(tilt);
    let sampler = SpectralSampler::new(scene.light.illuminant, &scene.spectrum, 4);
    let mirror = (stone.n_eff * (2.0 * tilt).sin()).asin();
    let center = Vec3::new(mirror.sin(), 0.0, mirror.cos()) * 1000.0;
    let mut s = setup(&sampler, EnvironmentKind::None, 4, 0.02, 16);
    s.area_light = Some(AreaLight::sphere(center, 1000.0 * 1f32.to_radians(), 1.0));
    s.gloss = 0.0;
    let image = trace_paths(&stone, &s);
    let orders = assert_holds_the_image(&image);
    eprintln!("{:?}", orders.summary);
    assert!(orders.mean_luminance > 0.0);
    let (one, _) = orders.summary[BRAGG_1];
    assert!(one > 0.95, "one Bragg reflection: {one}");
    assert_eq!(orders.summary[BRAGG_0].0, 0.0, "nothing but the flash");
}

#[test]
fn a_crystal_lit_from_below_shows_its_flash_after_an_internal_reflection_on_one_side() {
    // The crystal above without a backing, the ball now below it. The eye ray (straight
    // down) reaches the base in two ways with one reflection off the planes (normal n, 5°
    // towards +x) and one at the flat top or base: reflected by the planes at once (up, 10°
    // towards +x), then at the top, it leaves the base 10° from straight down towards +x
    // inside; reflected at the base first, then by the planes on its way up, it leaves 10°
    // towards −x (the mirror of +z about n). A ball on the −x side sees only a Bragg event
    // after an internal reflection; on the +x side, only one before it.
    let tilt = 5f32.to_radians();
    let (scene, mut stone) = common::tilted_crystal(tilt);
    stone.back = None;
    let sampler = SpectralSampler::new(scene.light.illuminant, &scene.spectrum, 4);
    let mirror = (stone.n_eff * (2.0 * tilt).sin()).asin();
    for (side, lo, hi) in [(-1.0, 0.95, 1.0), (1.0, 0.0, 0.05)] {
        let center = Vec3::new(side * mirror.sin(), 0.0, -mirror.cos()) * 1000.0;
        let mut s = setup(&sampler, EnvironmentKind::None, 4, 0.02, 64);
        s.area_light = Some(AreaLight::sphere(center, 1000.0 * 1f32.to_radians(), 1.0));
        s.gloss = 0.0;
        let image = trace_paths(&stone, &s);
        let orders = assert_holds_the_image(&image);
        let (after, se) = orders.summary[AFTER_REFLECTION];
        eprintln!("ball at {side:+} x: after an internal reflection {after:.4} ± {se:?}");
        assert!(orders.mean_luminance > 0.0, "no flash at {side:+} x");
        assert!(orders.summary[BRAGG_1].0 > 0.95, "{:?}", orders.summary);
        assert!(
            (lo..=hi).contains(&after),
            "ball at {side:+} x: {after} after an internal reflection, expected [{lo}, {hi}]"
        );
    }
}

#[test]
fn the_light_that_met_no_body_is_the_image_of_a_body_that_keeps_none() {
    // A path's light added before its first scattering does not depend on the body's albedo:
    // over the same stone, the tally's light without the body flag must equal (in
    // expectation) the whole image of the stone whose body keeps nothing (albedo 0). The
    // harlequin, its potch made thick and pale so that the body's share is large.
    let mut scene = preset("harlequin").unwrap();
    scene.structure.seed = 1;
    let mut stone = Stone::new(&scene).unwrap();
    stone.potch.albedo = 0.9;
    stone.potch.extinction_per_mm = 2.0;
    let sampler = SpectralSampler::new(scene.light.illuminant, &scene.spectrum, 4);
    let s = setup(&sampler, EnvironmentKind::Studio, 8, 12.0, 64);
    let image = trace_paths(&stone, &s);
    let orders = assert_holds_the_image(&image);
    let (body, body_se) = orders.summary[BODY];
    let kept = orders.mean_luminance * (1.0 - body);
    let kept_se = orders.mean_luminance * body_se.unwrap();
    stone.potch.albedo = 0.0;
    let black = trace_paths(&stone, &s);
    let pixels = orders.pixels as f64;
    let y_black = stone_luminance(&black) / pixels;
    let black_se = black
        .variance
        .iter()
        .zip(&black.on_stone)
        .filter(|(_, &on)| on)
        .map(|(v, _)| f64::from(v[1]))
        .sum::<f64>()
        .sqrt()
        / pixels;
    let se = (kept_se * kept_se + black_se * black_se).sqrt();
    eprintln!("without the body {kept:.5} ± {kept_se:.5}, black body {y_black:.5} ± {black_se:.5} (body share {body:.3})");
    assert!(
        (kept - y_black).abs() <= 4.0 * se,
        "{kept} vs {y_black} ± {se}"
    );
    assert!(body > 0.1, "the test needs a large body share: {body}");
}

#[test]
fn the_tally_is_the_same_at_any_thread_count_and_however_the_passes_fall() {
    let mut scene = preset("black-opal").unwrap();
    scene.structure.seed = 3;
    let stone = Stone::new(&scene).unwrap();
    let sampler = SpectralSampler::new(scene.light.illuminant, &scene.spectrum, 4);
    let s = setup(&sampler, EnvironmentKind::Studio, 8, 25.0, 6);
    let run = |threads: usize, max_pass_spp: Option<u32>| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                let passes = Passes {
                    max_pass_spp,
                    ..Passes::default()
                };
                trace_passes(&stone, &s, &passes).bragg_orders.unwrap()
            })
    };
    let one = run(1, None);
    assert!(one.summary[BRAGG_1].0 > 0.0);
    assert_eq!(one, run(2, None));
    assert_eq!(one, run(3, Some(1)));
}

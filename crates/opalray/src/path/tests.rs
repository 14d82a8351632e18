//! The path tracer's tests that span its events (the roulette on first reflections), and the
//! helpers its modules' tests share: a small studio view and the mean of its paths.

use glam::Vec3;

use super::sampler::PathSampler;
use super::{PathSetup, Sampling, SpectralSampler, Tracer, MIN_FOLLOW};
use crate::geometry::Camera;
use crate::lights::{AreaLight, Environment};
use crate::scene::{EnvironmentConfig, EnvironmentKind};
use crate::stone::Stone;

/// An 8 × 8 face-on view, `fov_deg` wide, of a stone under the studio at `intensity`
/// (and `area_light`): 8 events, no gloss, no point light.
pub(in crate::path) fn studio_8x8(
    sampler: &SpectralSampler,
    intensity: f64,
    area_light: Option<AreaLight>,
    fov_deg: f32,
    seed: u64,
) -> PathSetup<'_> {
    let environment = Environment::new(
        &EnvironmentConfig {
            kind: EnvironmentKind::Studio,
            intensity,
            ..EnvironmentConfig::default()
        },
        0.0,
    )
    .unwrap();
    PathSetup {
        camera: Camera::look_at(
            Vec3::new(0.0, 0.0, 100.0),
            Vec3::ZERO,
            Vec3::Y,
            fov_deg,
            8,
            8,
        ),
        width: 8,
        height: 8,
        spp: 1,
        max_depth: 8,
        max_scatterings: 0,
        light: None,
        environment,
        area_light,
        gloss: 0.0,
        seed,

        sampling: Sampling::Sobol,
        spectral: sampler,
    }
}

/// [`mean_y`] with the tracer set by `configure`, its paths drawn from `stream`.
pub(in crate::path) fn mean_y_with(
    stone: &Stone,
    setup: &PathSetup,
    stream: u64,
    spp: u64,
    configure: impl Fn(&mut Tracer),
) -> [f64; 3] {
    let mut tracer = Tracer::new(stone, setup);
    configure(&mut tracer);
    let mut bins = vec![0.0f32; setup.spectral.grid.bins];
    let pixels = (setup.width * setup.height) as u64;
    let (mut mean, mut variance) = (0.0f64, 0.0f64);
    for p in 0..pixels {
        let (mut sum, mut sum2) = (0.0f64, 0.0f64);
        for s in 0..spp {
            let key = setup.seed ^ stream.wrapping_mul(0x9E37_79B9_7F4A_7C15);
            let mut sampler = PathSampler::new(key, p, s as u32, Sampling::Independent);
            let x = (p % setup.width as u64) as f32 + sampler.uniform_f32();
            let y = (p / setup.width as u64) as f32 + sampler.uniform_f32();
            let mut acc = [0.0f64; 3];
            tracer.sample(setup.camera.ray(x, y), &mut sampler, &mut acc, &mut bins);
            sum += acc[1];
            sum2 += acc[1] * acc[1];
        }
        let m = sum / spp as f64;
        mean += m / pixels as f64;
        variance += (sum2 / spp as f64 - m * m) / pixels as f64;
    }
    [mean, (variance / (spp * pixels) as f64).sqrt(), variance]
}

#[test]
fn the_roulette_on_first_reflections_keeps_the_mean() {
    // The harlequin's cabochon under the studio, seen whole: with every reflection of the
    // camera ray's first segment followed, and with each followed at random (the bar
    // raised over the room's brightest, so that nearly every one is followed with
    // probability ¼, its weight over that), the mean is the same (4 standard errors).
    let mut scene = crate::scene::preset("harlequin").unwrap();
    scene.structure.seed = 1;
    let stone = Stone::new(&scene).unwrap();
    let sampler = SpectralSampler::new(scene.light.illuminant, &scene.spectrum, 4);
    let setup = studio_8x8(&sampler, 1.0, None, 12.0, 3);
    let tracer = Tracer::new(&stone, &setup);
    assert!(tracer.follow_from > 0.0);
    // A reflection straight up from the centre looks out through the camera's dark side
    // of the room: followed with the least probability.
    let p = tracer.follow_probability(Vec3::ZERO, Vec3::Z);
    assert_eq!(p, MIN_FOLLOW);
    let spp = 400;
    let [all, se_all, _] = mean_y_with(&stone, &setup, 0, spp, |t| t.follow_from = 0.0);
    let bar = 4.0 * setup.environment.peak();
    let [some, se_some, _] = mean_y_with(&stone, &setup, 1, spp, |t| t.follow_from = bar);
    let se = (se_all * se_all + se_some * se_some).sqrt();
    assert!(
        (some - all).abs() <= 4.0 * se,
        "roulette {some} vs all {all} ± {se}"
    );
}

//! The paper's two passes against the path tracer as the reference, on the paper's stone and
//! light: how far the two-pass approximation is from a converged render of the same scene.
//!
//! The two models differ by design: the two passes shade every cluster with the paper's Phong
//! lobe (n = 40, about 21° wide) and its diffuse glow, the path tracer with each domain a
//! mirror within its mosaic spread and the half-vector law. The measured relative RMS difference
//! over the stone (docs/model.md, "The two passes against the reference") is bounded here so
//! that a change to either renderer that moves them apart, or together, is seen.

use opalray::render::prepare;
use opalray::scene::{preset, IntegratorConfig, Method};

/// Linear RGB of the paper scene at `w × h` rendered by `method`.
fn render(method: Method, w: u32, h: u32, spp: u32) -> Vec<[f32; 3]> {
    let mut scene = preset("paper").unwrap();
    scene.render.width = w;
    scene.render.height = h;
    scene.integrator = IntegratorConfig::of(method);
    scene.integrator.set_spp(spp);
    scene.light.rays = 20_000;
    // The light's disc in the gloss is a lottery for the path tracer at 64 spp (tests/stored.rs,
    // `paper_stone`): with it the ratio below read 2.42, 1.48, 2.00 and 1.70 for seeds 0 to 3.
    scene.render.gloss = 0.0;
    let prepared = prepare(&scene).unwrap();
    prepared.render(scene.light.angle_deg).rgb.data
}

#[test]
fn the_two_passes_stay_within_their_measured_distance_of_the_path_tracer() {
    let (w, h) = (64, 48);
    let two_pass = render(Method::TwoPass, w, h, 1);
    let reference = render(Method::Path, w, h, 64);
    let lum = |v: &[f32; 3]| 0.2126 * v[0] + 0.7152 * v[1] + 0.0722 * v[2];
    let (mut diff, mut norm, mut n) = (0.0f64, 0.0f64, 0);
    let (mut mean_a, mut mean_r) = (0.0f64, 0.0f64);
    for (a, r) in two_pass.iter().zip(&reference) {
        // The stone: where either render is above the backdrop.
        if lum(a) + lum(r) < 0.01 {
            continue;
        }
        n += 1;
        for c in 0..3 {
            diff += f64::from(a[c] - r[c]).powi(2);
            norm += f64::from(r[c]).powi(2);
        }
        mean_a += f64::from(lum(a));
        mean_r += f64::from(lum(r));
    }
    assert!(n > 500, "{n} stone pixels");
    let rms = (diff / norm).sqrt();
    let ratio = mean_a / mean_r;
    eprintln!(
        "two-pass vs path: relative RMS {rms:.3}, mean luminance ratio {ratio:.3} over {n} px"
    );
    assert!(rms < RMS_BOUND, "relative RMS {rms}");
    assert!(
        (RATIO_RANGE.0..RATIO_RANGE.1).contains(&ratio),
        "mean ratio {ratio}"
    );
}

/// The measured relative RMS without the gloss at 64 × 48 (docs/model.md): 2.16, 2.13, 2.65
/// for seeds 0 to 2 with independent streams, 2.29 with the Sobol points (its spread is the
/// path tracer's fireflies at 64 spp), with a margin.
const RMS_BOUND: f64 = 3.2;
/// The measured ratio of mean luminances (two-pass over path) without the gloss: 2.08 to 2.09
/// for seeds 0 to 2 with independent streams, 2.05 with the Sobol points, with a margin.
const RATIO_RANGE: (f64, f64) = (1.8, 2.4);

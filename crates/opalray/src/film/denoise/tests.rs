//! The denoiser's tests: renders of known images with Gaussian noise, filtered.

use super::*;
use crate::sampling::Rng;

/// A sampled image as a film develops it (the parts the denoiser reads).
struct Sampled {
    xyz: Vec<[f32; 3]>,
    half_difference: Vec<[f32; 3]>,
    variance: Vec<[f32; 3]>,
    spp: u32,
}

impl<'a> From<&'a Sampled> for FilmImage<'a> {
    fn from(image: &'a Sampled) -> Self {
        FilmImage {
            xyz: &image.xyz,
            half_difference: &image.half_difference,
            variance: &image.variance,
            spp: image.spp,
        }
    }
}

const W: usize = 48;
const H: usize = 32;

/// A render of `truth` (per pixel) with `n` samples each `truth + N(0, sigma²)`, plus
/// `extra` added to one even sample of the pixel `(x, y)` if given.
fn render(
    truth: &dyn Fn(usize, usize) -> [f32; 3],
    n: u32,
    sigma: f64,
    extra: Option<(usize, usize, [f64; 3])>,
) -> Sampled {
    render_with(truth, n, &|_| sigma, extra)
}

/// [`render`] with each sample's σ a function of the pixel's true value in the channel
/// (light's noise grows with the light).
fn render_with(
    truth: &dyn Fn(usize, usize) -> [f32; 3],
    n: u32,
    sigma: &dyn Fn(f64) -> f64,
    extra: Option<(usize, usize, [f64; 3])>,
) -> Sampled {
    let mut rng = Rng::new(3, 0, 0);
    let mut normal = move || {
        let (u, v) = (1.0 - rng.uniform(), rng.uniform());
        (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
    };
    let (mut xyz, mut half_difference, mut variance) = (vec![], vec![], vec![]);
    for y in 0..H {
        for x in 0..W {
            let t = truth(x, y);
            let (mut halves, mut squares) = ([[0.0f64; 3]; 2], [0.0f64; 3]);
            for s in 0..n {
                for c in 0..3 {
                    let mut v = f64::from(t[c]) + sigma(f64::from(t[c])) * normal();
                    if s == 0 && extra.is_some_and(|(ex, ey, _)| (ex, ey) == (x, y)) {
                        v += extra.unwrap().2[c];
                    }
                    halves[(s % 2) as usize][c] += v;
                    squares[c] += v * v;
                }
            }
            let (na, nb, nf) = (f64::from(n.div_ceil(2)), f64::from(n / 2), f64::from(n));
            let mean: [f64; 3] = std::array::from_fn(|c| (halves[0][c] + halves[1][c]) / nf);
            xyz.push(mean.map(|v| v as f32));
            half_difference.push(std::array::from_fn(|c| {
                (halves[0][c] / na - halves[1][c] / nb) as f32
            }));
            variance.push(std::array::from_fn(|c| {
                ((squares[c] - nf * mean[c] * mean[c]) / (nf - 1.0) / nf) as f32
            }));
        }
    }
    Sampled {
        xyz,
        half_difference,
        variance,
        spp: n,
    }
}

/// Two flat patches of different colour meeting at `x = W / 2`.
fn two_patches(x: usize, _y: usize) -> [f32; 3] {
    if x < W / 2 {
        [1.0, 2.0, 0.5]
    } else {
        [3.0, 1.0, 2.5]
    }
}

fn rms_error(image: &[[f32; 3]], truth: &dyn Fn(usize, usize) -> [f32; 3]) -> f64 {
    let mut sum = 0.0;
    for (i, v) in image.iter().enumerate() {
        let t = truth(i % W, i / W);
        sum += (0..3).map(|c| f64::from(v[c] - t[c]).powi(2)).sum::<f64>();
    }
    (sum / (3 * image.len()) as f64).sqrt()
}

#[test]
fn a_noiseless_image_passes_unchanged() {
    // Every pixel different, no noise: no pixel is alike to another within ε.
    let truth = |x: usize, y: usize| [x as f32, y as f32, (x * y) as f32 * 0.01];
    let image = render(&truth, 4, 0.0, None);
    let out = denoise(&image, W, H, &NlMeans::default()).unwrap();
    assert!(rms_error(&out.xyz, &truth) < 1e-6);
    assert!(out
        .half_difference
        .iter()
        .flatten()
        .all(|&d| d.abs() < 1e-6));
}

#[test]
fn noise_falls_and_a_patch_edge_stays_sharp() {
    // Samples of σ = 1 and n = 8: each pixel's mean has an error of 1/√8 ≈ 0.354 (the
    // raw image's RMS error, checked). Two patches whose channels differ by 1–2 (3–6 of
    // those errors) meet in a vertical edge.
    let image = render(&two_patches, 8, 1.0, None);
    let raw = rms_error(&image.xyz, &two_patches);
    assert!((raw / (1.0 / 8f64.sqrt()) - 1.0).abs() < 0.05, "{raw}");
    let out = denoise(&image, W, H, &NlMeans::default()).unwrap();
    let filtered = rms_error(&out.xyz, &two_patches);
    assert!(filtered < raw / 3.0, "{filtered} against {raw}");
    // The columns either side of the edge keep their own patch's mean: the other
    // patch's value would be 1–2 away.
    for x in [W / 2 - 1, W / 2] {
        let column: Vec<_> = (0..H).map(|y| out.xyz[y * W + x]).collect();
        for c in 0..3 {
            let mean = column.iter().map(|v| v[c]).sum::<f32>() / H as f32;
            let t = two_patches(x, 0)[c];
            assert!(
                (mean - t).abs() < 0.25,
                "column {x} channel {c}: {mean} for {t}"
            );
        }
    }
    // The filtered halves' difference estimates the noise left: within a factor of two
    // of the true error (it cannot see bias; here the bias is small).
    let d = out.half_difference.iter().flatten();
    let estimate =
        (d.map(|&v| f64::from(v).powi(2)).sum::<f64>() / (3 * W * H) as f64 / 4.0).sqrt();
    assert!(
        estimate > filtered / 2.0 && estimate < filtered * 2.0,
        "{estimate} {filtered}"
    );
}

#[test]
fn a_lone_firefly_is_cut_and_a_bright_detail_kept() {
    // A flat image of 1 (σ = 0.2, n = 8) with one sample of one pixel 2000 above the rest:
    // the firefly is cut to at most 4 × its surroundings (in one half: 4 + 1 in the mean
    // of the two, so no pixel shows over 3 after the filter). A bright pixel in both
    // halves (each of its 8 samples 30 above) keeps its mean to within a tenth.
    let flat = |_x: usize, _y: usize| [1.0f32; 3];
    let (fx, fy) = (W / 2, H / 2);
    let image = render(&flat, 8, 0.2, Some((fx, fy, [2000.0; 3])));
    let out = denoise(&image, W, H, &NlMeans::default()).unwrap();
    let peak = out.xyz.iter().map(|v| v[1]).fold(0.0f32, f32::max);
    assert!(peak < 3.0, "{peak}");
    let detail = |x: usize, y: usize| {
        if (x, y) == (fx, fy) {
            [31.0f32; 3]
        } else {
            [1.0; 3]
        }
    };
    let image = render(&detail, 8, 0.2, None);
    let out = denoise(&image, W, H, &NlMeans::default()).unwrap();
    let kept = out.xyz[fy * W + fx][1];
    assert!((kept / 31.0 - 1.0).abs() < 0.1, "{kept}");
}

#[test]
fn a_firefly_of_one_channel_is_cut() {
    // A white body (1 in X, Y and Z; σ = 0.05, n = 8) with one sample of one pixel 400 above
    // it in Z alone (a violet sample: its Y no brighter than the body's): cut, no pixel's
    // Z shows over 3 after the filter, where spread with its energy it would lift the
    // disc about it (radius 7) by 400 / 8 / 150 ≈ 0.3 over an area of 150 pixels.
    let flat = |_x: usize, _y: usize| [1.0f32; 3];
    let (fx, fy) = (W / 2, H / 2);
    let image = render(&flat, 8, 0.05, Some((fx, fy, [0.0, 0.0, 400.0])));
    let out = denoise(&image, W, H, &NlMeans::default()).unwrap();
    let peak = out.xyz.iter().map(|v| v[2]).fold(0.0f32, f32::max);
    assert!(peak < 3.0, "{peak}");
    let lifted = out.xyz.iter().filter(|v| v[2] > 1.15).count();
    assert!(lifted < 5, "{lifted} pixels lifted");
}

#[test]
fn the_filtered_image_keeps_the_raw_images_mean_and_colour() {
    // Two patches (σ = 0.3, n = 8) and, on every 37th pixel, one sample far above the rest
    // in Z, less in Y and X (violet fireflies: rare paths of a blue flash). On the same
    // samples the filtered image's sums of X, Y, Z and luminance (Y) are the raw image's
    // within 0.5 %: what the firefly cut takes is returned. Without the return they lose
    // several %: X alone comes out 3.7 % low (measured).
    let mut image = render(&two_patches, 8, 0.3, None);
    let firefly = [20.0f32, 12.0, 150.0];
    for i in (0..W * H).step_by(37) {
        for (c, f) in firefly.iter().enumerate() {
            // One even sample of eight `firefly` higher: the mean by firefly / 8, the even
            // half's mean by firefly / 4, so the halves' difference by firefly / 4.
            image.xyz[i][c] += f / 8.0;
            image.half_difference[i][c] += f / 4.0;
        }
    }
    let out = denoise(&image, W, H, &NlMeans::default()).unwrap();
    assert!(out.cut_share[2] > 0.02, "the cut took {:?}", out.cut_share);
    for c in 0..3 {
        let (filtered, raw) = (channel_sum(&out.xyz, c), channel_sum(&image.xyz, c));
        assert!(
            (filtered / raw - 1.0).abs() < 0.005,
            "channel {c}: filtered {filtered} vs raw {raw}"
        );
        assert!((out.bias[c] - (filtered / raw - 1.0)).abs() < 1e-9);
    }
}

#[test]
fn bright_fragments_on_a_dark_body_keep_their_light() {
    // A dark body (0.05, 0.04, 0.08) strewn with bright pixels (3 in 23; X, Y, Z up to
    // 2.1, 1.5, 3.9: a blue-green flash), the noise growing with the light (σ = 1.5 √v per
    // sample, 16 samples) as a path tracer's does, no firefly. Each pixel's variance sets
    // how widely it averages, so plain non-local means moves light between bright and dark
    // pixels unevenly (X came out 1.9 % high before the residual was returned); on the
    // same samples the filtered image must keep the raw image's X, Y, Z within 0.5 %.
    let truth = |x: usize, y: usize| {
        let h = (x * 7919 + y * 104_729) % 23;
        if h < 3 {
            let k = 1.0 + h as f32;
            [0.7 * k, 0.5 * k, 1.3 * k]
        } else {
            [0.05, 0.04, 0.08]
        }
    };
    let image = render_with(&truth, 16, &|v| 1.5 * v.sqrt(), None);
    let out = denoise(&image, W, H, &NlMeans::default()).unwrap();
    for c in 0..3 {
        let (filtered, raw) = (channel_sum(&out.xyz, c), channel_sum(&image.xyz, c));
        assert!(
            (filtered / raw - 1.0).abs() < 0.005,
            "channel {c}: filtered {filtered} vs raw {raw}"
        );
    }
}

#[test]
fn the_filter_is_the_same_bytes_at_any_thread_count() {
    let image = render(&two_patches, 4, 1.0, None);
    let at = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        pool.install(|| denoise(&image, W, H, &NlMeans::default()).unwrap().xyz)
    };
    let one = at(1);
    for threads in [2, 3] {
        assert!(at(threads) == one, "{threads} threads");
    }
}

#[test]
fn one_sample_per_pixel_cannot_be_filtered() {
    let image = render(&two_patches, 1, 1.0, None);
    assert!(denoise(&image, W, H, &NlMeans::default()).is_none());
}

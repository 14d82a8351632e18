//! The path tracer's golden image, compared statistically (the Monte Carlo renderer's
//! counterpart of golden.rs): a reference stored with each pixel's variance, a new render
//! with *independent* samples of the same stone (`integrator.seed`), and a per-pixel test.
//!
//! Each pixel's XYZ mean `m` comes with the variance of that mean, `v = s²/n` (the samples'
//! variance over their number). For pixel p and channel c the statistic is
//! `z = (m₁ − m₂) / √(v₁ + v₂)`, under the null hypothesis (same scene, independent samples) a
//! Welch t variable with at least `n − 1` degrees of freedom. A pixel is an outlier if any
//! channel has `|z| > K`. The chance of that is at most `p = 3 · P(|T_{n−1}| > K)` (three
//! channels, the union bound), and pixels are independent, so the number of outliers is at
//! most Binomial(N, p) in distribution; the test allows the smallest count `m` with
//! `P(Binomial(N, p) > m) < 10⁻⁴`, which bounds the false-failure rate of the whole image.
//! Here (48 × 36, 64 spp, K = 4) 6 outliers are allowed; six independent seeds gave 0–1, and
//! spheres 1 % / 3 % larger gave 18 / 58. On failure the actual, reference and difference (|z|/K, red beyond K) images are written
//! under the test's target directory and their paths printed. `OPALRAY_BLESS=1 cargo test
//! --test golden_path` rewrites the reference (look at its PNG before committing).

use std::path::{Path, PathBuf};

use glam::{Mat3, Vec3};
use opalray::integrator::Passes;
use opalray::path::{PathImage, Sampling};
use opalray::render::prepare;
use opalray::scene::{preset, Backing, IntegratorConfig, OrientationLaw, PathConfig};
use opalray::Scene;

/// A channel beyond this many combined standard errors makes its pixel an outlier.
const K: f64 = 4.0;
/// Most accepted chance that a correct render fails the test.
const FALSE_FAILURE_RATE: f64 = 1e-4;
/// Samples per pixel of the reference and of the renders compared with it.
const SPP: u32 = 64;
/// `integrator.seed` of the reference.
const REFERENCE_SEED: u64 = 0;
/// `integrator.seed` of the renders compared with it: independent samples.
const TEST_SEED: u64 = 1;
/// Header line of the reference file, before width, height and spp.
const MAGIC: &str = "opalray path golden v1";

fn scene() -> Scene {
    let mut s = preset("harlequin").unwrap();
    // The path tracer, denoised, as the preset rendered when the reference was made.
    s.integrator = IntegratorConfig::Path(PathConfig {
        denoise: true,
        ..PathConfig::default()
    });
    // The stone the reference was rendered with (the preset has since drawn another).
    s.structure.seed = 1;
    // Thick grains of independent orientations (fewer domains along a ray than the
    // preset's settled plates): a quarter of the time for the same power.
    s.domains.stretch = [1.0, 1.0, 0.35];
    s.domains.orientation = OrientationLaw::Independent;
    // The sphere sizes the reference was rendered with (each grain its own).
    s.crystal.sphere_diameter_nm = 265.0;
    s.domains.sphere_diameter_spread = 0.07;
    s.domains.diameter_correlation_mm = 0.0;
    s.body.colour_bar_mm = 2.0;
    // The bare polished back the reference was rendered with (the black opal presets have
    // since had their black potch back).
    s.body.backing = Some(Backing::None);
    s.render.width = 48;
    s.render.height = 36;
    s.spectrum.bins = 16;
    s.integrator.set_spp(SPP);
    s
}

/// XYZ means and the variances of those means, per pixel.
struct Stats {
    width: usize,
    height: usize,
    spp: u32,
    mean: Vec<[f32; 3]>,
    variance: Vec<[f32; 3]>,
}

fn render(scene: &Scene) -> (Stats, Mat3) {
    let prepared = prepare(scene).unwrap();
    let (image, m): (PathImage, Mat3) = prepared
        .render_path_image(scene.light.angle_deg, &Passes::default(), Sampling::Sobol)
        .unwrap();
    let stats = Stats {
        width: scene.render.width as usize,
        height: scene.render.height as usize,
        spp: image.spp,
        mean: image.xyz,
        variance: image.variance,
    };
    (stats, m)
}

fn reference_path() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden/harlequin-path.f32")
}

fn save(path: &Path, s: &Stats) {
    let mut bytes = format!("{MAGIC} {} {} {}\n", s.width, s.height, s.spp).into_bytes();
    for (m, v) in s.mean.iter().zip(&s.variance) {
        for x in m.iter().chain(v) {
            bytes.extend_from_slice(&x.to_le_bytes());
        }
    }
    std::fs::write(path, bytes).unwrap();
}

fn load(path: &Path) -> Stats {
    let bytes = std::fs::read(path)
        .unwrap_or_else(|e| panic!("{}: {e}; run with OPALRAY_BLESS=1", path.display()));
    let end = bytes.iter().position(|&b| b == b'\n').unwrap();
    let header = std::str::from_utf8(&bytes[..end]).unwrap();
    let fields: Vec<&str> = header
        .strip_prefix(MAGIC)
        .expect("a path golden file")
        .split_whitespace()
        .collect();
    let [width, height, spp] = [0, 1, 2].map(|i| fields[i].parse::<usize>().unwrap());
    let floats: Vec<f32> = bytes[end + 1..]
        .chunks_exact(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    assert_eq!(floats.len(), width * height * 6, "{}: size", path.display());
    let px = |i: usize, at: usize| [0, 1, 2].map(|c| floats[i * 6 + at + c]);
    Stats {
        width,
        height,
        spp: spp as u32,
        mean: (0..width * height).map(|i| px(i, 0)).collect(),
        variance: (0..width * height).map(|i| px(i, 3)).collect(),
    }
}

/// `P(|T| > k)` for Student's t with `nu` degrees of freedom: the density's shape integrated
/// by Simpson's rule (normalised by its own integral), the tail over `u = 1/t` so that it is a
/// finite interval.
fn student_two_sided_tail(k: f64, nu: f64) -> f64 {
    let shape = |t: f64| (1.0 + t * t / nu).powf(-(nu + 1.0) / 2.0);
    let simpson = |f: &dyn Fn(f64) -> f64, a: f64, b: f64| {
        let n = 4000;
        let h = (b - a) / n as f64;
        let inner: f64 = (1..n)
            .map(|i| f(a + i as f64 * h) * if i % 2 == 1 { 4.0 } else { 2.0 })
            .sum();
        (f(a) + f(b) + inner) * h / 3.0
    };
    // shape(1/u)/u² = u^(ν−1) (u² + 1/ν)^(−(ν+1)/2), in logarithms; at u = 0 its limit.
    let tail_shape = |u: f64| {
        if u > 0.0 {
            ((nu - 1.0) * u.ln() - 0.5 * (nu + 1.0) * (u * u + 1.0 / nu).ln()).exp()
        } else if nu == 1.0 {
            1.0
        } else {
            0.0
        }
    };
    let tail = simpson(&tail_shape, 0.0, 1.0 / k);
    let body = simpson(&shape, 0.0, k);
    tail / (tail + body)
}

/// Smallest `m` with `P(Binomial(n, p) > m) < rate`, and that probability.
fn allowed_outliers(n: usize, p: f64, rate: f64) -> (usize, f64) {
    let mut pmf = (1.0 - p).powf(n as f64);
    let mut cdf = pmf;
    let mut m = 0;
    while 1.0 - cdf >= rate {
        pmf *= (n - m) as f64 / (m + 1) as f64 * p / (1.0 - p);
        cdf += pmf;
        m += 1;
    }
    (m, 1.0 - cdf)
}

/// How a render compares with the reference.
struct Comparison {
    /// Per pixel, the largest |z| over its channels.
    z: Vec<f64>,
    outliers: usize,
    allowed: usize,
    false_failure_rate: f64,
}

fn compare(actual: &Stats, reference: &Stats) -> Comparison {
    assert_eq!(
        (actual.width, actual.height),
        (reference.width, reference.height),
        "size"
    );
    let n = actual.spp.min(reference.spp);
    assert!(n >= 2, "variances need two samples per pixel");
    // Pixels whose samples are all equal (the backdrop) have no variance: a floor of 10⁻⁶ of
    // the image's mean Y in standard error keeps their z finite.
    let mean_y =
        reference.mean.iter().map(|v| f64::from(v[1])).sum::<f64>() / reference.mean.len() as f64;
    let floor = (1e-6 * mean_y).powi(2);
    let z: Vec<f64> = (0..actual.mean.len())
        .map(|i| {
            (0..3)
                .map(|c| {
                    let d = f64::from(actual.mean[i][c]) - f64::from(reference.mean[i][c]);
                    let v = f64::from(actual.variance[i][c])
                        + f64::from(reference.variance[i][c])
                        + floor;
                    d.abs() / v.sqrt()
                })
                .fold(0.0, f64::max)
        })
        .collect();
    let outliers = z.iter().filter(|&&z| z > K).count();
    let p = (3.0 * student_two_sided_tail(K, f64::from(n - 1))).min(1.0);
    let (allowed, false_failure_rate) = allowed_outliers(z.len(), p, FALSE_FAILURE_RATE);
    Comparison {
        z,
        outliers,
        allowed,
        false_failure_rate,
    }
}

/// Display codes of an XYZ image through `m` (the frame's XYZ → linear RGB).
fn display(s: &Stats, m: Mat3, scene: &Scene) -> Vec<u8> {
    let rgb = opalray::color::RgbImage {
        width: s.width,
        height: s.height,
        data: s
            .mean
            .iter()
            .map(|&v| (m * Vec3::from_array(v)).to_array())
            .collect(),
    };
    opalray::color::to_display_rgb8(&rgb, &scene.color)
}

/// Compare a render of `scene` with the reference; on failure write the images and panic.
/// Blessing renders the reference: `scene` with `integrator.seed` = [`REFERENCE_SEED`].
fn check(name: &str, scene: &Scene) {
    let path = reference_path();
    if std::env::var_os("OPALRAY_BLESS").is_some() {
        let mut scene = scene.clone();
        scene.integrator.set_seed(REFERENCE_SEED);
        let (actual, m) = render(&scene);
        save(&path, &actual);
        let png = path.with_extension("png");
        let codes = display(&actual, m, &scene);
        opalray::output::write_png_rgb8(&png, actual.width as u32, actual.height as u32, &codes)
            .unwrap();
        return;
    }
    let (actual, m) = render(scene);
    let reference = load(&path);
    let c = compare(&actual, &reference);
    if c.outliers > c.allowed {
        let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("golden");
        std::fs::create_dir_all(&out).unwrap();
        let (w, h) = (actual.width as u32, actual.height as u32);
        let write = |suffix: &str, data: &[u8]| {
            let p = out.join(format!("{name}-{suffix}.png"));
            opalray::output::write_png_rgb8(&p, w, h, data).unwrap();
            p
        };
        let a = write("actual", &display(&actual, m, scene));
        let r = write("reference", &display(&reference, m, scene));
        let diff: Vec<u8> =
            c.z.iter()
                .flat_map(|&z| {
                    if z > K {
                        [255, 0, 0]
                    } else {
                        [(255.0 * z / K) as u8; 3]
                    }
                })
                .collect();
        let d = write("difference", &diff);
        panic!(
            "{name}: {} pixels beyond {K} standard errors, {} allowed (false-failure rate \
             {:.1e})\nactual {}\nreference {}\ndifference (|z|/{K}, red beyond) {}",
            c.outliers,
            c.allowed,
            c.false_failure_rate,
            a.display(),
            r.display(),
            d.display()
        );
    }
}

#[test]
fn student_tail_matches_the_cauchy_and_normal_laws() {
    // ν = 1 is Cauchy: P(|T| > k) = 1 − 2 atan(k)/π; ν → ∞ is the normal law:
    // P(|Z| > 2) = 0.045500 (Abramowitz & Stegun table 26.1).
    for k in [0.5, 1.0, 4.0] {
        let cauchy = 1.0 - 2.0 * f64::atan(k) / std::f64::consts::PI;
        let got = student_two_sided_tail(k, 1.0);
        assert!((got / cauchy - 1.0).abs() < 1e-6, "{k}: {got} vs {cauchy}");
    }
    let normal = student_two_sided_tail(2.0, 1e7);
    assert!((normal - 0.045500).abs() < 2e-6, "{normal}");
    let (m, rate) = allowed_outliers(1728, 1e-3, 1e-4);
    assert!(rate < 1e-4 && m > 1, "{m} {rate}");
}

#[test]
fn golden_harlequin_path_with_independent_samples() {
    let mut s = scene();
    s.integrator.set_seed(TEST_SEED);
    check("harlequin-path", &s);
}

#[test]
fn golden_path_test_fails_for_spheres_three_percent_larger() {
    // The test must be able to fail: the same stone with spheres 3 % larger (every line 3 %
    // redder) is refused.
    let mut s = scene();
    s.integrator.set_seed(TEST_SEED);
    s.crystal.sphere_diameter_nm *= 1.03;
    let (actual, _) = render(&s);
    let c = compare(&actual, &load(&reference_path()));
    assert!(
        c.outliers > c.allowed,
        "{} outliers, {} allowed: a 3 % larger sphere passes",
        c.outliers,
        c.allowed
    );
}

#[test]
fn noise_from_half_sums_agrees_with_the_samples_variance() {
    // Two estimators of the RMS standard error over the stone, from the same samples: the
    // even/odd half differences (`PathImage::noise`, Var(m) = Var(a − b)/4) and each pixel's
    // sample variance over n. Over the ~540 stone pixels their ratio was 0.86–1.14 for six
    // seeds (a few bright pixels carry most of the variance); a missing ¼ would make it 2.
    let s = scene();
    let prepared = prepare(&s).unwrap();
    let (image, m) = prepared
        .render_path_image(s.light.angle_deg, &Passes::default(), Sampling::Sobol)
        .unwrap();
    let noise = image.noise(m).unwrap();
    let stone: Vec<usize> = (0..image.xyz.len())
        .filter(|&i| image.on_stone[i])
        .collect();
    assert_eq!(noise.pixels, stone.len());
    assert!(stone.len() > 400, "{} stone pixels", stone.len());
    let count = stone.len() as f64;
    let mean_y = stone
        .iter()
        .map(|&i| f64::from(image.xyz[i][1]))
        .sum::<f64>()
        / count;
    let var_y = stone
        .iter()
        .map(|&i| f64::from(image.variance[i][1]))
        .sum::<f64>()
        / count;
    let from_variance = var_y.sqrt() / mean_y;
    let from_halves = noise.relative_rms.unwrap();
    assert!(
        (from_halves / from_variance - 1.0).abs() < 0.3,
        "halves {from_halves}, sample variance {from_variance}"
    );
}

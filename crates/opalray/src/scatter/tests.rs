//! Each kind's draw against its density: a χ² test over directions (the draws binned in
//! (θ, φ) about the kind's axis, the expected counts integrated from the density), the
//! density's integral over the sphere, and a wrong density rejected by the same test (so
//! that the test can fail).

use std::f64::consts::PI;

use glam::Vec3;

use super::*;
use crate::sampling::Rng;

impl Draws for Rng {
    fn uniform_f32(&mut self) -> f32 {
        Rng::uniform_f32(self)
    }

    fn uniform(&mut self) -> f64 {
        Rng::uniform(self)
    }
}

/// Draws per test.
const DRAWS: usize = 200_000;
/// Bins in θ and in φ.
const THETA_BINS: usize = 20;
const PHI_BINS: usize = 40;
/// Midpoint nodes per bin and axis for the expected counts.
const NODES: usize = 6;
/// Significance of one test, corrected for the tests run (Šidák).
const TESTS: f64 = 8.0;
const ALPHA: f64 = 0.01;

/// The frame of the binning: `axis` and two unit vectors across it.
fn frame(axis: Vec3) -> (Vec3, Vec3, Vec3) {
    let (t, b) = axis.any_orthonormal_pair();
    (axis, t, b)
}

/// The bin of `d` (θ up to `theta_max` about the frame's axis), or the last index beyond.
fn bin(d: Vec3, (axis, t, b): (Vec3, Vec3, Vec3), theta_max: f64) -> usize {
    let theta = f64::from(angle_between(d.normalize(), axis));
    if theta >= theta_max {
        return THETA_BINS * PHI_BINS;
    }
    let phi = f64::from(d.dot(b))
        .atan2(f64::from(d.dot(t)))
        .rem_euclid(2.0 * PI);
    let i = ((theta / theta_max) * THETA_BINS as f64) as usize;
    let j = ((phi / (2.0 * PI)) * PHI_BINS as f64) as usize;
    i.min(THETA_BINS - 1) * PHI_BINS + j.min(PHI_BINS - 1)
}

/// Expected counts of `DRAWS` draws in each bin from the density `density`, the last entry
/// the rest of the sphere.
fn expected(
    density: &dyn Fn(Vec3) -> f32,
    (axis, t, b): (Vec3, Vec3, Vec3),
    theta_max: f64,
) -> Vec<f64> {
    let (dt, dp) = (theta_max / THETA_BINS as f64, 2.0 * PI / PHI_BINS as f64);
    let mut out = vec![0.0; THETA_BINS * PHI_BINS + 1];
    for i in 0..THETA_BINS {
        for j in 0..PHI_BINS {
            let mut mass = 0.0;
            for u in 0..NODES {
                for v in 0..NODES {
                    let theta = (i as f64 + (u as f64 + 0.5) / NODES as f64) * dt;
                    let phi = (j as f64 + (v as f64 + 0.5) / NODES as f64) * dp;
                    let d = axis * theta.cos() as f32
                        + (t * phi.cos() as f32 + b * phi.sin() as f32) * theta.sin() as f32;
                    mass += f64::from(density(d.normalize())) * theta.sin();
                }
            }
            out[i * PHI_BINS + j] = mass * dt * dp / (NODES * NODES) as f64 * DRAWS as f64;
        }
    }
    let inside: f64 = out.iter().sum();
    out[THETA_BINS * PHI_BINS] = (DRAWS as f64 - inside).max(0.0);
    out
}

/// The regularised upper incomplete gamma function Q(a, x) (series below a + 1, Lentz's
/// continued fraction above; Numerical Recipes §6.2).
fn gamma_q(a: f64, x: f64) -> f64 {
    let ln_gamma_a = ln_gamma(a);
    if x < a + 1.0 {
        let (mut term, mut sum, mut n) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            n += 1.0;
            term *= x / n;
            sum += term;
            if term < sum * 1e-15 {
                break;
            }
        }
        1.0 - sum * (-x + a * x.ln() - ln_gamma_a).exp()
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            d = if d.abs() < tiny { tiny } else { d };
            c = b + an / c;
            c = if c.abs() < tiny { tiny } else { c };
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-15 {
                break;
            }
        }
        (-x + a * x.ln() - ln_gamma_a).exp() * h
    }
}

/// ln Γ(x) for x > 0 (Lanczos, g = 7, nine terms).
fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    let x = x - 1.0;
    let t = x + 7.5;
    let sum: f64 = C[0] + (1..9).map(|k| C[k] / (x + k as f64)).sum::<f64>();
    0.5 * (2.0 * PI).ln() + (x + 0.5) * t.ln() - t + sum.ln()
}

/// The p-value of the draws of `sample` against `density`, binned about `axis` up to
/// `theta_max` (bins expecting under 5 draws pooled, as pbrt does).
fn chi2_p(
    sample: &mut dyn FnMut(&mut Rng) -> Vec3,
    density: &dyn Fn(Vec3) -> f32,
    axis: Vec3,
    theta_max: f64,
    seed: u64,
) -> f64 {
    let f = frame(axis);
    let mut observed = vec![0.0f64; THETA_BINS * PHI_BINS + 1];
    let mut rng = Rng::new(seed, 0x5ca7, 0);
    for _ in 0..DRAWS {
        observed[bin(sample(&mut rng), f, theta_max)] += 1.0;
    }
    let want = expected(density, f, theta_max);
    let (mut chi2, mut dof, mut pool_o, mut pool_e) = (0.0, 0usize, 0.0, 0.0);
    for (o, e) in observed.iter().zip(&want) {
        if *e < 5.0 {
            pool_o += o;
            pool_e += e;
        } else {
            chi2 += (o - e).powi(2) / e;
            dof += 1;
        }
    }
    if pool_e > 0.0 {
        chi2 += (pool_o - pool_e).powi(2) / pool_e;
        dof += 1;
    }
    gamma_q((dof as f64 - 1.0) / 2.0, chi2 / 2.0)
}

/// The significance each test must pass.
fn threshold() -> f64 {
    1.0 - (1.0 - ALPHA).powf(1.0 / TESTS)
}

/// `∫ density dω` over the sphere, by the midpoint rule on a fine (θ, φ) grid about `axis`.
fn integral(density: &dyn Fn(Vec3) -> f32, axis: Vec3, theta_max: f64) -> f64 {
    expected(density, frame(axis), theta_max)[..THETA_BINS * PHI_BINS]
        .iter()
        .sum::<f64>()
        / DRAWS as f64
}

#[test]
fn the_gamma_function_and_the_chi2_tail_are_right() {
    // Γ(5) = 24, Γ(½) = √π; χ² with 2 dof: Q(1, x/2) = e^(−x/2); with 10 dof at 18.307 the
    // upper tail is 0.05 (tables).
    assert!((ln_gamma(5.0) - 24f64.ln()).abs() < 1e-12);
    assert!((ln_gamma(0.5) - PI.sqrt().ln()).abs() < 1e-12);
    assert!((gamma_q(1.0, 1.5) - (-1.5f64).exp()).abs() < 1e-12);
    assert!((gamma_q(5.0, 18.307 / 2.0) - 0.05).abs() < 1e-4);
}

#[test]
fn the_phase_function_draws_follow_its_density() {
    let incoming = Vec3::new(0.3, -0.2, 0.9).normalize();
    for (k, g) in [0.0f32, 0.4, 0.85, -0.3].into_iter().enumerate() {
        let law = Phase { incoming, g };
        let mass = integral(&|d| law.density(d), incoming, PI);
        assert!((mass - 1.0).abs() < 2e-3, "g {g}: ∫ p dω = {mass}");
        let p = chi2_p(
            &mut |r| law.sample(r),
            &|d| law.density(d),
            incoming,
            PI,
            k as u64,
        );
        assert!(p > threshold(), "g {g}: p = {p}");
        assert_eq!(law.eval(incoming), law.density(incoming));
    }
}

#[test]
fn the_mosaic_lobe_draws_follow_its_density() {
    let normal = Vec3::new(-0.1, 0.2, 1.0).normalize();
    for (k, sigma) in [0.01f32, 0.05, 0.2].into_iter().enumerate() {
        let law = Mosaic { normal, sigma };
        let reach = f64::from(6.0 * sigma);
        let mass = integral(&|h| law.density(h), normal, reach);
        assert!((mass - 1.0).abs() < 2e-3, "σ {sigma}: ∫ D dω = {mass}");
        let p = chi2_p(
            &mut |r| law.sample(r),
            &|h| law.density(h),
            normal,
            reach,
            10 + k as u64,
        );
        assert!(p > threshold(), "σ {sigma}: p = {p}");
        // The small-angle form the gather uses differs by sin α / α.
        let h = law.sample(&mut Rng::new(3, 3, 3));
        let alpha = angle_between(h, normal);
        let ratio = law.small_angle_density(h, 100.0) / law.density(h);
        assert!(
            (ratio - alpha.sin() / alpha).abs() < 1e-4,
            "σ {sigma}: {ratio}"
        );
    }
}

#[test]
fn the_backing_draws_follow_the_cosine() {
    let law = Lambert { albedo: 0.3 };
    let mass = integral(&|d| law.density(d), Vec3::Z, PI / 2.0);
    assert!((mass - 1.0).abs() < 2e-3, "∫ cos/π dω = {mass}");
    let p = chi2_p(
        &mut |r| law.sample(r),
        &|d| law.density(d),
        Vec3::Z,
        PI / 2.0,
        20,
    );
    assert!(p > threshold(), "p = {p}");
    // Its value is the reflectance's share: ∫ eval dω = albedo.
    let albedo = integral(&|d| law.eval(d), Vec3::Z, PI / 2.0);
    assert!((albedo - 0.3).abs() < 1e-3, "{albedo}");
}

#[test]
fn a_wrong_density_is_rejected() {
    // The same test, the draws of one law against the density of a slightly different one:
    // it must fail, or the tests above could not.
    let incoming = Vec3::Z;
    let drawn = Phase { incoming, g: 0.4 };
    let other = Phase { incoming, g: 0.43 };
    let p = chi2_p(
        &mut |r| drawn.sample(r),
        &|d| other.density(d),
        incoming,
        PI,
        30,
    );
    assert!(p < 1e-6, "g 0.4 against 0.43: p = {p}");
    let normal = Vec3::Z;
    let drawn = Mosaic {
        normal,
        sigma: 0.05,
    };
    let wider = Mosaic {
        normal,
        sigma: 0.052,
    };
    let p = chi2_p(
        &mut |r| drawn.sample(r),
        &|h| wider.density(h),
        normal,
        0.3,
        31,
    );
    assert!(p < 1e-6, "σ 0.05 against 0.052: p = {p}");
}

//! How much of a narrow lobe of directions an area light fills: the integral of a Gaussian
//! lobe over the light's solid angle, for the integrators that read the lights through a
//! lobe rather than by sampling them (the lobe integrator's Bragg reflections).
//!
//! The lobe about the unit direction `d` has standard deviation σ per axis; it is laid on
//! the tangent plane at `d` by the gnomonic projection (`u = p·e₁ / p·d`, `v = p·e₂ / p·d`),
//! where it is the plane's Gaussian `φ(u/σ) φ(v/σ) / σ²` (for σ of a few degrees the
//! projection's stretch is under 0.1 % of the lobe). A rectangle projects to a convex
//! polygon (straight lines stay straight), clipped first to the half space in front of the
//! lobe; a ball's cap projects to a disc of its angular radius about its axis's angular
//! offset. Either is integrated exactly in one direction (`Φ` at the two sides of the
//! shape) and by Gauss–Legendre quadrature in the other, over the part of the shape within
//! [`REACH`] σ of the lobe's centre, split at the polygon's corners so that every piece is
//! smooth. A cheap cone test first returns 0 for the lobes far from the light.

use glam::{DVec3, Vec3};

use super::emitters::AreaLight;
use super::env::filter::erf;

/// Lobe widths beyond which the lobe holds nothing (`e^{−REACH²/2}` ≈ 10⁻¹⁴).
const REACH: f64 = 8.0;
/// Most pieces of one quadrature.
const MAX_PIECES: f64 = 8.0;
/// Gauss–Legendre nodes and weights on [−1, 1] (16 points).
const NODES: [f64; 8] = [
    0.095_012_509_837_637_44,
    0.281_603_550_779_258_9,
    0.458_016_777_657_227_4,
    0.617_876_244_402_643_7,
    0.755_404_408_355_003,
    0.865_631_202_387_831_7,
    0.944_575_023_073_232_6,
    0.989_400_934_991_649_9,
];
const WEIGHTS: [f64; 8] = [
    0.189_450_610_455_068_5,
    0.182_603_415_044_923_6,
    0.169_156_519_395_002_5,
    0.149_595_988_816_576_7,
    0.124_628_971_255_533_9,
    0.095_158_511_682_492_8,
    0.062_253_523_938_647_9,
    0.027_152_459_411_754_1,
];

impl AreaLight {
    /// The share (0 to 1) of a Gaussian lobe of directions about `dir` (unit) with standard
    /// deviation `sigma_rad` per axis, seen from `x`, that falls on the light's emitting
    /// surface. A lobe of zero width is the plain hit test.
    pub fn lobe_share(&self, x: Vec3, dir: Vec3, sigma_rad: f32) -> f32 {
        if sigma_rad <= 0.0 {
            return if self.hit(x, dir).is_some() { 1.0 } else { 0.0 };
        }
        let (x, d, s) = (
            x.as_dvec3(),
            dir.as_dvec3().normalize(),
            f64::from(sigma_rad),
        );
        if self.beyond_reach(x, d, s) {
            return 0.0;
        }
        let (e1, e2) = d.any_orthonormal_pair();
        let share = match *self {
            AreaLight::Sphere {
                center, radius_mm, ..
            } => {
                let to = center - x;
                let dist = to.length();
                if dist <= radius_mm {
                    return 0.0;
                }
                let axis = to / dist;
                let alpha = (radius_mm / dist).asin();
                let beta = axis.dot(d).clamp(-1.0, 1.0).acos();
                disc_share(alpha, beta, s)
            }
            AreaLight::Rect {
                center,
                normal,
                across,
                up,
                half_mm,
                ..
            } => {
                if (center - x).dot(normal) >= 0.0 {
                    // Behind its emitting face.
                    return 0.0;
                }
                let corners = [(-1.0, -1.0), (1.0, -1.0), (1.0, 1.0), (-1.0, 1.0)]
                    .map(|(a, b)| center + across * (a * half_mm[0]) + up * (b * half_mm[1]) - x);
                let polygon = project(&corners, d, e1, e2);
                polygon_share(&polygon, s)
            }
        };
        share.clamp(0.0, 1.0) as f32
    }

    /// Whether the light lies wholly beyond [`REACH`] lobe widths of `d` seen from `x`: its
    /// bounding ball's cone against the lobe's.
    fn beyond_reach(&self, x: DVec3, d: DVec3, s: f64) -> bool {
        let (center, radius) = match *self {
            AreaLight::Sphere {
                center, radius_mm, ..
            } => (center, radius_mm),
            AreaLight::Rect {
                center, half_mm, ..
            } => (center, half_mm[0].hypot(half_mm[1])),
        };
        let to = center - x;
        let dist = to.length();
        if dist <= radius {
            return false;
        }
        let cone = (radius / dist).asin();
        let off = (to / dist).dot(d).clamp(-1.0, 1.0).acos();
        off > cone + REACH * s
    }
}

/// The corners `corners` (relative to the lobe's origin) clipped to the half space well in
/// front of the lobe (`p·d` above a thousandth of `|p|`: beyond 89.9° from `d`, where a
/// lobe of a few degrees holds nothing) and projected onto its tangent plane.
fn project(corners: &[DVec3; 4], d: DVec3, e1: DVec3, e2: DVec3) -> Vec<(f64, f64)> {
    let front = |p: DVec3| p.dot(d) - 1e-3 * p.length();
    let mut clipped: Vec<DVec3> = Vec::with_capacity(6);
    for k in 0..4 {
        let (a, b) = (corners[k], corners[(k + 1) % 4]);
        let (fa, fb) = (front(a), front(b));
        if fa >= 0.0 {
            clipped.push(a);
        }
        if (fa >= 0.0) != (fb >= 0.0) {
            // The edge crosses the clipping cone: bisect for the crossing (the cone's side
            // is not a plane, so no closed form), 40 halvings.
            let (mut lo, mut hi) = (0.0, 1.0);
            for _ in 0..40 {
                let mid = 0.5 * (lo + hi);
                if (front(a.lerp(b, mid)) >= 0.0) == (fa >= 0.0) {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            clipped.push(a.lerp(b, 0.5 * (lo + hi)));
        }
    }
    clipped
        .iter()
        .map(|p| {
            let z = p.dot(d);
            (p.dot(e1) / z, p.dot(e2) / z)
        })
        .collect()
}

/// `∫ φ(u/s) φ(v/s) / s² du dv` over the convex `polygon` (any winding).
fn polygon_share(polygon: &[(f64, f64)], s: f64) -> f64 {
    if polygon.len() < 3 {
        return 0.0;
    }
    let mut us: Vec<f64> = polygon.iter().map(|p| p.0).collect();
    us.sort_by(f64::total_cmp);
    let (lo, hi) = (-REACH * s, REACH * s);
    let mut total = 0.0;
    for pair in us.windows(2) {
        let (a, b) = (pair[0].max(lo), pair[1].min(hi));
        if b <= a {
            continue;
        }
        total += legendre(a, b, 2.0 * s, |u| {
            let (v_lo, v_hi) = chord(polygon, u);
            gauss(u, s) * (cdf(v_hi / s) - cdf(v_lo / s))
        });
    }
    total
}

/// The lowest and highest `v` of the convex `polygon` on the line at `u`.
fn chord(polygon: &[(f64, f64)], u: f64) -> (f64, f64) {
    let (mut v_lo, mut v_hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for k in 0..polygon.len() {
        let (a, b) = (polygon[k], polygon[(k + 1) % polygon.len()]);
        let (u0, u1) = if a.0 <= b.0 { (a.0, b.0) } else { (b.0, a.0) };
        if u < u0 || u > u1 {
            continue;
        }
        let v = if u1 - u0 <= f64::EPSILON * (1.0 + u1.abs()) {
            // A vertical edge: both its ends.
            v_lo = v_lo.min(a.1.min(b.1));
            v_hi = v_hi.max(a.1.max(b.1));
            continue;
        } else {
            a.1 + (b.1 - a.1) * (u - a.0) / (b.0 - a.0)
        };
        v_lo = v_lo.min(v);
        v_hi = v_hi.max(v);
    }
    if v_hi < v_lo {
        (0.0, 0.0)
    } else {
        (v_lo, v_hi)
    }
}

/// `∫ φ(u/s) φ(v/s) / s²` over a disc of radius `alpha` whose centre is `beta` from the
/// lobe's (along u): with `u = beta + alpha cos t`, the chord's half length is
/// `alpha sin t` and the integrand is smooth in t.
fn disc_share(alpha: f64, beta: f64, s: f64) -> f64 {
    let (lo, hi) = (
        (beta - alpha).max(-REACH * s),
        (beta + alpha).min(REACH * s),
    );
    if hi <= lo {
        return 0.0;
    }
    // u from lo to hi is t from t_hi down to t_lo.
    let t_of = |u: f64| ((u - beta) / alpha).clamp(-1.0, 1.0).acos();
    let (t_a, t_b) = (t_of(hi), t_of(lo));
    legendre(t_a, t_b, 2.0 * s / alpha, |t| {
        let (sin, cos) = t.sin_cos();
        let half = alpha * sin;
        gauss(beta + alpha * cos, s) * (cdf(half / s) - cdf(-half / s)) * alpha * sin
    })
}

/// Gauss–Legendre quadrature of `f` over [a, b], 16 points on each of as many equal pieces
/// as `step` fits in it (at most [`MAX_PIECES`]).
fn legendre(a: f64, b: f64, step: f64, f: impl Fn(f64) -> f64) -> f64 {
    let pieces = ((b - a) / step).ceil().clamp(1.0, MAX_PIECES);
    let width = (b - a) / pieces;
    let mut sum = 0.0;
    for k in 0..pieces as usize {
        let (mid, half) = (a + (k as f64 + 0.5) * width, 0.5 * width);
        let mut piece = 0.0;
        for (x, w) in NODES.iter().zip(WEIGHTS) {
            piece += w * (f(mid - half * x) + f(mid + half * x));
        }
        sum += piece * half;
    }
    sum
}

/// The normal density of `u` with standard deviation `s`.
fn gauss(u: f64, s: f64) -> f64 {
    let z = u / s;
    (-0.5 * z * z).exp() / (s * (2.0 * std::f64::consts::PI).sqrt())
}

/// The standard normal distribution function.
fn cdf(z: f64) -> f64 {
    0.5 * (1.0 + erf(z / std::f64::consts::SQRT_2))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The lobe's density over directions in the tangent plane's coordinates, per
    /// steradian: the plane's Gaussian times the projection's Jacobian `(1 + u² + v²)^{3/2}`.
    fn lobe_density(w: DVec3, d: DVec3, e1: DVec3, e2: DVec3, s: f64) -> f64 {
        let z = w.dot(d);
        if z <= 0.0 {
            return 0.0;
        }
        let (u, v) = (w.dot(e1) / z, w.dot(e2) / z);
        gauss(u, s) * gauss(v, s) * (1.0 + u * u + v * v).powf(1.5)
    }

    /// The share by brute force: the lobe's density over the light's surface, a fine
    /// midpoint grid over the rectangle's area, each cell's solid angle `cos θ_l dA / t²`.
    fn brute_rect(light: &AreaLight, x: DVec3, d: DVec3, s: f64) -> f64 {
        let AreaLight::Rect {
            center,
            normal,
            across,
            up,
            half_mm,
            ..
        } = *light
        else {
            unreachable!()
        };
        let (e1, e2) = d.any_orthonormal_pair();
        let n = 1000;
        let (da, db) = (2.0 * half_mm[0] / n as f64, 2.0 * half_mm[1] / n as f64);
        let mut sum = 0.0;
        for i in 0..n {
            for j in 0..n {
                let a = -half_mm[0] + (i as f64 + 0.5) * da;
                let b = -half_mm[1] + (j as f64 + 0.5) * db;
                let p = center + across * a + up * b - x;
                let t = p.length();
                let w = p / t;
                let cos_l = -w.dot(normal);
                if cos_l > 0.0 {
                    sum += lobe_density(w, d, e1, e2, s) * cos_l * da * db / (t * t);
                }
            }
        }
        sum
    }

    #[test]
    fn a_lobe_against_a_rectangle_matches_brute_force_quadrature() {
        let x = Vec3::new(0.5, -0.3, 1.0);
        let sigma = 1.5f32.to_radians();
        // From much smaller to much larger than the lobe (at 100 mm, a lobe of 1.5° is
        // about 2.6 mm across per σ), the lobe's centre on the light, at its edge and at
        // a corner, and a light turned about its axis.
        let center = Vec3::new(20.0, 10.0, 100.0);
        for size in [0.5f32, 3.0, 10.0, 40.0, 300.0] {
            for up in [Vec3::Y, Vec3::new(0.4, 1.0, 0.1)] {
                let light = AreaLight::rect(center, [size, 0.6 * size], up, 1.0);
                let AreaLight::Rect {
                    across,
                    up: up_axis,
                    half_mm,
                    ..
                } = light
                else {
                    unreachable!()
                };
                let c = center.as_dvec3();
                for target in [
                    c,
                    c + across * half_mm[0],
                    c + across * half_mm[0] + up_axis * half_mm[1],
                    c + across * (half_mm[0] + 2.0),
                ] {
                    let d = (target - x.as_dvec3()).normalize();
                    let got = f64::from(light.lobe_share(x, d.as_vec3(), sigma));
                    let want = brute_rect(&light, x.as_dvec3(), d, f64::from(sigma));
                    assert!(
                        (got - want).abs() <= 0.005 * want.max(1e-3),
                        "size {size}, up {up}, target {target}: {got} against {want}"
                    );
                }
            }
        }
    }

    #[test]
    fn a_lobe_against_a_ball_matches_brute_force_quadrature() {
        let x = Vec3::new(0.2, 0.1, 0.9);
        let sigma = 1.2f32.to_radians();
        let center = Vec3::new(-30.0, 40.0, 120.0);
        for radius in [0.3f32, 2.0, 6.0, 30.0] {
            let light = AreaLight::sphere(center, radius, 1.0);
            let to = (center - x).as_dvec3();
            let axis = to.normalize();
            let alpha = (f64::from(radius) / to.length()).asin();
            let side = axis.any_orthonormal_vector();
            for off in [0.0, 0.7 * alpha, alpha, alpha + 0.03] {
                let d = (axis * off.cos() + side * off.sin()).normalize();
                let got = f64::from(light.lobe_share(x, d.as_vec3(), sigma));
                // Brute force over the cap: a polar grid about its axis, the lobe's density
                // at each cell times the cell's solid angle.
                let s = f64::from(sigma);
                let (e1, e2) = d.any_orthonormal_pair();
                let (a1, a2) = axis.any_orthonormal_pair();
                let (nr, nphi) = (800, 1600);
                let mut want = 0.0;
                for i in 0..nr {
                    let theta = (i as f64 + 0.5) / nr as f64 * alpha;
                    for j in 0..nphi {
                        let phi = (j as f64 + 0.5) / nphi as f64 * 2.0 * std::f64::consts::PI;
                        let w =
                            axis * theta.cos() + (a1 * phi.cos() + a2 * phi.sin()) * theta.sin();
                        let cell = theta.sin()
                            * (alpha / nr as f64)
                            * (2.0 * std::f64::consts::PI / nphi as f64);
                        want += lobe_density(w, d, e1, e2, s) * cell;
                    }
                }
                assert!(
                    (got - want).abs() <= 0.005 * want.max(1e-3),
                    "radius {radius}, offset {off}: {got} against {want}"
                );
            }
        }
    }

    #[test]
    fn far_lobes_see_nothing_and_a_lobe_inside_a_large_light_sees_all() {
        let light = AreaLight::rect(Vec3::new(0.0, 0.0, 50.0), [400.0, 400.0], Vec3::Y, 1.0);
        let s = 1.0f32.to_radians();
        assert!((light.lobe_share(Vec3::ZERO, Vec3::Z, s) - 1.0).abs() < 1e-4);
        assert_eq!(light.lobe_share(Vec3::ZERO, -Vec3::Z, s), 0.0);
        let ball = AreaLight::sphere(Vec3::new(0.0, 0.0, 50.0), 1.0, 1.0);
        assert_eq!(ball.lobe_share(Vec3::ZERO, Vec3::X, s), 0.0);
    }
}

//! The environment seen through a narrow Gaussian lobe of directions: its value convolved with
//! `exp(−α²/2σ²)` over the angle α to a direction, for the lobe integrator
//! ([`crate::lobe`]), which reads one filtered value per Bragg lobe instead of sampling it.
//!
//! - **Built-in environments** are regions of constant value with sharp edges (a softbox's
//!   circle, strips and windows bounded by azimuth and elevation, the horizon). A lobe much
//!   narrower than a region sees each edge as straight: its share beyond the edge is
//!   `Φ(−s/σ)`, s the signed angular distance to the edge and Φ the normal distribution. The
//!   filtered value is the regions' values weighted by those soft memberships (exact for a
//!   straight edge; within the lobe's curvature of a corner elsewhere).
//! - **Maps** are read from a mip chain (each level the 2 × 2 means of the one below,
//!   Williams 1983), bilinear within a level and linear between the two levels whose texel
//!   (π / rows) brackets 2σ: a box filter of about the lobe's width, not its Gaussian, and
//!   stretched in azimuth near the poles as the equirectangular texels are.

use std::f32::consts::PI as PI_F32;

use glam::Vec3;

use super::{
    square_of, Environment, LuminanceMap, SOFTBOX_AXIS, SOFTBOX_RADIUS_DEG, TENT_PORT_RADIUS_DEG,
};
use crate::scene::EnvironmentKind;

/// Below this lobe width (radians) the filtered value is the plain one.
const SHARP_RAD: f32 = 1e-5;

impl Environment {
    /// The value seen along `dir` (unit, the stone's frame) through a Gaussian lobe of
    /// directions of standard deviation `sigma_rad` (radians, per axis) about it.
    pub fn filtered(&self, dir: Vec3, sigma_rad: f32) -> f32 {
        if sigma_rad <= SHARP_RAD {
            return self.value(dir);
        }
        let d = (self.to_env * dir.as_dvec3()).as_vec3();
        if self.map.is_some() {
            return self.read_mips(d, sigma_rad) * self.intensity;
        }
        self.built_in_filtered(d, dir, sigma_rad)
    }

    /// A built-in environment along `d` (its frame) through the lobe: the module's soft edges.
    fn built_in_filtered(&self, d: Vec3, dir: Vec3, sigma: f32) -> f32 {
        let elevation = d.z.clamp(-1.0, 1.0).asin();
        let azimuth = d.y.atan2(d.x);
        // Share of the lobe above the horizon.
        let up = soft(elevation, sigma);
        let deg = |v: f32| v.to_radians();
        let v = match self.kind {
            EnvironmentKind::None | EnvironmentKind::File => {
                let below = soft(-dir.z.clamp(-1.0, 1.0).asin(), sigma);
                return below * self.background;
            }
            EnvironmentKind::Studio => {
                let softbox = soft_cap(
                    d.dot(SOFTBOX_AXIS.normalize()).clamp(-1.0, 1.0).acos(),
                    deg(SOFTBOX_RADIUS_DEG),
                    sigma,
                );
                let cos_elevation = elevation.cos();
                let left = band(azimuth, 0.0, deg(30.0), (elevation, cos_elevation), sigma);
                let right = band(
                    azimuth,
                    PI_F32,
                    deg(30.0),
                    (elevation, cos_elevation),
                    sigma,
                );
                let room = (1.0 - softbox - left - right).max(0.0);
                let above = softbox + 0.8 * left + 0.5 * right + 0.004 * room;
                up * above + (1.0 - up) * 0.0004
            }
            EnvironmentKind::Window => {
                let h = elevation;
                let az = soft(
                    deg(25.0) - wrap(azimuth - deg(115.0)).abs(),
                    sigma / h.cos().max(0.05),
                );
                let window = az * soft(h - deg(20.0), sigma) * soft(deg(60.0) - h, sigma);
                up * (window + 0.04 * (1.0 - window)) + (1.0 - up) * 0.02
            }
            EnvironmentKind::Uniform => 1.0,
            EnvironmentKind::Tent => {
                let port = soft_cap(deg(90.0) - elevation, deg(TENT_PORT_RADIUS_DEG), sigma);
                let hem = soft(deg(10.0) - elevation, sigma);
                let dome = (1.0 - port - hem).max(0.0);
                up * (0.004 * port + 0.3 * hem + dome) + (1.0 - up) * 0.0004
            }
            EnvironmentKind::Overcast => up * (1.0 + 2.0 * d.z.max(0.0)) / 3.0 + (1.0 - up) * 0.1,
        };
        v * self.intensity
    }

    /// A map's mip chain read along `d` (its frame) at the level of the lobe's width.
    fn read_mips(&self, d: Vec3, sigma: f32) -> f32 {
        let levels = &self.mips;
        let Some(base) = self.map.as_deref() else {
            return 0.0;
        };
        let texel = PI_F32 / base.height as f32;
        let level = (2.0 * sigma / texel).max(1.0).log2();
        let [u, v] = square_of(d.as_dvec3());
        let (u, v) = (u as f32, v as f32);
        let at = |k: usize| {
            if k == 0 {
                bilinear(base, u, v)
            } else {
                levels
                    .get(k - 1)
                    .or(levels.last())
                    .map_or_else(|| bilinear(base, u, v), |m| bilinear(m, u, v))
            }
        };
        let k = level.floor() as usize;
        let f = level - k as f32;
        at(k) * (1.0 - f) + at(k + 1) * f
    }
}

/// `Φ(s/σ)`: the share of a Gaussian lobe of width `sigma` on the inner side of a straight
/// edge at signed angular distance `s` (positive: the lobe's centre inside).
pub(crate) fn soft(s: f32, sigma: f32) -> f32 {
    let x = f64::from(s / (sigma * std::f32::consts::SQRT_2));
    (0.5 * (1.0 + erf(x))) as f32
}

/// The share of a Gaussian lobe of width `sigma` inside a cap of angular radius `radius`
/// whose centre is `angle` from the lobe's: the straight edge's `Φ(s/σ)`, s = radius − angle,
/// less the edge's curvature term `(κσ/2) φ(s/σ)`, κ = cot(radius) the geodesic curvature
/// of the cap's rim (second order in the lobe's width; without it the softbox's edge is
/// off by 1 % of its value at σ = 1.5°).
pub(crate) fn soft_cap(angle: f32, radius: f32, sigma: f32) -> f32 {
    let x = (radius - angle) / sigma;
    let density = (-0.5 * x * x).exp() / (2.0 * std::f32::consts::PI).sqrt();
    let curvature = 1.0 / radius.tan();
    (soft(radius - angle, sigma) - 0.5 * curvature * sigma * density).clamp(0.0, 1.0)
}

/// Beyond this |x| the formula of [`erf`] rounds to ±1 exactly (`poly · e^{−x²}` under
/// 2.3·10⁻¹⁷, below half an ulp of 1; from 5.93 on, checked in the tests): most edges are many
/// lobe widths away, and the exponential is then left out.
const ERF_SATURATES: f64 = 6.0;

/// The error function, Abramowitz & Stegun 7.1.26 (absolute error under 1.5·10⁻⁷).
pub(crate) fn erf(x: f64) -> f64 {
    if x.abs() >= ERF_SATURATES {
        return if x >= 0.0 { 1.0 } else { -1.0 };
    }
    let t = 1.0 / (1.0 + 0.327_591_1 * x.abs());
    let poly = t
        * (0.254_829_592
            + t * (-0.284_496_736
                + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))));
    let y = 1.0 - poly * (-x * x).exp();
    if x >= 0.0 {
        y
    } else {
        -y
    }
}

/// An angle wrapped into (−π, π].
fn wrap(a: f32) -> f32 {
    let mut a = a;
    while a > PI_F32 {
        a -= 2.0 * PI_F32;
    }
    while a <= -PI_F32 {
        a += 2.0 * PI_F32;
    }
    a
}

/// The soft membership of a studio strip light: azimuth within `half_width` of `centre`,
/// elevation 10°–25° (as `strip` in [`super::built_in`]); distances in azimuth shrink by
/// cos elevation (`elevation` is the pair of the angle and its cosine).
fn band(
    azimuth: f32,
    centre: f32,
    half_width: f32,
    (elevation, cos_elevation): (f32, f32),
    sigma: f32,
) -> f32 {
    let across = (half_width - wrap(azimuth - centre).abs()) * cos_elevation;
    let (lo, hi) = (10f32.to_radians(), 25f32.to_radians());
    let inside = soft(across, sigma);
    if inside == 0.0 {
        // The lobe misses the strip in azimuth: the product is 0 whatever its elevation.
        return 0.0;
    }
    inside * soft(elevation - lo, sigma) * soft(hi - elevation, sigma)
}

/// `map` at `(u, v)` ∈ [0, 1)², bilinear between texel centres (wrapping in u, clamped in v).
fn bilinear(map: &LuminanceMap, u: f32, v: f32) -> f32 {
    let (w, h) = (map.width, map.height);
    let x = u * w as f32 - 0.5;
    let y = (v * h as f32 - 0.5).clamp(0.0, (h - 1) as f32);
    let x0 = x.floor();
    let fx = x - x0;
    let y0 = y.floor().min((h.saturating_sub(2)) as f32);
    let fy = (y - y0).min(1.0);
    let col = |c: f32| (c as i64).rem_euclid(w as i64) as usize;
    let (c0, c1) = (col(x0), col(x0 + 1.0));
    let (r0, r1) = (y0 as usize, (y0 as usize + 1).min(h - 1));
    let t = |r: usize, c: usize| map.luminance[r * w + c];
    let top = t(r0, c0) * (1.0 - fx) + t(r0, c1) * fx;
    let bottom = t(r1, c0) * (1.0 - fx) + t(r1, c1) * fx;
    top * (1.0 - fy) + bottom * fy
}

/// Each level the 2 × 2 means of the one before, down to one row.
pub(super) fn mip_chain(map: &LuminanceMap) -> Vec<LuminanceMap> {
    let mut levels: Vec<LuminanceMap> = Vec::new();
    loop {
        let prev = levels.last().unwrap_or(map);
        if prev.height < 2 || prev.width < 2 {
            break;
        }
        let (w, h) = (prev.width / 2, prev.height / 2);
        let mut luminance = Vec::with_capacity(w * h);
        for r in 0..h {
            for c in 0..w {
                let t = |rr: usize, cc: usize| prev.luminance[rr * prev.width + cc];
                let (r2, c2) = (2 * r, 2 * c);
                luminance
                    .push(0.25 * (t(r2, c2) + t(r2, c2 + 1) + t(r2 + 1, c2) + t(r2 + 1, c2 + 1)));
            }
        }
        levels.push(LuminanceMap {
            width: w,
            height: h,
            luminance,
        });
    }
    levels
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::EnvironmentConfig;

    fn studio() -> Environment {
        let config = EnvironmentConfig {
            kind: EnvironmentKind::Studio,
            ..EnvironmentConfig::default()
        };
        Environment::new(&config, 0.0).unwrap()
    }

    /// The Gaussian lobe's mean of `env.value` by brute-force quadrature over the plane tangent
    /// to `dir` (the lobe's small-angle form).
    fn brute_force(env: &Environment, dir: Vec3, sigma: f32) -> f64 {
        let (t, b) = dir.any_orthonormal_pair();
        let n = 161;
        let reach = 4.0 * sigma;
        let (mut sum, mut weights) = (0.0f64, 0.0f64);
        for i in 0..n {
            for j in 0..n {
                let x = -reach + 2.0 * reach * (i as f32 + 0.5) / n as f32;
                let y = -reach + 2.0 * reach * (j as f32 + 0.5) / n as f32;
                let w = f64::from((-(x * x + y * y) / (2.0 * sigma * sigma)).exp());
                sum += w * f64::from(env.value((dir + x * t + y * b).normalize()));
                weights += w;
            }
        }
        sum / weights
    }

    #[test]
    fn erf_matches_known_values() {
        // erf(0.5) = 0.520 499 878, erf(1) = 0.842 700 793, erf(2) = 0.995 322 265 (A & S table 7.1).
        for (x, e) in [
            (0.5, 0.520_499_878),
            (1.0, 0.842_700_793),
            (2.0, 0.995_322_265),
        ] {
            assert!((erf(x) - e).abs() < 2e-7, "{x}");
            assert!((erf(-x) + e).abs() < 2e-7, "{x}");
        }
    }

    #[test]
    fn erf_saturates_exactly_where_its_formula_rounds_to_one() {
        // The formula without the shortcut, term for term: from ERF_SATURATES on it is ±1
        // to the last bit, so the shortcut changes no value.
        let formula = |x: f64| {
            let t = 1.0 / (1.0 + 0.327_591_1 * x.abs());
            let poly = t
                * (0.254_829_592
                    + t * (-0.284_496_736
                        + t * (1.421_413_741 + t * (-1.453_152_027 + t * 1.061_405_429))));
            let y = 1.0 - poly * (-x * x).exp();
            if x >= 0.0 {
                y
            } else {
                -y
            }
        };
        for k in 0..200_000 {
            let x = ERF_SATURATES + f64::from(k) * 2e-4;
            assert_eq!(formula(x), 1.0, "{x}");
            assert_eq!(formula(-x), -1.0, "{x}");
            assert_eq!(erf(x), formula(x));
            assert_eq!(erf(-x), formula(-x));
        }
        for k in 0..60_000 {
            let x = f64::from(k) * 1e-4;
            assert_eq!(erf(x).to_bits(), formula(x).to_bits(), "{x}");
            assert_eq!(erf(-x).to_bits(), formula(-x).to_bits(), "{x}");
        }
        assert_eq!(erf(f64::INFINITY), 1.0);
        assert!(erf(f64::NAN).is_nan());
    }

    #[test]
    fn the_filtered_studio_is_the_lobe_mean_across_the_softbox_edge() {
        let env = studio();
        let axis = SOFTBOX_AXIS.normalize();
        let across = axis.cross(Vec3::X).normalize();
        let sigma = 1.5f32.to_radians();
        // Directions from inside the softbox, across its edge, to the room beyond.
        for k in -6..=6 {
            let angle = (SOFTBOX_RADIUS_DEG + k as f32 * 0.75).to_radians();
            let dir = (axis * angle.cos() + across * angle.sin()).normalize();
            let exact = brute_force(&env, dir, sigma);
            let filtered = f64::from(env.filtered(dir, sigma));
            assert!(
                (filtered - exact).abs() < 0.01,
                "{k}: {filtered} vs {exact}"
            );
        }
        // Far from an edge the filter changes nothing.
        assert!((env.filtered(axis, sigma) - 1.0).abs() < 1e-6);
    }

    #[test]
    fn a_filtered_map_keeps_a_uniform_value_and_blurs_an_edge() {
        let (w, h) = (64, 32);
        let luminance = (0..w * h)
            .map(|i| if i % w < w / 2 { 1.0 } else { 0.0 })
            .collect();
        let map = LuminanceMap {
            width: w,
            height: h,
            luminance,
        };
        let mips = mip_chain(&map);
        assert_eq!(mips.len(), 5);
        assert_eq!(mips[0].width, 32);
        // A uniform half keeps its value at every level; the mean over the map is kept.
        for level in &mips {
            let mean: f32 = level.luminance.iter().sum::<f32>() / level.luminance.len() as f32;
            assert!((mean - 0.5).abs() < 1e-6);
        }
        assert!((bilinear(&map, 0.25, 0.5) - 1.0).abs() < 1e-6);
        // At the edge the bilinear read is between.
        let edge = bilinear(&map, 0.5, 0.5);
        assert!(edge > 0.4 && edge < 0.6, "{edge}");
    }
}

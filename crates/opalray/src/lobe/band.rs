//! A reflected line as its domain's mosaic spreads it, and the share of its light that a
//! crossed line's notch takes on the way: the notch read over the reflection's spectrum, not
//! at its centre.
//!
//! A domain's normals spread as a Gaussian of `σ` per axis (the mosaic); a ray meeting the
//! family at `θ` is reflected, by the normals it meets, over a band of wavelengths: the line
//! moved by `λ tan θ δ` for a tilt `δ` in the plane of incidence and `−λ α²/2` on average for
//! any tilt `α` (as [`super::LineColours::in_lobe`] spreads its colour). The path tracer
//! draws that normal for a reflection, and lets a ray through a crossing with `1 − R` of the
//! line at the family's normal; so here the reflection's band is spread and the notch is
//! the line itself ([`Band::notch`]).
//!
//! Two narrow lines of nearly the same centre are the case that matters: plates of one
//! crystal stacked along the eye ray, each reflecting the same colour. Read at the deeper
//! line's centre, the nearer line's notch is its peak (`tanh² ν`, 0.95 for a 400-layer
//! plate), and the deeper plate's light is lost; spread over the deeper line's band, most
//! of it passes in the nearer notch's wings.
//!
//! Each line is taken as the Gaussian of its equivalent width `W` (`Σ ½ (λ/N) ν tanh ν` over
//! the two polarisations, [`super::colour::LineProfile`]'s) and its peak `P`: variance
//! `w₀² = (W / (P √(2π)))²`; a reflection's spread by the mosaic to `v = w₀² + (λ tan θ σ)²`
//! and centred at `λ (1 − σ²)`. The share of a band `a`'s light that a band `b` reflects is
//!
//! `∫ R_a R_b dλ / ∫ R_a dλ = P_b' √(v_b / (v_a + v_b)) exp(−(c_a − c_b)² / 2(v_a + v_b))`,
//!
//! `P_b' = W_b / √(2π v_b)` the band's peak. Against a quadrature over the lines' own
//! profiles, the reflection's spread by the mosaic, it is within 0.07 and a third of the
//! share, a tenth or less but for two lines both near the normal and 2 nm apart, and mostly
//! high (tested; read at the reflection's centre instead, off by up to 0.7; a box of the
//! stop band's width in place of either Gaussian was further off, up to 0.17).
//! Several notches multiply their passes, `Π (1 − share)`, as if each took from the band
//! independently.

use std::f64::consts::PI;

use super::colour::mosaic_spread_nm;
use crate::optics::BraggLine;

/// Bands further apart than this many standard deviations of their sum take nothing from
/// each other (`e^{−12.5}`).
const REACH_SIGMAS: f64 = 5.0;

/// A line as the mosaic spreads it: a Gaussian over wavelength.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct Band {
    /// Centre, nm.
    center_nm: f64,
    /// Variance, nm².
    variance: f64,
    /// Peak of the spread band (its equivalent width over `√(2π v)`), at most the line's.
    peak: f64,
}

impl Band {
    /// `line`, met at `cos_theta` (inside) by a domain of mosaic spread `sigma` (rad, per
    /// axis, the lobe's width over normals).
    pub(crate) fn of(line: &BraggLine, cos_theta: f64, sigma: f64) -> Band {
        Band::of_tanh(line, (line.nu_s.tanh(), line.nu_p.tanh()), cos_theta, sigma)
    }

    /// [`Band::of`], given `tanh` of the s and the p coupling: each polarisation's width
    /// `½ (λ/N) ν tanh ν`, its peak `tanh² ν`.
    pub(crate) fn of_tanh(line: &BraggLine, tanh: (f64, f64), cos_theta: f64, sigma: f64) -> Band {
        let scale = line.center_nm / line.layers.max(1.0);
        let (ts, tp) = tanh;
        let width = 0.5 * scale * (line.nu_s * ts + line.nu_p * tp);
        let peak = 0.5 * (ts * ts + tp * tp);
        if width <= 0.0 || peak <= 0.0 {
            return Band {
                center_nm: line.center_nm,
                variance: 1.0,
                peak: 0.0,
            };
        }
        let root = (2.0 * PI).sqrt();
        let w0 = width / (peak * root);
        let spread = mosaic_spread_nm(line.center_nm, cos_theta, sigma);
        let variance = w0 * w0 + spread * spread;
        Band {
            center_nm: line.center_nm * (1.0 - sigma * sigma),
            variance,
            peak: (width / (root * variance.sqrt())).min(peak),
        }
    }

    /// A crossed line's notch: the line at the family's normal, unspread (as the path
    /// tracer's ray goes through a crossing).
    pub(crate) fn notch(line: &BraggLine) -> Band {
        Band::of(line, 1.0, 0.0)
    }

    /// [`Band::notch`], given `tanh` of the s and the p coupling.
    pub(crate) fn notch_tanh(line: &BraggLine, tanh: (f64, f64)) -> Band {
        Band::of_tanh(line, tanh, 1.0, 0.0)
    }

    /// The share of this band's light that `notch` reflects (what it takes on the way).
    pub(crate) fn taken_by(&self, notch: &Band) -> f64 {
        let v = self.variance + notch.variance;
        let d = self.center_nm - notch.center_nm;
        if d * d >= REACH_SIGMAS * REACH_SIGMAS * v {
            return 0.0;
        }
        notch.peak * (notch.variance / v).sqrt() * (-0.5 * d * d / v).exp()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `∫ f` over `center ± 15` nm at 0.005 nm: a line's window and more.
    fn over_line(center: f64, f: impl Fn(f64) -> f64) -> f64 {
        let steps = (30.0 / 0.005) as usize;
        (0..steps)
            .map(|k| f(center - 15.0 + (k as f64 + 0.5) * 0.005))
            .sum::<f64>()
            * 0.005
    }

    /// `∫ R_a R_b / ∫ R_a` of the reflection `a` (met at `a.1`) spread by the mosaic (its
    /// centre moved by `λ tan θ σ x` for a standard normal `x`, and `−λ σ²`) and the notch `b`:
    /// the spread by the trapezoid rule over ±6 standard deviations (241 points), each
    /// tilt's product over the notch's window at 0.005 nm; `∫ R_a` is the line's own, the
    /// spread moving it but keeping its area (over `1 + σ²`).
    fn share_by_quadrature(a: (&BraggLine, f64), b: &BraggLine, sigma: f64) -> f64 {
        let spread = mosaic_spread_nm(a.0.center_nm, a.1, sigma);
        let stretch = 1.0 + sigma * sigma;
        let n = 241;
        let (mut num, mut norm) = (0.0, 0.0);
        for k in 0..n {
            let x = -6.0 + 12.0 * k as f64 / (n - 1) as f64;
            let w = (-0.5 * x * x).exp();
            num += w * over_line(b.center_nm, |l| {
                a.0.reflectance(l * stretch - spread * x) * b.reflectance(l)
            });
            norm += w;
        }
        let den = over_line(a.0.center_nm, |l| a.0.reflectance(l)) / stretch;
        num / norm / den
    }

    #[test]
    fn a_notch_read_over_the_band_agrees_with_quadrature_over_the_spread_reflection() {
        // The {111} coupling of the default silica opal (about 0.0036), plates of 120 to
        // 600 layers, the black opal's 1.5° mosaic and the crystal's 3°; reflections met
        // from near the normal to 37° (spread 0.6 to 20 nm), notches from the same centre to
        // 3 nm apart, and two lines both near the normal (the least spread, where the
        // Gaussian's shape matters most).
        let g = 0.0036;
        let cases = [
            (408.0, 0.973, 387.0, 0.998, 0.0),
            (408.0, 0.973, 387.0, 0.998, 1.5),
            (408.0, 0.973, 387.0, 0.998, 3.0),
            (236.0, 0.990, 400.0, 0.998, 0.0),
            (400.0, 0.999, 400.0, 0.998, 0.0),
            (400.0, 0.999, 400.0, 0.998, 2.0),
            (150.0, 0.950, 150.0, 0.990, 0.0),
            (600.0, 0.980, 600.0, 0.999, 0.5),
            (400.0, 0.800, 400.0, 0.998, 2.0),
            (300.0, 0.999, 120.0, 0.990, 0.0),
        ];
        for mosaic_deg in [1.5f64, 3.0] {
            let sigma = mosaic_deg.to_radians();
            for (na, ca, nb, cb, apart) in cases {
                let a = BraggLine::new(g, 505.0 / ca, ca, na);
                let b = BraggLine::new(g, (505.0 + apart) / cb, cb, nb);
                let exact = share_by_quadrature((&a, ca), &b, sigma);
                let band = Band::of(&a, ca, sigma).taken_by(&Band::notch(&b));
                assert!(
                    (band - exact).abs() < 0.07 && (band - exact).abs() < 0.4 * exact,
                    "{mosaic_deg}°, layers {na} / {nb}, cos {ca} / {cb}, {apart} nm apart: band \
                     {band:.3}, quadrature {exact:.3}"
                );
            }
        }
    }

    #[test]
    fn a_notch_at_the_deeper_line_s_centre_would_take_nearly_all_of_it() {
        // The defect the band mends: the nearer plate's peak, read at the deeper line's
        // centre, leaves 5 % where the reflection spread over its band keeps seven tenths.
        let sigma = 1.5f64.to_radians();
        let a = BraggLine::new(0.0036, 505.0 / 0.973, 0.973, 408.0);
        let b = BraggLine::new(0.0036, 505.0 / 0.998, 0.998, 387.0);
        let at_centre = 1.0 - b.reflectance(a.center_nm);
        let exact = 1.0 - share_by_quadrature((&a, 0.973), &b, sigma);
        let band = 1.0 - Band::of(&a, 0.973, sigma).taken_by(&Band::notch(&b));
        assert!(at_centre < 0.1, "{at_centre}");
        assert!(exact > 0.5 && band > 0.5, "quadrature {exact}, band {band}");
    }

    #[test]
    fn bands_far_apart_take_nothing() {
        let sigma = 1.5f64.to_radians();
        let a = Band::of(&BraggLine::new(0.0036, 520.0, 0.99, 400.0), 0.99, sigma);
        let b = Band::of(&BraggLine::new(0.0036, 600.0, 0.99, 400.0), 0.99, sigma);
        assert_eq!(a.taken_by(&b), 0.0);
        assert!(a.taken_by(&a) > 0.0 && a.taken_by(&a) < 1.0);
    }
}

//! Exact colorimetric integrals of spectra given as samples: the tristimulus values of a
//! measured spectrum (`opalray color`) and the white points of the illuminants.
//!
//! A sampled spectrum, the 1 nm CMF table and an illuminant table are each read as the
//! piecewise-linear function through their samples. Their product is a polynomial of degree
//! ≤ 3 between consecutive knots of the merged sampling, and Simpson's rule integrates such a
//! polynomial exactly, so the integrals below have no discretisation error at all.

use super::cmf::{cmf_samples, interpolate};
use super::illuminant::illuminant_samples;
use crate::scene::Illuminant;

/// Exact integral over all wavelengths of the product of piecewise-linear functions, each given
/// by samples `(x, y)` sorted by increasing x and taken as zero outside its samples.
pub(crate) fn integrate_product(factors: &[&[(f64, f64)]]) -> f64 {
    if factors.iter().any(|f| f.len() < 2) {
        return 0.0;
    }
    let lo = factors.iter().map(|f| f[0].0).fold(f64::MIN, f64::max);
    let hi = factors
        .iter()
        .map(|f| f[f.len() - 1].0)
        .fold(f64::MAX, f64::min);
    if hi <= lo {
        return 0.0;
    }
    // Every knot of every factor inside [lo, hi]; between two of them all factors are linear.
    let mut knots: Vec<f64> = factors
        .iter()
        .flat_map(|f| f.iter().map(|&(x, _)| x))
        .filter(|&x| x > lo && x < hi)
        .chain([lo, hi])
        .collect();
    knots.sort_by(f64::total_cmp);
    knots.dedup();
    let product = |x: f64| factors.iter().map(|f| interpolate(f, x)).product::<f64>();
    knots
        .windows(2)
        .map(|k| {
            let (a, b) = (k[0], k[1]);
            (b - a) / 6.0 * (product(a) + 4.0 * product(0.5 * (a + b)) + product(b))
        })
        .sum()
}

/// Tristimulus values `[X, Y, Z]` of an emission spectrum sampled at any wavelengths:
/// `X = ∫ S(λ) x̄(λ) dλ` etc., exactly, in the spectrum's units × nm.
pub fn emission_xyz(samples: &[(f64, f64)]) -> [f64; 3] {
    cmf_samples()
        .each_ref()
        .map(|cmf| integrate_product(&[samples, cmf]))
}

/// Tristimulus values `[X, Y, Z]` of a reflectance (or transmittance) sampled at any
/// wavelengths, lit by `illuminant`, exactly: `X = ∫ R S x̄ dλ / ∫ S ȳ dλ`, so a perfect
/// white reflector has Y = 1 (the luminance factor).
pub fn reflectance_xyz(samples: &[(f64, f64)], illuminant: Illuminant) -> [f64; 3] {
    let light = illuminant_samples(illuminant);
    let cmfs = cmf_samples();
    let norm = integrate_product(&[light, &cmfs[1]]);
    cmfs.each_ref()
        .map(|cmf| integrate_product(&[samples, light, cmf]) / norm)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn simpson_is_exact_for_products_of_lines() {
        // x (2 − x)(1 + x) = 2x + x² − x³, whose integral over [0, 2] is 4 + 8/3 − 4 = 8/3.
        let a = [(0.0, 0.0), (2.0, 2.0)];
        let b = [(0.0, 2.0), (2.0, 0.0)];
        let c = [(-1.0, 0.0), (5.0, 6.0)];
        let v = integrate_product(&[&a, &b, &c]);
        assert!((v - 8.0 / 3.0).abs() < 1e-12, "{v}");
    }

    #[test]
    fn integral_is_zero_without_overlap() {
        let a = [(0.0, 1.0), (1.0, 1.0)];
        let b = [(2.0, 1.0), (3.0, 1.0)];
        assert_eq!(integrate_product(&[&a, &b]), 0.0);
        assert_eq!(integrate_product(&[&a, &[(0.5, 1.0)]]), 0.0);
    }

    #[test]
    fn perfect_white_reflector_has_unit_luminance() {
        let white = [(300.0, 1.0), (900.0, 1.0)];
        for illuminant in [Illuminant::D65, Illuminant::A, Illuminant::C, Illuminant::E] {
            let y = reflectance_xyz(&white, illuminant)[1];
            assert!((y - 1.0).abs() < 1e-12, "{illuminant:?}: {y}");
        }
    }
}

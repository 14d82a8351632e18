//! Where the sphere size changes across a stone: a smooth random field of the relative
//! deviation of the sphere diameter, so that domains close together share their sphere size
//! (a patch of one colour spans the plates stacked through a colour bar) while distant parts
//! of the stone differ (blue at one end, red at the other).
//!
//! The field is a sum of `WAVES` cosines with random wave vectors and phases (the spectral
//! method of Shinozuka & Deodatis 1991): `z(p) = √(2/M) Σ cos(k_m · p + φ_m)`, `k_m` drawn
//! from a normal law of standard deviation `1/L` per axis, `φ_m` uniform. Its mean is 0, its
//! variance 1 and its covariance `E[z(p) z(p + r)] = E[cos(k · r)] = exp(−|r|² / (2 L²))`,
//! `L` the correlation length; with many waves it is close to Gaussian.

use glam::Vec3;

use super::grains::normal;
use crate::sampling::Rng;

/// Cosines in the sum.
const WAVES: usize = 64;

/// A smooth random field of mean 0, variance 1 and a correlation length set by [`SizeField::new`].
#[derive(Clone, Debug)]
pub struct SizeField {
    /// Wave vector (per mm) and phase of each cosine.
    waves: Vec<(Vec3, f32)>,
}

impl SizeField {
    /// A field of correlation length `length_mm` (> 0) drawn from `rng`.
    pub fn new(length_mm: f64, rng: &mut Rng) -> SizeField {
        let scale = (1.0 / length_mm) as f32;
        let waves = (0..WAVES)
            .map(|_| {
                let k = Vec3::new(normal(rng), normal(rng), normal(rng)) * scale;
                (k, (std::f64::consts::TAU * rng.uniform()) as f32)
            })
            .collect();
        SizeField { waves }
    }

    /// The field's value at `p` (mm): close to a standard normal number over the stone, at
    /// most `√(2 × 64) ≈ 11.3` in size.
    pub fn at(&self, p: Vec3) -> f32 {
        let sum: f32 = self
            .waves
            .iter()
            .map(|(k, phi)| (k.dot(p) + phi).cos())
            .sum();
        sum * (2.0 / WAVES as f32).sqrt()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::stage;

    #[test]
    fn the_fields_covariance_is_the_gaussian_of_its_length() {
        // Over many fields, E[z(p) z(p + r)] = exp(−r²/(2L²)) (the spectral method's
        // covariance, independent of the code) and E[z²] = 1.
        let length = 2.0;
        let fields = 400;
        let offsets = [0.0f32, 1.0, 2.0, 4.0];
        let mut sums = [0.0f64; 4];
        for f in 0..fields {
            let field = SizeField::new(length, &mut Rng::new(5, stage::STONE, f));
            let p = Vec3::new(0.3, -1.1, 0.4);
            let dir = Vec3::new(0.6, 0.8, 0.0);
            for (s, &r) in sums.iter_mut().zip(&offsets) {
                *s += f64::from(field.at(p) * field.at(p + dir * r));
            }
        }
        for (s, &r) in sums.iter().zip(&offsets) {
            let expected = (-(f64::from(r) / length).powi(2) / 2.0).exp();
            let measured = s / fields as f64;
            // The estimate's standard error is at most √(2/400) ≈ 0.07.
            assert!(
                (measured - expected).abs() < 0.21,
                "r = {r}: {measured} vs {expected}"
            );
        }
    }
}

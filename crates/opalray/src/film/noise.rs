//! The noise of a path-traced image, estimated from the image itself: input the even and odd
//! half sums of each pixel ([`super::FilmImage::half_difference`]) → output a [`Noise`].
//!
//! A pixel's `n` samples are independent and identically distributed, of variance σ². Split
//! them into the `n_a = ⌈n/2⌉` even and the `n_b = ⌊n/2⌋` odd samples, of means `a` and `b`:
//! the two are independent, so `Var(a − b) = σ²/n_a + σ²/n_b = σ² n / (n_a n_b)`, while the
//! pixel's mean `m` has `Var(m) = σ²/n`. Hence
//!
//! `Var(m) = Var(a − b) · n_a n_b / n²` (= `Var(a − b) / 4` for even `n`),
//!
//! and `E[(a − b)²] = Var(a − b)` as `a − b` has mean zero. One pixel's `(a − b)²` is a
//! one-degree-of-freedom estimate; its mean over the stone's pixels is a good one. The
//! *relative RMS noise* is `√(mean over the stone of (a − b)² n_a n_b / n²) / (mean over the
//! stone of m)`: the RMS standard error of the pixels' means over their mean value. It falls as
//! `1/√n`. The stone's pixels are those whose centre sees the stone.

use glam::{DVec3, Mat3};
use serde::Serialize;

/// The noise of a path-traced image over the stone's pixels.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Noise {
    /// Pixels the estimate is over (those whose centre sees the stone).
    pub pixels: usize,
    /// Relative RMS noise of the luminance Y (the RMS standard error over the mean, 0.01 =
    /// 1 %); `None` if the stone's mean luminance is 0.
    pub relative_rms: Option<f64>,
    /// The same for each linear RGB channel of the output's colour space.
    pub relative_rms_rgb: [Option<f64>; 3],
}

/// One pixel's mean and half difference `a − b` in one channel.
#[derive(Clone, Copy, Debug)]
pub struct PixelNoise {
    /// The pixel's mean.
    pub mean: f64,
    /// The mean of its even samples minus the mean of its odd ones.
    pub half_difference: f64,
}

/// The relative RMS noise of `pixels` after `n` ≥ 2 samples each (see the module's notes);
/// `None` with no pixels, fewer than two samples or a mean ≤ 0.
pub fn relative_rms(pixels: impl Iterator<Item = PixelNoise>, n: u32) -> Option<f64> {
    if n < 2 {
        return None;
    }
    let (n_a, n_b, n) = (f64::from(n.div_ceil(2)), f64::from(n / 2), f64::from(n));
    let (mut count, mut sum, mut sum_sq) = (0usize, 0.0f64, 0.0f64);
    for p in pixels {
        count += 1;
        sum += p.mean;
        sum_sq += p.half_difference * p.half_difference;
    }
    if count == 0 || sum <= 0.0 {
        return None;
    }
    let count = count as f64;
    let variance_of_mean = sum_sq / count * n_a * n_b / (n * n);
    Some(variance_of_mean.sqrt() / (sum / count))
}

/// The noise over the pixels `on_stone` of an image of pixel means `xyz` and half differences
/// `half_difference` after `spp` samples, as `path::PathImage::noise` gives it; `None` below two samples
/// per pixel or if the two images differ in size.
pub fn noise_of(
    xyz: &[[f32; 3]],
    half_difference: &[[f32; 3]],
    on_stone: &[bool],
    spp: u32,
    xyz_to_rgb: Mat3,
) -> Option<Noise> {
    if spp < 2 || half_difference.len() != xyz.len() {
        return None;
    }
    let m = xyz_to_rgb.as_dmat3();
    let stone = || {
        xyz.iter()
            .zip(half_difference)
            .zip(on_stone)
            .filter(|(_, &on)| on)
            .map(|((v, d), _)| {
                let v = DVec3::from_array(v.map(f64::from));
                let d = DVec3::from_array(d.map(f64::from));
                (v, d)
            })
    };
    let channel = |f: &dyn Fn(DVec3) -> f64| {
        relative_rms(
            stone().map(|(v, d)| PixelNoise {
                mean: f(v),
                half_difference: f(d),
            }),
            spp,
        )
    };
    Some(Noise {
        pixels: on_stone.iter().filter(|&&on| on).count(),
        relative_rms: channel(&|v| v.y),
        relative_rms_rgb: [0, 1, 2].map(|c| channel(&|v| (m * v)[c])),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn half_differences_estimate_the_standard_error_of_the_mean() {
        // Pixels of mean 2 and samples N(2, 0.5²) (Box–Muller): the standard error of a mean
        // of n = 16 is 0.5/4 = 0.125, relative 0.0625; 4000 pixels estimate it within ~2 %.
        let n = 16u32;
        let mut rng = Rng::new(9, 0, 0);
        let mut normal = || {
            let (u, v) = (1.0 - rng.uniform(), rng.uniform());
            (-2.0 * u.ln()).sqrt() * (std::f64::consts::TAU * v).cos()
        };
        let pixels: Vec<PixelNoise> = (0..4000)
            .map(|_| {
                let mut halves = [0.0; 2];
                for s in 0..n {
                    halves[(s % 2) as usize] += 2.0 + 0.5 * normal();
                }
                PixelNoise {
                    mean: (halves[0] + halves[1]) / f64::from(n),
                    half_difference: (halves[0] - halves[1]) / f64::from(n / 2),
                }
            })
            .collect();
        let got = relative_rms(pixels.iter().copied(), n).unwrap();
        assert!((got / 0.0625 - 1.0).abs() < 0.06, "{got}");
        assert_eq!(relative_rms(pixels.iter().copied(), 1), None);
        assert_eq!(relative_rms(std::iter::empty(), n), None);
    }
}

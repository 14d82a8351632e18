//! Denoising a sampled image: input a [`FilmImage`] (each pixel's mean, the
//! difference of its even and odd samples' means, the variance of its mean) → output a
//! [`Denoised`] XYZ image and an estimate of the noise left in it.
//!
//! Dual-buffer non-local means (Rousselle, Knaus & Zwicker 2012, §5): the even samples' image
//! `a` and the odd samples' image `b` are two independent renders of the same picture. `a` is
//! filtered with the weights that `b` gives ([`nl_means`]) and `b` with those of `a`, so that
//! a pixel's own noise never raises its weight; the result is their mean (weighted by their
//! samples). A pixel averages with the pixels of its window whose neighbourhoods look alike
//! beyond what their noise explains: within one patch of colour it averages widely, across
//! a patch's edge hardly at all. A firefly (one rare sample of large weight, in one half alone)
//! is first cut to a few times its surroundings (`FIREFLY_RATIO`): spread with its energy
//! kept, it would leave a soft spot.
//!
//! The filtered halves `a'`, `b'` still differ by what noise is left, so `a' − b'` estimates
//! it as the unfiltered halves' difference does ([`super::noise`]). That estimate does
//! not see the filter's bias (detail finer than the noise, averaged away); comparing with a
//! longer render does (`BENCHMARKS.md`).

pub mod nl_means;

use glam::Mat3;

pub use nl_means::NlMeans;

use super::noise::{noise_of, Noise};
use super::FilmImage;
use residual::{channel_sum, clamp_fireflies, return_residual, share_of, FIREFLY_RATIO};

mod residual;

impl Default for NlMeans {
    /// Window of radius 7 (a disc), patches 5 × 5, strength 0.55. The sizes: the least error
    /// against a 256-sample reference of the black opal at 4 and 16 samples per pixel among
    /// the settings tried (`BENCHMARKS.md`); the paper's 21 × 21 and 7 × 7 take 4 × the time.
    /// The disc, against the square of the same radius, is a third faster and leaves less
    /// error at 8 and 16 samples. The strength: with fireflies cut first, the least error at 8
    /// samples per pixel (the gem presets') among 0.45, 0.55, 0.7 and 0.85, on both the
    /// ragged and the straight-edged stone, and at 16 (0.7 was best before the cut, when
    /// fireflies had to be smoothed away); it keeps more of the fragments within a patch.
    fn default() -> Self {
        Self {
            window_radius: 7,
            patch_radius: 2,
            strength: 0.55,
        }
    }
}

/// A denoised image.
pub struct Denoised {
    /// CIE XYZ per pixel, row-major, on the scale of [`FilmImage::xyz`].
    pub xyz: Vec<[f32; 3]>,
    /// Per pixel, the filtered even samples' image minus the filtered odd samples'.
    pub half_difference: Vec<[f32; 3]>,
    /// Share of the image's X, Y and Z that the firefly cut took (returned about the
    /// fireflies with the filter's own residual, [`return_residual`]): e.g. 0.013 for 1.3 %.
    pub cut_share: [f64; 3],
    /// The filter's bias in the image's mean X, Y and Z: filtered over unfiltered, less 1
    /// (after [`return_residual`], zero to rounding).
    pub bias: [f64; 3],
}

/// Denoise `image` (`width × height`) with `params`; `None` below two samples per pixel (no
/// two halves to filter each other with).
pub fn denoise<'a>(
    image: impl Into<FilmImage<'a>>,
    width: usize,
    height: usize,
    params: &NlMeans,
) -> Option<Denoised> {
    let image = image.into();
    let n = image.spp;
    if n < 2 || image.half_difference.len() != width * height {
        return None;
    }
    // The halves and the variances of their pixels' means.
    let (n_a, n_b) = (n.div_ceil(2) as f32, (n / 2) as f32);
    let n = n as f32;
    let (mut a, mut b) = (Vec::with_capacity(width * height), Vec::new());
    b.reserve(width * height);
    for (m, d) in image.xyz.iter().zip(image.half_difference) {
        a.push(std::array::from_fn(|c| m[c] + n_b / n * d[c]));
        b.push(std::array::from_fn(|c| m[c] - n_a / n * d[c]));
    }
    let (raw_a, raw_b) = (a.clone(), b.clone());
    clamp_fireflies(&mut a, &mut b, width, height, FIREFLY_RATIO);
    // What the cut took, in the image's mean: returned after the filter.
    let cut: Vec<[f32; 3]> = (0..a.len())
        .map(|i| {
            std::array::from_fn(|c| {
                (n_a * (raw_a[i][c] - a[i][c]) + n_b * (raw_b[i][c] - b[i][c])) / n
            })
        })
        .collect();
    let scaled =
        |k: f32| -> Vec<[f32; 3]> { image.variance.iter().map(|v| v.map(|c| c * k)).collect() };
    let (var_a, var_b) = (scaled(n / n_a), scaled(n / n_b));
    // Each half filtered with the other's weights.
    let a_f = nl_means::filter(&a, &b, &var_b, width, height, params);
    let b_f = nl_means::filter(&b, &a, &var_a, width, height, params);
    let mut xyz: Vec<[f32; 3]> = a_f
        .iter()
        .zip(&b_f)
        .map(|(p, q)| std::array::from_fn(|c| (n_a * p[c] + n_b * q[c]) / n))
        .collect();
    let cut_share = share_of(&cut, image.xyz);
    return_residual(&mut xyz, image.xyz, width, height);
    let bias = std::array::from_fn(|c| {
        let (filtered, raw) = (channel_sum(&xyz, c), channel_sum(image.xyz, c));
        if raw > 0.0 {
            filtered / raw - 1.0
        } else {
            0.0
        }
    });
    let half_difference = a_f
        .iter()
        .zip(&b_f)
        .map(|(p, q)| std::array::from_fn(|c| p[c] - q[c]))
        .collect();
    Some(Denoised {
        xyz,
        half_difference,
        cut_share,
        bias,
    })
}

impl Denoised {
    /// The noise left over the stone's pixels (`on_stone`, after `spp` samples per pixel) as
    /// the filtered halves' difference estimates it, the RGB channels through `xyz_to_rgb`;
    /// blind to the filter's bias.
    pub fn noise(&self, on_stone: &[bool], spp: u32, xyz_to_rgb: Mat3) -> Option<Noise> {
        noise_of(&self.xyz, &self.half_difference, on_stone, spp, xyz_to_rgb)
    }
}

#[cfg(test)]
mod tests;

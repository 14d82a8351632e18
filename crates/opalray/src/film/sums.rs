//! The film's accumulation of a sampled render: input each camera sample's XYZ (and, through
//! the [`super::SpectralSampler`], its spectral bins) → output the developed image: each
//! pixel's mean, the difference of its even and odd samples' means (for the noise estimate,
//! [`super::noise`], and the denoiser, [`super::denoise`]) and the variance of its mean.
//!
//! Each pixel keeps the sums of its even and of its odd samples and of the squares of the
//! samples' XYZ. Sums are taken in the order of the sample index, whatever the passes, so the
//! developed image is the same bytes however the passes fall.

use crate::spectrum::{SpectralImage, WavelengthGrid};

use super::noise::{relative_rms, PixelNoise};

/// One pixel's sums over its samples.
#[derive(Clone, Copy, Default)]
pub(crate) struct PixelSums {
    /// XYZ summed over the even (`[0]`) and the odd (`[1]`) samples.
    halves: [[f64; 3]; 2],
    /// The squares of the samples' XYZ, summed.
    squares: [f64; 3],
}

impl PixelSums {
    /// Add sample `s`'s XYZ `xyz` to its half (even or odd) and to the squares.
    #[inline]
    pub(crate) fn add(&mut self, s: u32, xyz: &[f64; 3]) {
        let half = &mut self.halves[(s % 2) as usize];
        for c in 0..3 {
            half[c] += xyz[c];
            self.squares[c] += xyz[c] * xyz[c];
        }
    }

    fn mean(&self, n: u32) -> [f64; 3] {
        std::array::from_fn(|c| (self.halves[0][c] + self.halves[1][c]) / f64::from(n))
    }

    /// The mean of the even samples minus the mean of the odd ones (`n` ≥ 2).
    fn half_difference(&self, n: u32) -> [f64; 3] {
        let (n_even, n_odd) = (f64::from(n.div_ceil(2)), f64::from(n / 2));
        std::array::from_fn(|c| self.halves[0][c] / n_even - self.halves[1][c] / n_odd)
    }

    /// The variance of the pixel's mean, `s²/n` with `s²` the samples' variance (`n − 1` in
    /// the denominator); infinite with one sample.
    fn variance_of_mean(&self, n: u32) -> [f64; 3] {
        let mean = self.mean(n);
        let n = f64::from(n);
        std::array::from_fn(|c| {
            if n < 2.0 {
                return f64::INFINITY;
            }
            ((self.squares[c] - n * mean[c] * mean[c]) / (n - 1.0)).max(0.0) / n
        })
    }
}

/// A sampled render's film: every pixel's sums and the spectral image's bin sums.
pub(crate) struct Film {
    /// Per pixel, row-major, its sums.
    pub(crate) sums: Vec<PixelSums>,
    /// The spectral bins, summed over the samples until [`Film::develop`].
    pub(crate) spectral: SpectralImage,
}

/// A film developed after `spp` samples per pixel (see [`Film::develop`]).
pub(crate) struct Developed {
    /// CIE XYZ per pixel: the mean of its samples.
    pub(crate) xyz: Vec<[f32; 3]>,
    /// The spectral image (bin averages).
    pub(crate) spectral: SpectralImage,
    /// Per pixel, the XYZ mean of its even samples minus that of its odd ones; empty below
    /// two samples per pixel.
    pub(crate) half_difference: Vec<[f32; 3]>,
    /// Per pixel, the variance of its XYZ mean (infinite with one sample).
    pub(crate) variance: Vec<[f32; 3]>,
}

impl Film {
    /// An empty film of `width × height` pixels, its spectral image on `grid`.
    pub(crate) fn new(width: usize, height: usize, grid: WavelengthGrid) -> Self {
        Film {
            sums: vec![PixelSums::default(); width * height],
            spectral: SpectralImage::new(width, height, grid),
        }
    }

    /// The relative RMS noise of Y over the pixels `on_stone` after `n` samples
    /// ([`relative_rms`]); `None` below two.
    pub(crate) fn noise(&self, on_stone: &[bool], n: u32) -> Option<f64> {
        if n < 2 {
            return None;
        }
        let pixels = self
            .sums
            .iter()
            .zip(on_stone)
            .filter(|(_, &on)| on)
            .map(|(p, _)| PixelNoise {
                mean: p.mean(n)[1],
                half_difference: p.half_difference(n)[1],
            });
        relative_rms(pixels, n)
    }

    /// The means after `done` samples per pixel, their half differences and variances.
    pub(crate) fn develop(mut self, done: u32) -> Developed {
        let k = 1.0 / done as f32;
        for v in &mut self.spectral.data {
            *v *= k;
        }
        let to_f32 = |v: [f64; 3]| v.map(|c| c as f32);
        let sums = &self.sums;
        Developed {
            xyz: sums.iter().map(|p| to_f32(p.mean(done))).collect(),
            half_difference: if done >= 2 {
                sums.iter()
                    .map(|p| to_f32(p.half_difference(done)))
                    .collect()
            } else {
                Vec::new()
            },
            variance: sums
                .iter()
                .map(|p| to_f32(p.variance_of_mean(done)))
                .collect(),
            spectral: self.spectral,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn variance_of_mean_is_the_sample_variance_over_n() {
        // Samples 1, 2, 3, 6 (Y): mean 3, s² = (4 + 1 + 0 + 9)/3 = 14/3, s²/n = 7/6.
        let mut p = PixelSums::default();
        for (s, v) in [1.0, 2.0, 3.0, 6.0].into_iter().enumerate() {
            p.add(s as u32, &[0.0, v, 0.0]);
        }
        assert!((p.mean(4)[1] - 3.0).abs() < 1e-12);
        assert!((p.variance_of_mean(4)[1] - 7.0 / 6.0).abs() < 1e-12);
        // Even samples 1, 3 (mean 2), odd 2, 6 (mean 4).
        assert!((p.half_difference(4)[1] + 2.0).abs() < 1e-12);
        assert!(p.variance_of_mean(1)[1].is_infinite());
    }
}

//! The path integrator's samples: Owen-scrambled Sobol points (Burley 2020, "Practical
//! Hash-based Owen Scrambling", through `sobol_burley`), one sequence per pixel.
//!
//! Sample `s` of pixel `p` is point `s` of a scrambled and shuffled Sobol sequence seeded by
//! `(seed, PATH, p)`: its first two dimensions place the camera ray in the pixel, the next
//! ones each decision along the path in the order the path draws them. Dimensions come four
//! at a time, each set of four from a sequence of its own seed (Burley's padding, §4), so a
//! path draws as many as it needs: stratified within a set and over the pixel's samples,
//! independent between sets and between pixels (noise, not patterns). A sample is a pure
//! function of `(seed, pixel, s)`, so the image is the same at any thread count and any
//! order of passes. At most 2^16 samples per pixel (`integrator.spp` ≤ 65536).

use crate::sampling::{mix64, stage};

/// Most samples per pixel a sequence holds (`sobol_burley`'s length).
pub const MAX_SAMPLES: u32 = 1 << 16;

/// The draws of one sample of one pixel.
#[derive(Clone, Debug)]
pub struct PathSampler {
    /// Index of the sample in its pixel's sequence, `< MAX_SAMPLES`.
    sample: u32,
    /// The pixel's key, from the scene's seed and the pixel's index.
    key: u64,
    /// The next dimension to draw.
    dimension: u32,
}

impl PathSampler {
    /// Sample `sample` (< [`MAX_SAMPLES`]) of pixel `pixel` under `seed`.
    pub fn new(seed: u64, pixel: u64, sample: u32) -> Self {
        debug_assert!(sample < MAX_SAMPLES);
        PathSampler {
            sample,
            key: mix64(seed ^ mix64(stage::PATH.wrapping_mul(0xA076_1D64_78BD_642F) ^ pixel)),
            dimension: 0,
        }
    }

    /// The next dimension, uniform in [0, 1) (24 bits).
    pub fn uniform_f32(&mut self) -> f32 {
        let d = self.dimension;
        self.dimension = d.wrapping_add(1);
        // The seed of this set of four dimensions.
        let set = (mix64(self.key ^ u64::from(d / 4)) >> 32) as u32;
        sobol_burley::sample(self.sample, d % 4, set)
    }

    /// The next dimension, uniform in [0, 1), as `f64` (24 bits).
    pub fn uniform(&mut self) -> f64 {
        f64::from(self.uniform_f32())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The first two dimensions of 16 samples put one sample in each cell of a 4 × 4 grid
    /// (a (0, 4, 2)-net in base 2 stays one under Owen scrambling), for any pixel.
    #[test]
    fn sixteen_samples_stratify_the_pixel() {
        for pixel in [0, 1, 12_345] {
            let mut cells = [0u32; 16];
            for s in 0..16 {
                let mut sampler = PathSampler::new(7, pixel, s);
                let (x, y) = (sampler.uniform_f32(), sampler.uniform_f32());
                cells[(4.0 * y) as usize * 4 + (4.0 * x) as usize] += 1;
            }
            assert_eq!(cells, [1; 16], "pixel {pixel}");
        }
    }

    #[test]
    fn draws_are_uniform_and_pixels_independent() {
        // The mean of 4096 samples × 8 dimensions is 1/2 within a few standard errors
        // (σ = 1/√12 per value, 32 768 values: 0.0016).
        let mut sum = 0.0f64;
        for s in 0..4096 {
            let mut sampler = PathSampler::new(3, 99, s);
            for _ in 0..8 {
                let u = sampler.uniform();
                assert!((0.0..1.0).contains(&u));
                sum += u;
            }
        }
        assert!((sum / 32_768.0 - 0.5).abs() < 0.006, "{}", sum / 32_768.0);
        // Two pixels, or two seeds, draw different points.
        let first = |seed, pixel| PathSampler::new(seed, pixel, 0).uniform_f32();
        assert_ne!(first(0, 1), first(0, 2));
        assert_ne!(first(0, 1), first(1, 1));
    }
}

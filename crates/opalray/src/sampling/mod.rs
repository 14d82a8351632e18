//! Deterministic random numbers keyed by `(seed, stage, index)`.
//!
//! Every random decision in opalray draws from a stream named by the scene seed, the stage
//! that uses it and an index within the stage (a growth step, a light ray). Streams never
//! depend on threads or scheduling, so the same scene and seed give the same bytes at any
//! thread count. The generator is PCG-XSH-RR 64/32 (O'Neill 2014) seeded through SplitMix64.

pub mod distribution;

use glam::{Quat, Vec3};

/// Stage keys: each stage that draws random numbers has its own stream family.
pub mod stage {
    /// Cluster growth (structure).
    pub const STRUCTURE: u64 = 1;
    /// Light pass: one stream per light ray.
    pub const LIGHT: u64 = 2;
    /// View pass: one stream per pixel (sub-pixel jitter).
    pub const VIEW: u64 = 3;
    /// Light pass's roulette (`light.roulette`): one stream per lattice cell, apart from the
    /// rays' jitter, so that roulette leaves the rays where the cut traces them.
    pub const ROULETTE: u64 = 4;
    /// The stone model's domains: grains, their orientations and sphere sizes.
    pub const STONE: u64 = 5;
    /// Path integrator: one stream per pixel.
    pub const PATH: u64 = 6;
    /// The stored method's sub-pixel positions.
    pub const STORED: u64 = 7;
    /// The lobe integrator's sub-pixel positions.
    pub const LOBE: u64 = 8;
}

/// SplitMix64 finaliser: a bijective 64-bit mix (Steele, Lea, Flood 2014).
pub fn mix64(mut z: u64) -> u64 {
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// A small PCG32 stream. Cheap to create: make one per ray or per step.
#[derive(Clone, Debug)]
pub struct Rng {
    state: u64,
    inc: u64,
}

const PCG_MULT: u64 = 6_364_136_223_846_793_005;

impl Rng {
    /// The stream for `(seed, stage, index)`; see [`stage`] for stage keys.
    pub fn new(seed: u64, stage: u64, index: u64) -> Self {
        let key = mix64(seed ^ mix64(stage.wrapping_mul(0xA076_1D64_78BD_642F) ^ mix64(index)));
        let mut rng = Rng {
            state: 0,
            inc: (mix64(key ^ 0xE703_7ED1_A0B4_28DB) << 1) | 1,
        };
        rng.next_u32();
        rng.state = rng.state.wrapping_add(key);
        rng.next_u32();
        rng
    }

    /// Next 32 random bits.
    pub fn next_u32(&mut self) -> u32 {
        let old = self.state;
        self.state = old.wrapping_mul(PCG_MULT).wrapping_add(self.inc);
        let xorshifted = (((old >> 18) ^ old) >> 27) as u32;
        let rot = (old >> 59) as u32;
        xorshifted.rotate_right(rot)
    }

    /// Next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        (u64::from(self.next_u32()) << 32) | u64::from(self.next_u32())
    }

    /// Uniform in [0, 1) with 53 random bits.
    pub fn uniform(&mut self) -> f64 {
        (self.next_u64() >> 11) as f64 * (1.0 / (1u64 << 53) as f64)
    }

    /// Uniform in [0, 1) as `f32` (24 random bits).
    pub fn uniform_f32(&mut self) -> f32 {
        (self.next_u32() >> 8) as f32 * (1.0 / (1u32 << 24) as f32)
    }

    /// Uniform integer in `0..n` (Lemire's nearly-divisionless method); `n > 0`.
    pub fn below(&mut self, n: u64) -> u64 {
        debug_assert!(n > 0);
        let mut m = u128::from(self.next_u64()) * u128::from(n);
        if (m as u64) < n {
            let threshold = n.wrapping_neg() % n;
            while (m as u64) < threshold {
                m = u128::from(self.next_u64()) * u128::from(n);
            }
        }
        (m >> 64) as u64
    }

    /// Exponential variate with the given mean: density `exp(−x/mean)/mean`, x ≥ 0.
    pub fn exponential(&mut self, mean: f64) -> f64 {
        -mean * (1.0 - self.uniform()).ln()
    }

    /// Uniformly distributed unit vector on the sphere.
    pub fn unit_vector(&mut self) -> Vec3 {
        let z = 1.0 - 2.0 * self.uniform_f32();
        let r = (1.0 - z * z).max(0.0).sqrt();
        let phi = std::f32::consts::TAU * self.uniform_f32();
        Vec3::new(r * phi.cos(), r * phi.sin(), z)
    }

    /// Uniformly distributed rotation (Shoemake 1992, "Uniform random rotations").
    pub fn rotation(&mut self) -> Quat {
        let u1 = self.uniform();
        let u2 = std::f64::consts::TAU * self.uniform();
        let u3 = std::f64::consts::TAU * self.uniform();
        let a = (1.0 - u1).sqrt();
        let b = u1.sqrt();
        Quat::from_xyzw(
            (a * u2.sin()) as f32,
            (a * u2.cos()) as f32,
            (b * u3.sin()) as f32,
            (b * u3.cos()) as f32,
        )
        .normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn streams_are_reproducible_and_distinct() {
        let draw = |index| {
            let mut rng = Rng::new(7, 1, index);
            (0..8).map(|_| rng.next_u32()).collect::<Vec<_>>()
        };
        let (a, b, c) = (draw(3), draw(3), draw(4));
        assert_eq!(a, b);
        assert_ne!(a, c);
    }

    #[test]
    fn uniform_has_mean_one_half() {
        let mut rng = Rng::new(1, 2, 3);
        let n = 100_000;
        let mean = (0..n).map(|_| rng.uniform()).sum::<f64>() / n as f64;
        // Standard error of the mean of U(0,1) is 1/sqrt(12 n) ≈ 0.0009; allow 4 sigma.
        assert!((mean - 0.5).abs() < 0.004, "mean {mean}");
    }

    #[test]
    fn below_stays_in_range_and_covers_it() {
        let mut rng = Rng::new(3, 0, 0);
        let mut seen = [0u32; 7];
        for _ in 0..7000 {
            seen[rng.below(7) as usize] += 1;
        }
        assert!(seen.iter().all(|&c| (850..1150).contains(&c)), "{seen:?}");
    }

    #[test]
    fn unit_vectors_are_unit_and_centred() {
        let mut rng = Rng::new(5, 0, 0);
        let mut sum = Vec3::ZERO;
        for _ in 0..20_000 {
            let v = rng.unit_vector();
            assert!((v.length() - 1.0).abs() < 1e-5);
            sum += v;
        }
        // Each component has variance 1/3; 4 sigma of the mean is 4·sqrt(1/3/20000) ≈ 0.016.
        assert!((sum / 20_000.0).length() < 0.03);
    }
}

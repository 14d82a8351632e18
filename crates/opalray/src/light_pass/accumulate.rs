//! Order-independent accumulation of light deposits.
//!
//! Deposits are summed as 64-bit fixed-point integers, which are associative: whichever
//! thread traces a ray and in whatever order buffers are merged, the sums, and so the image
//! bytes, are identical at any thread count.

use glam::Vec3;

/// Fixed-point scale: 2⁻³² resolution, room for sums up to 2³¹ before overflow.
const SCALE: f32 = 4_294_967_296.0;

/// Round `x` (|x| < 2⁵¹) to the nearest integer by the floating-point magic-number trick,
/// which compiles to vector instructions where `as i64` does not.
#[inline(always)]
fn round_to_i64(x: f64) -> i64 {
    const MAGIC: f64 = 6_755_399_441_055_744.0; // 2⁵² + 2⁵¹
    (x + MAGIC).to_bits() as i64 - MAGIC.to_bits() as i64
}

/// Per-thread sums of the light crossing each stored cell: for every slot and lobe, the
/// fluence spectrum (`bins` values) and the power-weighted direction (3 values).
#[derive(Clone, Debug)]
pub struct Accumulator {
    stride: usize,
    bins: usize,
    sums: Vec<i64>,
}

impl Accumulator {
    /// Zeroed sums for `slots × lobes` entries of `bins` spectral values.
    pub fn new(slots: usize, lobes: usize, bins: usize) -> Self {
        let stride = bins + 3;
        Accumulator {
            stride,
            bins,
            sums: vec![0; slots * lobes * stride],
        }
    }

    /// Add `weight × spectrum` to entry `entry`, with its direction weighted by `power`.
    #[inline]
    pub fn deposit(
        &mut self,
        entry: usize,
        spectrum: &[f32],
        weight: f32,
        direction: Vec3,
        power: f32,
    ) {
        let base = entry * self.stride;
        let sums = &mut self.sums[base..base + self.stride];
        let k = f64::from(weight * SCALE);
        for (sum, &s) in sums[..self.bins].iter_mut().zip(spectrum) {
            *sum += round_to_i64(f64::from(s) * k);
        }
        let p = f64::from(power * weight * SCALE);
        for a in 0..3 {
            sums[self.bins + a] += round_to_i64(f64::from(direction[a]) * p);
        }
    }

    /// Add another thread's sums (integer addition: order does not matter).
    pub fn merge(mut self, other: Accumulator) -> Accumulator {
        for (a, b) in self.sums.iter_mut().zip(other.sums) {
            *a += b;
        }
        self
    }

    /// The fluence spectra (`entries × bins`) and unit mean directions (zero where nothing
    /// arrived), as floats.
    pub fn finish(self) -> (Vec<f32>, Vec<Vec3>) {
        let entries = self.sums.len() / self.stride;
        let mut fluence = Vec::with_capacity(entries * self.bins);
        let mut directions = Vec::with_capacity(entries);
        for chunk in self.sums.chunks_exact(self.stride) {
            fluence.extend(chunk[..self.bins].iter().map(|&v| v as f32 / SCALE));
            let d = Vec3::new(
                chunk[self.bins] as f32,
                chunk[self.bins + 1] as f32,
                chunk[self.bins + 2] as f32,
            );
            directions.push(d.normalize_or_zero());
        }
        (fluence, directions)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn merge_order_does_not_change_the_result() {
        let spectra = [[0.1f32, 0.7], [0.33, 1e-3], [5.0, 0.25]];
        let mut parts: Vec<Accumulator> = spectra
            .iter()
            .map(|s| {
                let mut a = Accumulator::new(1, 1, 2);
                a.deposit(0, s, 0.37, Vec3::X, 1.0);
                a
            })
            .collect();
        let forward = parts
            .clone()
            .into_iter()
            .reduce(Accumulator::merge)
            .unwrap();
        parts.reverse();
        let backward = parts.into_iter().reduce(Accumulator::merge).unwrap();
        assert_eq!(forward.finish(), backward.finish());
    }

    #[test]
    fn sums_are_accurate_to_the_fixed_point_resolution() {
        let mut a = Accumulator::new(2, 1, 1);
        for _ in 0..1000 {
            a.deposit(1, &[0.01], 0.5, Vec3::Z, 1.0);
        }
        let (f, d) = a.finish();
        assert_eq!(f[0], 0.0);
        assert!((f[1] - 5.0).abs() < 1e-5);
        assert_eq!(d[1], Vec3::Z);
        assert_eq!(d[0], Vec3::ZERO);
    }
}

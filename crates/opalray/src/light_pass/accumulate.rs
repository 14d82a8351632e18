//! Order-independent accumulation of light deposits, in two levels.
//!
//! A [`TileSums`] gathers the deposits of one tile of rays in `f32`, in the tile's fixed ray
//! order, in a small buffer that stays in cache. When the tile is done its sums are rounded
//! onto a fixed-point scale and added, as 64-bit integers, to the thread's [`Accumulator`].
//! Integer sums are associative: whichever thread traces a tile and in whatever order the
//! tiles are added, the result, and so the image bytes, are identical at any
//! thread count.

use glam::Vec3;
use rayon::prelude::*;

/// Fixed-point resolution: the largest possible single deposit maps to 2³¹.
const DEPOSIT_RANGE: f64 = 2_147_483_648.0;

/// Round `x` (|x| < 2⁵¹) to the nearest integer by the floating-point magic-number trick:
/// inline and vectorisable, where `f64::round` is a library call.
#[inline(always)]
fn round_to_i64(x: f64) -> i64 {
    const MAGIC: f64 = 6_755_399_441_055_744.0; // 2⁵² + 2⁵¹
    (x + MAGIC).to_bits() as i64 - MAGIC.to_bits() as i64
}

/// Sums of the light crossing each stored cell: for every entry (slot and lobe), the fluence
/// spectrum (`bins` values), the power-weighted direction (3 values) and the power weight.
#[derive(Clone, Debug)]
pub struct Accumulator {
    stride: usize,
    bins: usize,
    spectrum_scale: f64,
    direction_scale: f64,
    sums: Vec<i64>,
}

impl Accumulator {
    /// Zeroed sums for `entries` entries of `bins` spectral values. `max_spectral` and
    /// `max_power` bound one deposit's spectral value and direction weight; they set the
    /// fixed-point scales (a resolution of 5·10⁻¹⁰ of them).
    pub fn new(entries: usize, bins: usize, max_spectral: f32, max_power: f32) -> Self {
        let stride = bins + 4;
        Accumulator {
            stride,
            bins,
            spectrum_scale: DEPOSIT_RANGE / f64::from(max_spectral.max(f32::MIN_POSITIVE)),
            direction_scale: DEPOSIT_RANGE / f64::from(max_power.max(f32::MIN_POSITIVE)),
            sums: vec![0; entries * stride],
        }
    }

    /// Add a tile's sums, rounded onto the fixed-point scale.
    pub fn add_tile(&mut self, tile: &mut TileSums) {
        for (k, &entry) in tile.entries.iter().enumerate() {
            let local = &tile.sums[k * self.stride..(k + 1) * self.stride];
            let global =
                &mut self.sums[entry as usize * self.stride..(entry as usize + 1) * self.stride];
            for (g, &v) in global[..self.bins].iter_mut().zip(&local[..self.bins]) {
                *g += round_to_i64(f64::from(v) * self.spectrum_scale);
            }
            for (g, &v) in global[self.bins..].iter_mut().zip(&local[self.bins..]) {
                *g += round_to_i64(f64::from(v) * self.direction_scale);
            }
        }
        tile.clear();
    }

    /// Values per entry in [`Accumulator::into_sums`]: the spectrum, the power-weighted
    /// direction and the power weight.
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// The sums as floats, `entries × stride`: for each entry the fluence spectrum (`bins`
    /// values), Σ P·w (3) and Σ P (1).
    #[cfg(test)]
    pub fn into_sums(self) -> Vec<f32> {
        self.into_group_sums(1, 1, 0)
    }

    /// The sums as floats, with room left for other entries: the accumulator's entries, taken
    /// `per_group` at a time, are written into groups of `group` entries starting at entry
    /// `first` of each group; the other entries are zero. (The light pass accumulates the two
    /// scattered lobes of each cell and leaves the direct lobe, solved per cell, to be
    /// filled in.)
    pub fn into_group_sums(self, group: usize, per_group: usize, first: usize) -> Vec<f32> {
        assert!(
            first + per_group <= group,
            "the entries must fit in their group"
        );
        let scale: Vec<f64> = (0..self.stride)
            .map(|k| {
                if k < self.bins {
                    1.0 / self.spectrum_scale
                } else {
                    1.0 / self.direction_scale
                }
            })
            .collect();
        let stride = self.stride;
        let groups = self.sums.len() / (stride * per_group);
        let mut out = vec![0.0f32; groups * group * stride];
        out.par_chunks_mut(group * stride)
            .zip(self.sums.par_chunks(per_group * stride))
            .for_each(|(o, s)| {
                let o = &mut o[first * stride..(first + per_group) * stride];
                for (o, s) in o.chunks_exact_mut(stride).zip(s.chunks_exact(stride)) {
                    for ((o, &s), &k) in o.iter_mut().zip(s).zip(&scale) {
                        *o = (s as f64 * k) as f32;
                    }
                }
            });
        out
    }
}

/// The mean directions of float sums (`entries × (bins + 4)`, see
/// [`Accumulator::into_sums`]): per entry its unit mean direction (zero where nothing
/// arrived) and the mean resultant length of the directions (|Σ P·w| / Σ P: 1 for light from
/// one direction, towards 0 for light from many). The spectra stay where they are.
pub fn directions(sums: &[f32], bins: usize) -> (Vec<Vec3>, Vec<f32>) {
    let stride = bins + 4;
    let entries = sums.len() / stride;
    let mut directions = vec![Vec3::ZERO; entries];
    let mut concentration = vec![0.0f32; entries];
    directions
        .par_iter_mut()
        .zip(concentration.par_iter_mut())
        .zip(sums.par_chunks(stride))
        .for_each(|((dir, conc), chunk)| {
            let d = Vec3::new(chunk[bins], chunk[bins + 1], chunk[bins + 2]);
            let total = chunk[bins + 3];
            *conc = if total > 0.0 {
                (d.length() / total).min(1.0)
            } else {
                0.0
            };
            *dir = d.normalize_or_zero();
        });
    (directions, concentration)
}

/// The deposits of one tile of rays, in `f32`, for the entries the tile touches.
#[derive(Clone, Debug)]
pub struct TileSums {
    stride: usize,
    bins: usize,
    /// For each global entry, the tile generation that last touched it and, if that is
    /// this generation, its local index (one record: one memory access per deposit).
    stamp: Vec<(u32, u32)>,
    generation: u32,
    entries: Vec<u32>,
    sums: Vec<f32>,
}

impl TileSums {
    /// Empty tile sums for `entries` global entries of `bins` values.
    pub fn new(entries: usize, bins: usize) -> Self {
        TileSums {
            stride: bins + 4,
            bins,
            stamp: vec![(0, 0); entries],
            generation: 1,
            entries: Vec::new(),
            sums: Vec::new(),
        }
    }

    fn clear(&mut self) {
        self.entries.clear();
        self.sums.clear();
        self.generation = self.generation.wrapping_add(1).max(1);
        if self.generation == 1 {
            self.stamp.fill((0, 0));
        }
    }

    /// Add `weight × spectrum` to `entry`, and its direction weighted by `power`.
    #[inline(always)]
    pub fn deposit(
        &mut self,
        entry: usize,
        spectrum: &[f32],
        weight: f32,
        direction: Vec3,
        power: f32,
    ) {
        let (stamp, mut local) = self.stamp[entry];
        if stamp != self.generation {
            local = self.entries.len() as u32;
            self.stamp[entry] = (self.generation, local);
            self.entries.push(entry as u32);
            self.sums.resize(self.sums.len() + self.stride, 0.0);
        }
        let base = local as usize * self.stride;
        let sums = &mut self.sums[base..base + self.stride];
        let (spectral, rest) = sums.split_at_mut(self.bins);
        for (sum, &s) in spectral.iter_mut().zip(spectrum) {
            *sum += s * weight;
        }
        let tail: &mut [f32; 4] = (&mut rest[..4])
            .try_into()
            .expect("a direction and a power after the spectrum");
        tail[0] += direction.x * power;
        tail[1] += direction.y * power;
        tail[2] += direction.z * power;
        tail[3] += power;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tile_with(entry: usize, spectrum: &[f32]) -> TileSums {
        let mut t = TileSums::new(2, 2);
        t.deposit(entry, spectrum, 0.37, Vec3::X, 0.37);
        t
    }

    #[test]
    fn tile_order_does_not_change_the_result() {
        let spectra = [[0.1f32, 0.7], [0.33, 1e-3], [5.0, 0.25]];
        let sum_in = |order: &[usize]| {
            let mut a = Accumulator::new(2, 2, 5.0, 1.0);
            for &k in order {
                a.add_tile(&mut tile_with(1, &spectra[k]));
            }
            a.into_sums()
        };
        assert_eq!(sum_in(&[0, 1, 2]), sum_in(&[2, 0, 1]));
    }

    #[test]
    fn sums_are_accurate_to_the_fixed_point_resolution() {
        let mut a = Accumulator::new(2, 1, 0.01, 1.0);
        let mut tile = TileSums::new(2, 1);
        for i in 0..1000 {
            tile.deposit(1, &[0.01], 0.5, Vec3::Z, 0.5);
            if i % 100 == 99 {
                a.add_tile(&mut tile);
            }
        }
        let f = a.into_sums();
        let (d, c) = directions(&f, 1);
        assert!((c[1] - 1.0).abs() < 1e-6 && c[0] == 0.0);
        assert_eq!(f[0], 0.0);
        assert!((f[5] - 5.0).abs() < 1e-5, "{}", f[5]);
        assert_eq!(d[1], Vec3::Z);
        assert_eq!(d[0], Vec3::ZERO);
    }

    #[test]
    fn opposite_directions_have_no_concentration() {
        let mut a = Accumulator::new(1, 1, 1.0, 1.0);
        let mut tile = TileSums::new(1, 1);
        tile.deposit(0, &[1.0], 1.0, Vec3::X, 1.0);
        tile.deposit(0, &[1.0], 1.0, Vec3::new(0.0, 1.0, 0.0), 1.0);
        a.add_tile(&mut tile);
        let (d, c) = directions(&a.into_sums(), 1);
        // Two perpendicular unit vectors of equal weight: |Σ w| / Σ 1 = √2 / 2.
        assert!(
            (c[0] - std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-5,
            "{}",
            c[0]
        );
        assert!((d[0] - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-5);
    }

    #[test]
    fn rounding_is_to_nearest() {
        assert_eq!(round_to_i64(2.4), 2);
        assert_eq!(round_to_i64(2.6), 3);
        assert_eq!(round_to_i64(-2.6), -3);
        assert_eq!(round_to_i64(1e15 + 0.7), 1_000_000_000_000_001);
    }

    #[test]
    fn a_flushed_tile_starts_empty() {
        let mut a = Accumulator::new(2, 1, 1.0, 1.0);
        let mut tile = TileSums::new(2, 1);
        tile.deposit(0, &[1.0], 1.0, Vec3::X, 1.0);
        a.add_tile(&mut tile);
        a.add_tile(&mut tile);
        let f = a.into_sums();
        assert!((f[0] - 1.0).abs() < 1e-6);
    }
}

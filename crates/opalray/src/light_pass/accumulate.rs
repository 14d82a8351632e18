//! Order-independent accumulation of light deposits, in two levels.
//!
//! A [`TileSums`] gathers the deposits of one tile of rays in `f32`, in the tile's fixed ray
//! order, in a small buffer that stays in cache. When the tile is done its sums are rounded
//! onto a fixed-point scale and added, as 64-bit integers, to the thread's [`Accumulator`].
//! Integer sums are associative: whichever thread traces a tile and in whatever order the
//! threads' buffers are merged, the result, and so the image bytes, are identical at any
//! thread count.

use glam::Vec3;

/// Fixed-point resolution: the largest possible single deposit maps to 2³¹.
const DEPOSIT_RANGE: f64 = 2_147_483_648.0;

/// Per-thread sums of the light crossing each stored cell: for every slot and lobe, the
/// fluence spectrum (`bins` values) and the power-weighted direction (3 values).
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
        let stride = bins + 3;
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
                *g += (f64::from(v) * self.spectrum_scale).round() as i64;
            }
            for (g, &v) in global[self.bins..].iter_mut().zip(&local[self.bins..]) {
                *g += (f64::from(v) * self.direction_scale).round() as i64;
            }
        }
        tile.clear();
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
        let unscale = 1.0 / self.spectrum_scale;
        let mut fluence = Vec::with_capacity(entries * self.bins);
        let mut directions = Vec::with_capacity(entries);
        for chunk in self.sums.chunks_exact(self.stride) {
            fluence.extend(
                chunk[..self.bins]
                    .iter()
                    .map(|&v| (v as f64 * unscale) as f32),
            );
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

/// The deposits of one tile of rays, in `f32`, for the entries the tile touches.
#[derive(Clone, Debug)]
pub struct TileSums {
    stride: usize,
    bins: usize,
    /// For each global entry, the tile generation that last touched it.
    stamp: Vec<u32>,
    /// For each global entry touched in this generation, its local index.
    local: Vec<u32>,
    generation: u32,
    entries: Vec<u32>,
    sums: Vec<f32>,
}

impl TileSums {
    /// Empty tile sums for `entries` global entries of `bins` values.
    pub fn new(entries: usize, bins: usize) -> Self {
        TileSums {
            stride: bins + 3,
            bins,
            stamp: vec![0; entries],
            local: vec![0; entries],
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
            self.stamp.fill(0);
        }
    }

    /// Add `weight × spectrum` to `entry`, and its direction weighted by `weight × power`.
    #[inline]
    pub fn deposit(
        &mut self,
        entry: usize,
        spectrum: &[f32],
        weight: f32,
        direction: Vec3,
        power: f32,
    ) {
        if self.stamp[entry] != self.generation {
            self.stamp[entry] = self.generation;
            self.local[entry] = self.entries.len() as u32;
            self.entries.push(entry as u32);
            self.sums.resize(self.sums.len() + self.stride, 0.0);
        }
        let base = self.local[entry] as usize * self.stride;
        let sums = &mut self.sums[base..base + self.stride];
        for (sum, &s) in sums[..self.bins].iter_mut().zip(spectrum) {
            *sum += s * weight;
        }
        let p = power * weight;
        for a in 0..3 {
            sums[self.bins + a] += direction[a] * p;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tile_with(entry: usize, spectrum: &[f32]) -> TileSums {
        let mut t = TileSums::new(2, 2);
        t.deposit(entry, spectrum, 0.37, Vec3::X, 1.0);
        t
    }

    #[test]
    fn merge_order_does_not_change_the_result() {
        let spectra = [[0.1f32, 0.7], [0.33, 1e-3], [5.0, 0.25]];
        let mut parts: Vec<Accumulator> = spectra
            .iter()
            .map(|s| {
                let mut a = Accumulator::new(2, 2, 5.0, 1.0);
                a.add_tile(&mut tile_with(1, s));
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
        let mut a = Accumulator::new(2, 1, 0.01, 1.0);
        let mut tile = TileSums::new(2, 1);
        for i in 0..1000 {
            tile.deposit(1, &[0.01], 0.5, Vec3::Z, 1.0);
            if i % 100 == 99 {
                a.add_tile(&mut tile);
            }
        }
        let (f, d) = a.finish();
        assert_eq!(f[0], 0.0);
        assert!((f[1] - 5.0).abs() < 1e-5, "{}", f[1]);
        assert_eq!(d[1], Vec3::Z);
        assert_eq!(d[0], Vec3::ZERO);
    }

    #[test]
    fn a_flushed_tile_starts_empty() {
        let mut a = Accumulator::new(2, 1, 1.0, 1.0);
        let mut tile = TileSums::new(2, 1);
        tile.deposit(0, &[1.0], 1.0, Vec3::X, 1.0);
        a.add_tile(&mut tile);
        a.add_tile(&mut tile);
        let (f, _) = a.finish();
        assert!((f[0] - 1.0).abs() < 1e-6);
    }
}

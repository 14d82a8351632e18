//! Accumulation of light deposits that gives the same sums at any thread count, in two
//! levels.
//!
//! A [`TileSums`] gathers the deposits of one tile of rays in `f32`, in the tile's fixed ray
//! order, in a compact buffer of the entries the tile touched. Finished tiles are added to the
//! one [`OrderedSums`] in tile order, whichever thread traced them and whenever it finished: a
//! tile that finishes before an earlier one waits, its sums kept, and is added by the thread
//! that adds the earlier one. Every sum is then formed by the same additions in the same order,
//! so the result, and the image bytes, are identical at any thread count.

use glam::Vec3;

/// Sums of the light crossing each stored cell, in their final layout: the accumulated entries
/// (slot and scattered lobe), taken `per_group` at a time, fill entries `first ..` of groups of
/// `group` entries, and the other entries of each group stay zero for the caller (the light
/// pass accumulates the two scattered lobes of each cell and solves the direct lobe per cell).
/// Each entry holds the fluence spectrum (`bins` values), the power-weighted direction (3
/// values) and the power weight.
#[derive(Debug)]
pub struct OrderedSums {
    stride: usize,
    group: usize,
    per_group: usize,
    first: usize,
    sums: Vec<f32>,
    /// The tile to be added next.
    next: u64,
    /// Finished tiles waiting for an earlier one.
    waiting: Vec<(u64, TileSums)>,
    /// Emptied tile sums, to be reused.
    spare: Vec<TileSums>,
}

impl OrderedSums {
    /// Zeroed sums for `entries` accumulated entries of `bins` spectral values, laid out in
    /// groups as described on the type.
    pub fn new(entries: usize, bins: usize, group: usize, per_group: usize, first: usize) -> Self {
        assert!(
            per_group > 0 && first + per_group <= group && entries % per_group == 0,
            "the entries must fill whole groups"
        );
        let stride = bins + 4;
        OrderedSums {
            stride,
            group,
            per_group,
            first,
            sums: crate::spectrum::zeroed(entries / per_group * group * stride),
            next: 0,
            waiting: Vec::new(),
            spare: Vec::new(),
        }
    }

    /// Hand in the sums of tile `index` (tiles are numbered from 0, each handed in once): they
    /// are added once every earlier tile has been, and so may be any waiting tiles after them.
    pub fn submit(&mut self, index: u64, tile: TileSums) {
        debug_assert!(index >= self.next, "tile {index} handed in twice");
        self.waiting.push((index, tile));
        while let Some(k) = self.waiting.iter().position(|(i, _)| *i == self.next) {
            let (_, mut tile) = self.waiting.swap_remove(k);
            self.add(&tile);
            tile.clear();
            self.spare.push(tile);
            self.next += 1;
        }
    }

    /// Emptied tile sums handed in earlier, if any, for the next tile.
    pub fn take_spare(&mut self) -> Option<TileSums> {
        self.spare.pop()
    }

    fn add(&mut self, tile: &TileSums) {
        let stride = self.stride;
        for (k, &entry) in tile.entries.iter().enumerate() {
            let entry = entry as usize;
            let at = (entry / self.per_group * self.group + self.first + entry % self.per_group)
                * stride;
            for (g, &v) in self.sums[at..at + stride]
                .iter_mut()
                .zip(&tile.sums[k * stride..(k + 1) * stride])
            {
                *g += v;
            }
        }
    }

    /// Values per entry: the spectrum, the power-weighted direction and the power weight.
    pub fn stride(&self) -> usize {
        self.stride
    }

    /// The sums, `entries × stride` in groups (see the type).
    pub fn into_sums(self) -> Vec<f32> {
        assert!(
            self.waiting.is_empty(),
            "every tile before a handed-in one must be handed in"
        );
        self.sums
    }
}

/// The mean direction of an entry's direction sums `[Σ P·w (3 values), Σ P]` (the first four
/// values of `sums`; see [`OrderedSums`]): its unit mean direction (zero where nothing
/// arrived) and the mean resultant length of the directions (|Σ P·w| / Σ P: 1 for light from
/// one direction, towards 0 for light from many).
#[inline(always)]
pub fn mean_direction(sums: &[f32]) -> (Vec3, f32) {
    let d = Vec3::new(sums[0], sums[1], sums[2]);
    let total = sums[3];
    let concentration = if total > 0.0 {
        (d.length() / total).min(1.0)
    } else {
        0.0
    };
    (d.normalize_or_zero(), concentration)
}

/// [`mean_direction`] of every entry of float sums (`entries × (bins + 4)`, see
/// [`OrderedSums::into_sums`]).
#[cfg(test)]
pub fn directions(sums: &[f32], bins: usize) -> (Vec<Vec3>, Vec<f32>) {
    sums.chunks_exact(bins + 4)
        .map(|chunk| mean_direction(&chunk[bins..]))
        .unzip()
}

/// The deposits of one tile of rays, in `f32`, for the entries the tile touches.
#[derive(Clone, Debug)]
pub struct TileSums {
    stride: usize,
    bins: usize,
    /// For each global entry, one more than its local index if this tile touched it, else 0
    /// (four bytes an entry: the array stays small enough for the core's cache).
    stamp: Vec<u32>,
    entries: Vec<u32>,
    sums: Vec<f32>,
}

impl TileSums {
    /// Empty tile sums for `entries` global entries of `bins` values.
    pub fn new(entries: usize, bins: usize) -> Self {
        TileSums {
            stride: bins + 4,
            bins,
            stamp: vec![0; entries],
            entries: Vec::new(),
            sums: Vec::new(),
        }
    }

    fn clear(&mut self) {
        // Only the entries touched were marked.
        for &entry in &self.entries {
            self.stamp[entry as usize] = 0;
        }
        self.entries.clear();
        self.sums.clear();
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
        let mut local = self.stamp[entry].wrapping_sub(1);
        if local == u32::MAX {
            local = self.entries.len() as u32;
            self.stamp[entry] = local + 1;
            self.entries.push(entry as u32);
            self.sums.resize(self.sums.len() + self.stride, 0.0);
        }
        let base = local as usize * self.stride;
        let sums = &mut self.sums[base..base + self.stride];
        let (spectral, rest) = sums.split_at_mut(self.bins);
        crate::spectrum::add_scaled(spectral, spectrum, weight);
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
        let mut t = TileSums::new(2, spectrum.len());
        t.deposit(entry, spectrum, 1.0, Vec3::X, 1.0);
        t
    }

    fn sums_of(mut sums: OrderedSums, tiles: &[(u64, TileSums)]) -> Vec<f32> {
        for (index, tile) in tiles {
            sums.submit(*index, tile.clone());
        }
        sums.into_sums()
    }

    #[test]
    fn tiles_are_added_in_tile_order_whatever_order_they_arrive_in() {
        // In f32, (10⁸ + 5) + 5 = 10⁸ + 16 but (5 + 5) + 10⁸ = 10⁸ + 8: adding in arrival
        // order would make the sum depend on which thread finished first.
        let tiles: Vec<(u64, TileSums)> = [1e8f32, 5.0, 5.0]
            .iter()
            .enumerate()
            .map(|(i, &v)| (i as u64, tile_with(1, &[v])))
            .collect();
        let in_order = sums_of(OrderedSums::new(2, 1, 1, 1, 0), &tiles);
        assert_eq!(in_order[5], 1e8 + 16.0);
        for order in [[2, 1, 0], [1, 2, 0], [2, 0, 1]] {
            let shuffled: Vec<(u64, TileSums)> = order.iter().map(|&k| tiles[k].clone()).collect();
            assert_eq!(
                sums_of(OrderedSums::new(2, 1, 1, 1, 0), &shuffled),
                in_order,
                "{order:?}"
            );
        }
    }

    #[test]
    fn a_tile_waits_for_the_ones_before_it() {
        let mut sums = OrderedSums::new(2, 1, 1, 1, 0);
        sums.submit(1, tile_with(0, &[2.0]));
        assert_eq!(sums.sums[0], 0.0, "tile 1 is not added before tile 0");
        assert!(sums.take_spare().is_none());
        sums.submit(0, tile_with(0, &[3.0]));
        assert_eq!(sums.sums[0], 5.0);
        let spare = sums
            .take_spare()
            .expect("both tiles were emptied for reuse");
        assert!(spare.entries.is_empty() && spare.sums.is_empty());
    }

    #[test]
    #[should_panic(expected = "every tile before")]
    fn a_missing_tile_is_an_error() {
        let mut sums = OrderedSums::new(2, 1, 1, 1, 0);
        sums.submit(1, tile_with(0, &[2.0]));
        sums.into_sums();
    }

    #[test]
    fn entries_fill_their_place_in_the_groups() {
        // Two accumulated entries per group of three, from entry 1: entry e of the sums goes
        // to entry 3 (e / 2) + 1 + e % 2.
        let mut sums = OrderedSums::new(4, 1, 3, 2, 1);
        let mut tile = TileSums::new(4, 1);
        for e in 0..4 {
            tile.deposit(e, &[10.0 + e as f32], 1.0, Vec3::Z, 1.0);
        }
        sums.submit(0, tile);
        let f = sums.into_sums();
        let spectra: Vec<f32> = f.chunks(5).map(|c| c[0]).collect();
        assert_eq!(spectra, [0.0, 10.0, 11.0, 0.0, 12.0, 13.0]);
        assert_eq!(&f[5..10], &[10.0, 0.0, 0.0, 1.0, 1.0]);
    }

    #[test]
    fn default_bins_sum_as_any_other_count() {
        // 40 bins (their own copy of the deposit's loop) give exactly the plain f32 sums, like
        // 3 bins.
        for bins in [crate::spectrum::DEFAULT_BINS, 3] {
            let value = |t: usize, i: usize| 0.1 + ((t * 97 + i * 13) as f32 * 0.37).sin();
            let mut sums = OrderedSums::new(2, bins, 1, 1, 0);
            for t in 0..3 {
                let mut tile = TileSums::new(2, bins);
                let spectrum: Vec<f32> = (0..bins).map(|i| value(t, i)).collect();
                tile.deposit(1, &spectrum, 0.7, Vec3::Y, 0.5);
                sums.submit(t as u64, tile);
            }
            let f = sums.into_sums();
            for i in 0..bins {
                let plain = (0..3).fold(0.0f32, |s, t| s + (0.0 + value(t, i) * 0.7));
                assert_eq!(f[bins + 4 + i].to_bits(), plain.to_bits(), "{bins}: {i}");
            }
        }
    }

    #[test]
    fn sums_add_up_the_deposits() {
        let mut sums = OrderedSums::new(2, 1, 1, 1, 0);
        let mut tile = sums.take_spare().unwrap_or_else(|| TileSums::new(2, 1));
        let mut index = 0;
        for i in 0..1000 {
            tile.deposit(1, &[0.01], 0.5, Vec3::Z, 0.5);
            if i % 100 == 99 {
                sums.submit(index, tile);
                index += 1;
                tile = sums.take_spare().expect("the tile was added at once");
            }
        }
        let f = sums.into_sums();
        let (d, c) = directions(&f, 1);
        assert!((c[1] - 1.0).abs() < 1e-6 && c[0] == 0.0);
        assert_eq!(f[0], 0.0);
        assert!((f[5] - 5.0).abs() < 1e-4, "{}", f[5]);
        assert_eq!(d[1], Vec3::Z);
        assert_eq!(d[0], Vec3::ZERO);
    }

    #[test]
    fn opposite_directions_have_no_concentration() {
        let mut sums = OrderedSums::new(1, 1, 1, 1, 0);
        let mut tile = TileSums::new(1, 1);
        tile.deposit(0, &[1.0], 1.0, Vec3::X, 1.0);
        tile.deposit(0, &[1.0], 1.0, Vec3::new(0.0, 1.0, 0.0), 1.0);
        sums.submit(0, tile);
        let (d, c) = directions(&sums.into_sums(), 1);
        // Two perpendicular unit vectors of equal weight: |Σ w| / Σ 1 = √2 / 2.
        assert!(
            (c[0] - std::f32::consts::FRAC_1_SQRT_2).abs() < 1e-5,
            "{}",
            c[0]
        );
        assert!((d[0] - Vec3::new(1.0, 1.0, 0.0).normalize()).length() < 1e-5);
    }
}

//! The light pass's work items: square tiles of the ray lattice, handed out heaviest first.
//! A lattice cell's work is known from the geometry alone: whether its ray meets the stone,
//! and whether its light is trapped by total internal reflection (then it is traced with
//! more, weaker rays).

use glam::Vec3;
use rayon::prelude::*;

use super::walk::Walker;
use super::TILE;
use crate::geometry::{refract, Ellipsoid, Ray};

impl Walker<'_> {
    /// Whether the ray through the centre of lattice cell `index` meets the stone.
    pub fn meets_stone(&self, index: u64) -> bool {
        let centre = self.lattice.ray_in(index, 0.5, 0.5);
        self.ellipsoid.intersect(&centre).is_some_and(|h| h.0 > 0.0)
    }

    /// Whether the light of lattice cell `index` is (likely to be) trapped: the ray through
    /// the cell's centre, refracted into the stone, meets the far surface beyond the critical
    /// angle; or it misses the stone by less than two cells of the lattice (the silhouette,
    /// where rays enter at grazing incidence). A near-rim ray trapped by total internal
    /// reflection crosses about three times as many cells as others and makes most of the
    /// light pass's noise: tracing these cells with more, weaker rays lowers the noise more
    /// per unit of work than more rays everywhere (`docs/model.md`). Which cells split is fixed
    /// by the geometry alone, not by the random jitter, so the estimate stays unbiased.
    pub fn is_trapped(&self, index: u64) -> bool {
        let centre = self.lattice.ray_in(index, 0.5, 0.5);
        let Some((t, _)) = self.ellipsoid.intersect(&centre).filter(|h| h.0 > 0.0) else {
            let margin = 2.0 * self.lattice.spacing();
            let halo = Ellipsoid::new(self.ellipsoid.semi_axes() + Vec3::splat(margin));
            return halo.intersect(&centre).is_some_and(|h| h.0 > 0.0);
        };
        let p = centre.at(t);
        let Some(d) = refract(centre.direction, self.ellipsoid.normal(p), 1.0, self.n_eff) else {
            return false;
        };
        let inner = Ray {
            origin: p,
            direction: d,
        };
        let Some((_, t_far)) = self.ellipsoid.intersect(&inner) else {
            return false;
        };
        let cos_out = d.dot(self.ellipsoid.normal(inner.at(t_far)));
        cos_out * cos_out < 1.0 - 1.0 / (self.n_eff * self.n_eff)
    }
}

/// Lattice cells per side of a tile between the samples that estimate its work.
const WORK_SAMPLE: u64 = 4;
/// A trapped lattice cell's work relative to an untrapped one's: 2 × 2 rays crossing about
/// three and a half times as many cells each (default render).
const TRAPPED_WORK: u32 = 14;

/// The tiles of the ray lattice, heaviest first (ties in tile order), from the work estimated
/// on every [`WORK_SAMPLE`]-th lattice cell: whether its ray meets the stone, and whether it is
/// trapped. The rim's tiles cost several times the others'; started last, one of them would
/// keep a core busy while the others wait at the end. The order is fixed by the geometry, so
/// the tiles' sums, added in this order, are the same at any thread count.
pub(super) fn heaviest_first(walker: &Walker, side: u64, tiles_per_row: u64) -> Vec<u64> {
    let mut work: Vec<(u32, u64)> = (0..tiles_per_row * tiles_per_row)
        .into_par_iter()
        .map(|tile| {
            let (x0, y0) = (tile % tiles_per_row * TILE, tile / tiles_per_row * TILE);
            let mut w = 0;
            for y in (y0..(y0 + TILE).min(side)).step_by(WORK_SAMPLE as usize) {
                for x in (x0..(x0 + TILE).min(side)).step_by(WORK_SAMPLE as usize) {
                    let index = y * side + x;
                    if walker.is_trapped(index) {
                        w += TRAPPED_WORK;
                    } else if walker.meets_stone(index) {
                        w += 1;
                    }
                }
            }
            (w, tile)
        })
        .collect();
    work.sort_by_key(|&(w, tile)| (std::cmp::Reverse(w), tile));
    work.into_iter().map(|(_, tile)| tile).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light_pass::{LightSetup, Termination, VoxelLayout};

    #[test]
    fn every_tile_is_traced_once_the_rim_first() {
        let (prepared, voxels) = VoxelLayout::of_default_scene([40, 30, 10]);
        let spectrum = prepared.light_spectrum();
        let (_, source) = prepared.placement(30.0);
        let setup = LightSetup {
            source,
            spectrum: &spectrum,
            rays: 65_536,
            seed: 1,
            body_albedo: 0.0,
            body_extinction_per_mm: 0.0,
            termination: Termination::DEFAULT,
        };
        let walker = Walker::new(&voxels, prepared.optics().unwrap(), &setup);
        let side = walker.lattice.side();
        let per_row = side.div_ceil(TILE);
        let order = heaviest_first(&walker, side, per_row);
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..per_row * per_row).collect::<Vec<_>>());
        // Trapped lattice cells in a tile, and whether any of its cells' rays meets the stone.
        let census = |tile: u64| {
            let (x0, y0) = (tile % per_row * TILE, tile / per_row * TILE);
            let (mut trapped, mut hits) = (0, 0);
            for y in y0..(y0 + TILE).min(side) {
                for x in x0..(x0 + TILE).min(side) {
                    let index = y * side + x;
                    trapped += u32::from(walker.is_trapped(index));
                    hits += u32::from(walker.meets_stone(index));
                }
            }
            (trapped, hits)
        };
        let first = census(order[0]);
        let last = census(*order.last().unwrap());
        assert!(first.0 > 100, "the first tile holds the rim: {first:?}");
        assert_eq!(last, (0, 0), "the last tile misses the stone");
    }
}

//! Density estimation of the stored light with a small kernel (as in photon mapping,
//! Jensen 2001 §7): the track-length tallies of neighbouring cells *of the same patch*
//! (both voids, or clusters with the same orientation) are blended with a separable
//! [1 2 1] / 4 kernel along x, y and z. Patch boundaries stay sharp; inside a patch, where the
//! light varies smoothly, the noise of a finite number of rays falls about threefold.
//!
//! The direct light, solved per cell without noise, is blended too. A cluster filters light
//! once per crossing, whatever the chord, so the paths to neighbouring cells may cross one
//! cell of a patch more or fewer and differ by a whole Bragg-line transmission; the kernel
//! anti-aliases that count (left out, the default image changes by 3.5 % RMS, in bands).
//!
//! Each pass blends in place, visiting the cells in storage order (x fastest, then y, then z):
//! the neighbour before a cell along the pass's axis has already been replaced, so its
//! original values are read from a copy kept for that (of the previous cell, of the previous
//! row of the plane, or of the previous plane). Every value is read once and written back
//! while still in the cache, and no second array of the whole field is needed. The x and y
//! passes share one sweep of each plane (a row along x, then the row before it along y), so
//! the field is swept twice, not three times.

use glam::Vec3;
use rayon::prelude::*;

use super::accumulate::mean_direction;
use super::voxel_layout::Site;
use super::{VoxelLayout, LOBES};
use crate::structure::Cell;

/// Normals closer than this (|cos|) count as the same orientation.
const SAME_PATCH_COS: f32 = 0.9995;

/// `out = (2 own + lower + upper) / (2 + neighbours)`, over the neighbours present. The
/// default grid's cells (three lobes of 40 bins and 4 direction sums each) take a copy with
/// the length known when compiling: straight runs of vector instructions (see
/// [`crate::spectrum::add_product`]), the same bits.
#[inline(always)]
fn blend(out: &mut [f32], own: &[f32], lower: Option<&[f32]>, upper: Option<&[f32]>) {
    const N: usize = LOBES * (crate::spectrum::DEFAULT_BINS + 4);
    if out.len() == N {
        let out: &mut [f32; N] = out.try_into().expect("N values");
        let own: &[f32; N] = own[..N].try_into().expect("N values");
        let lower = lower.map(|v| -> &[f32; N] { v[..N].try_into().expect("N values") });
        let upper = upper.map(|v| -> &[f32; N] { v[..N].try_into().expect("N values") });
        blend_values(out, own, lower, upper);
    } else {
        blend_values(out, own, lower, upper);
    }
}

/// [`blend`] over slices or arrays (whose length the compiler then knows).
#[inline(always)]
fn blend_values<T: AsRef<[f32]> + AsMut<[f32]> + ?Sized>(
    out: &mut T,
    own: &T,
    lower: Option<&T>,
    upper: Option<&T>,
) {
    let out = out.as_mut();
    let mut total = 2.0f32;
    out.iter_mut()
        .zip(own.as_ref())
        .for_each(|(d, s)| *d = 2.0 * s);
    for other in [lower, upper].into_iter().flatten() {
        total += 1.0;
        out.iter_mut()
            .zip(other.as_ref())
            .for_each(|(d, s)| *d += s);
    }
    let k = 1.0 / total;
    out.iter_mut().for_each(|d| *d *= k);
}

/// Smooth `fluence` (`slots × LOBES × width_per_lobe` values: per slot and lobe a spectrum and
/// its four direction sums, see [`mean_direction`]) in place, and return the mean direction and
/// mean resultant length of every slot and lobe of the smoothed sums, formed as the last pass
/// writes each cell (while its values are still in the cache: a pass of its own would read
/// the whole field again).
pub(crate) fn smooth_sums(
    fluence: &mut [f32],
    voxels: &VoxelLayout,
    width_per_lobe: usize,
) -> (Vec<Vec3>, Vec<f32>) {
    let grid = Grid::new(voxels, LOBES * width_per_lobe);
    grid.blend_xy(fluence);
    grid.blend_z(fluence, width_per_lobe)
}

/// The stored cells as the kernel walks them: the grid's size, each slot's cell, each cell's
/// site, the patches' normals, and where each plane's slots begin.
struct Grid<'a> {
    /// Cells along x, y, z.
    n: [usize; 3],
    /// Cells of a plane (`nx × ny`).
    plane: usize,
    /// Values per slot (every lobe's spectrum and direction sums).
    width: usize,
    /// Per slot, its cell.
    cell_of_slot: &'a [usize],
    /// Per cell, its kind, slot and patch.
    sites: &'a [Site],
    /// The (111) normal of each patch.
    patch_normals: &'a [Vec3],
    /// The first slot of each plane, and one past the last plane's.
    plane_start: Vec<usize>,
}

impl<'a> Grid<'a> {
    fn new(voxels: &'a VoxelLayout, width: usize) -> Self {
        let [nx, ny, nz] = voxels.grid.n;
        let mut grid = Grid {
            n: [nx, ny, nz],
            plane: nx * ny,
            width,
            cell_of_slot: &voxels.cell_of_slot,
            sites: &voxels.sites,
            patch_normals: &voxels.patch_normals,
            plane_start: Vec::new(),
        };
        grid.plane_start = (0..=nz).map(|z| grid.first_slot(z * grid.plane)).collect();
        grid
    }

    /// The first slot at or after `cell`: slots are numbered in cell order, so each plane's
    /// and each row's are consecutive.
    #[inline(always)]
    fn first_slot(&self, cell: usize) -> usize {
        self.cell_of_slot.partition_point(|&c| c < cell)
    }

    /// Whether two cells' light is blended: both voids, or clusters of one patch (or of two
    /// whose normals are that close). One 8-byte site per cell tells its kind and patch.
    #[inline(always)]
    fn same_patch(&self, a: Site, b: Site) -> bool {
        match (a.cell(), b.cell()) {
            (Cell::Void, Cell::Void) => true,
            (Cell::Cluster, Cell::Cluster) => {
                a.patch() == b.patch()
                    || self.patch_normals[a.patch() as usize]
                        .dot(self.patch_normals[b.patch() as usize])
                        .abs()
                        >= SAME_PATCH_COS
            }
            _ => false,
        }
    }

    /// The slot of the neighbour `cell ± step` along an axis (on which `cell` has coordinate
    /// `coord` of `n`), if it is stored and in the same patch.
    #[inline(always)]
    fn neighbour(
        &self,
        cell: usize,
        (coord, n, step): (usize, usize, usize),
        after: bool,
    ) -> Option<usize> {
        let other = if after {
            (coord + 1 < n).then(|| cell + step)
        } else {
            (coord > 0).then(|| cell - step)
        }?;
        let site = self.sites[other];
        (site.cell() != Cell::Outside && self.same_patch(self.sites[cell], site))
            .then(|| site.slot())
    }

    /// x, then y, within each plane, in one sweep: each row is blended along x, and then the
    /// row before it along y (whose neighbour after it is that row, blended along x already);
    /// the planes in parallel.
    fn blend_xy(&self, fluence: &mut [f32]) {
        let (nz, width) = (self.n[2], self.width);
        let mut planes = Vec::with_capacity(nz);
        let mut rest = fluence;
        for z in 0..nz {
            let slots = self.plane_start[z + 1] - self.plane_start[z];
            let (values, after) = rest.split_at_mut(slots * width);
            planes.push((z, self.plane_start[z], values));
            rest = after;
        }
        planes.into_par_iter().for_each(|(z, first, values)| {
            crate::simd::widest(
                #[inline(always)]
                || self.blend_plane(z, first, values),
            )
        });
    }

    /// [`Grid::blend_xy`] of plane `z`, whose slots from `first` hold `values`.
    #[inline(always)]
    fn blend_plane(&self, z: usize, first: usize, values: &mut [f32]) {
        let ([nx, ny, _], width) = (self.n, self.width);
        let mut out = vec![0.0f32; width];
        // Original values of the previous cell (x), and of the previous row by x (y).
        let mut previous = vec![0.0f32; width];
        let mut row = vec![0.0f32; nx * width];
        // Rows of slots: blend each along x, then the one before it along y.
        let mut before = first..first;
        for y in 0..=ny {
            let start = before.end;
            let end = if y < ny {
                self.first_slot(z * self.plane + (y + 1) * nx)
            } else {
                start
            };
            for (axis, range) in [(0, start..end), (1, before)] {
                for slot in range {
                    let k = slot - first;
                    let cell = self.cell_of_slot[slot];
                    let x = cell % nx;
                    let along = match axis {
                        0 => (x, nx, 1),
                        _ => (cell / nx % ny, ny, nx),
                    };
                    let kept = match axis {
                        0 => &mut previous[..],
                        _ => &mut row[x * width..(x + 1) * width],
                    };
                    let lower = self.neighbour(cell, along, false).map(|_| &*kept);
                    let upper = self
                        .neighbour(cell, along, true)
                        .map(|s| &values[(s - first) * width..][..width]);
                    let own = &values[k * width..][..width];
                    blend(&mut out, own, lower, upper);
                    kept.copy_from_slice(own);
                    values[k * width..][..width].copy_from_slice(&out);
                }
            }
            before = start..end;
        }
    }

    /// z: the planes in order, the rows of each in parallel, with the original values of the
    /// previous plane by row and x; each cell's directions are formed from its final values.
    fn blend_z(&self, fluence: &mut [f32], width_per_lobe: usize) -> (Vec<Vec3>, Vec<f32>) {
        let ([nx, ny, nz], width) = (self.n, self.width);
        let plane_start = &self.plane_start;
        let slots = self.cell_of_slot.len();
        let mut directions = vec![Vec3::ZERO; slots * LOBES];
        let mut concentration = vec![0.0f32; slots * LOBES];
        let mut below = vec![0.0f32; self.plane * width];
        for z in 0..nz {
            let (before, after) = fluence.split_at_mut(plane_start[z + 1] * width);
            let next: &[f32] = after;
            let mut rows = Vec::with_capacity(ny);
            let mut rest = &mut before[plane_start[z] * width..];
            let mut found = (
                &mut directions[plane_start[z] * LOBES..],
                &mut concentration[plane_start[z] * LOBES..],
            );
            let mut start = plane_start[z];
            for y in 0..ny {
                let end = self.first_slot(z * self.plane + (y + 1) * nx);
                let (values, after) = rest.split_at_mut((end - start) * width);
                let (dirs, dirs_after) = found.0.split_at_mut((end - start) * LOBES);
                let (concs, concs_after) = found.1.split_at_mut((end - start) * LOBES);
                rows.push((start, values, dirs, concs));
                rest = after;
                found = (dirs_after, concs_after);
                start = end;
            }
            let along = (z, nz, self.plane);
            rows.into_par_iter()
                .zip(below.par_chunks_mut(nx * width))
                .for_each(|((first, values, dirs, concs), below)| {
                    crate::simd::widest(
                        #[inline(always)]
                        || {
                            let mut out = vec![0.0f32; width];
                            for (k, slot) in (first..first + values.len() / width).enumerate() {
                                let cell = self.cell_of_slot[slot];
                                let kept = &mut below[cell % nx * width..][..width];
                                let lower = self.neighbour(cell, along, false).map(|_| &*kept);
                                let upper = self
                                    .neighbour(cell, along, true)
                                    .map(|s| &next[(s - plane_start[z + 1]) * width..][..width]);
                                let own = &values[k * width..][..width];
                                blend(&mut out, own, lower, upper);
                                kept.copy_from_slice(own);
                                values[k * width..][..width].copy_from_slice(&out);
                                for (lobe, sums) in out.chunks_exact(width_per_lobe).enumerate() {
                                    (dirs[k * LOBES + lobe], concs[k * LOBES + lobe]) =
                                        mean_direction(&sums[width_per_lobe - 4..]);
                                }
                            }
                        },
                    )
                });
        }
        (directions, concentration)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light_pass::NO_SLOT;

    /// The kernel as three plain passes, each from one whole array into another.
    fn three_passes(
        fluence: &[f32],
        cells: &[Cell],
        voxels: &VoxelLayout,
        width: usize,
    ) -> Vec<f32> {
        let n = voxels.grid.n;
        let stride = [1, n[0], n[0] * n[1]];
        let same_patch = |a: usize, b: usize| match (cells[a], cells[b]) {
            (Cell::Void, Cell::Void) => true,
            (Cell::Cluster, Cell::Cluster) => {
                voxels.normal(a).dot(voxels.normal(b)).abs() >= SAME_PATCH_COS
            }
            _ => false,
        };
        let mut src = fluence.to_vec();
        for axis in 0..3 {
            let mut out = vec![0.0; src.len()];
            for (slot, dst) in out.chunks_mut(width).enumerate() {
                let cell = voxels.cell_of_slot[slot];
                let coord = cell / stride[axis] % n[axis];
                let mut others = Vec::new();
                if coord > 0 {
                    others.push(cell - stride[axis]);
                }
                if coord + 1 < n[axis] {
                    others.push(cell + stride[axis]);
                }
                let others: Vec<&[f32]> = others
                    .into_iter()
                    .filter(|&o| voxels.slot_of_cell[o] != NO_SLOT && same_patch(cell, o))
                    .map(|o| &src[voxels.slot_of_cell[o] as usize * width..][..width])
                    .collect();
                // The kernel written out plainly: twice the cell, plus each neighbour, over
                // the weights' sum.
                let own = &src[slot * width..][..width];
                for (i, d) in dst.iter_mut().enumerate() {
                    *d = 2.0 * own[i];
                    for other in &others {
                        *d += other[i];
                    }
                    *d *= 1.0 / (2.0 + others.len() as f32);
                }
            }
            src = out;
        }
        src
    }

    #[test]
    fn in_place_passes_give_the_three_plain_passes_bits() {
        // An odd-sized grid, so that rows and planes hold different numbers of stored cells;
        // the default grid's 40 bins (their own copy of the blend) and another count.
        let (prepared, voxels) = VoxelLayout::of_default_scene([23, 17, 9]);
        let cells = &prepared.structure().unwrap().cells;
        for bins in [crate::spectrum::DEFAULT_BINS, 3] {
            check_against_plain_passes(cells, &voxels, bins + 4);
        }
    }

    fn check_against_plain_passes(cells: &[Cell], voxels: &VoxelLayout, width_per_lobe: usize) {
        let width = LOBES * width_per_lobe;
        // Values whose sums round differently in every order.
        let mut state = 0x9e37_79b9_7f4a_7c15u64;
        let fluence: Vec<f32> = (0..voxels.slots() * width)
            .map(|_| {
                state = state
                    .wrapping_mul(6_364_136_223_846_793_005)
                    .wrapping_add(1);
                (state >> 40) as f32 / (1u64 << 24) as f32 * 3.7 + 0.01
            })
            .collect();
        let expected = three_passes(&fluence, cells, voxels, width);
        let mut smoothed = fluence.clone();
        let (directions, concentration) = smooth_sums(&mut smoothed, voxels, width_per_lobe);
        assert_ne!(smoothed, fluence, "the kernel changed something");
        let bins = width_per_lobe - 4;
        assert_eq!(
            (directions, concentration),
            crate::light_pass::accumulate::directions(&smoothed, bins),
            "the directions are those of the smoothed sums"
        );
        assert!(smoothed
            .iter()
            .zip(&expected)
            .all(|(a, b)| a.to_bits() == b.to_bits()));
    }
}

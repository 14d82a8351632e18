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

use rayon::prelude::*;

use super::{StoneCells, LOBES, NO_SLOT};
use crate::structure::Cell;

/// Normals closer than this (|cos|) count as the same orientation.
const SAME_PATCH_COS: f32 = 0.9995;

/// Smooth `sums` (`slots × LOBES × width_per_lobe` values) in place.
pub(crate) fn smooth_sums(
    fluence: &mut Vec<f32>,
    cells: &[Cell],
    stone: &StoneCells,
    width_per_lobe: usize,
) {
    let grid = stone.grid.n;
    let (cell_of_slot, slot_of_cell, normals) =
        (&stone.cell_of_slot, &stone.slot_of_cell, &stone.normals);
    let same_patch = |a: usize, b: usize| match (cells[a], cells[b]) {
        (Cell::Void, Cell::Void) => true,
        (Cell::Cluster, Cell::Cluster) => normals[a].dot(normals[b]).abs() >= SAME_PATCH_COS,
        _ => false,
    };
    let stride = [1, grid[0], grid[0] * grid[1]];
    let width = LOBES * width_per_lobe;
    let mut out = crate::spectrum::zeroed(fluence.len());
    for axis in 0..3 {
        let src = &*fluence;
        out.par_chunks_mut(width)
            .enumerate()
            .for_each(|(slot, dst)| {
                let cell = cell_of_slot[slot];
                let coord = cell / stride[axis] % grid[axis];
                let mut total = 2.0f32;
                dst.iter_mut()
                    .zip(&src[slot * width..(slot + 1) * width])
                    .for_each(|(d, s)| *d = 2.0 * s);
                let neighbours = [
                    (coord > 0).then(|| cell - stride[axis]),
                    (coord + 1 < grid[axis]).then(|| cell + stride[axis]),
                ];
                for other in neighbours.into_iter().flatten() {
                    let other_slot = slot_of_cell[other];
                    if other_slot == NO_SLOT || !same_patch(cell, other) {
                        continue;
                    }
                    total += 1.0;
                    let o = other_slot as usize * width;
                    dst.iter_mut()
                        .zip(&src[o..o + width])
                        .for_each(|(d, s)| *d += s);
                }
                let k = 1.0 / total;
                dst.iter_mut().for_each(|d| *d *= k);
            });
        std::mem::swap(fluence, &mut out);
    }
}

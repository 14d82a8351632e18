//! Structure stage: the opal's macroscopic model of clusters and voids (paper §2.2, §2.4).
//!
//! Input: [`StructureConfig`](crate::scene::StructureConfig) → output: [`Structure`], a grid
//! of cells, each outside the stone, a void, or a cluster with a lattice orientation.
//!
//! The stone is an ellipsoid centred at the origin with semi-axes `a, b, c` (mm); its bounding
//! box `[−a, a] × [−b, b] × [−c, c]` is cut into `nx × ny × nz` cells, cell `(i, j, k)`
//! spanning `x ∈ [−a + i·dx, −a + (i+1)·dx]` (likewise y, z) with `dx = 2a/nx`. A cell whose
//! centre lies outside the ellipsoid is [`Cell::Outside`]. Growth (paper §2.4, eq. 1): pick
//! a random inside cell, draw a radius `r` from `P(r) ∝ exp(−r/R)`, make every inside cell
//! within `r` of it a cluster whose orientation is the average of the clusters already there
//! (a uniformly random one where there are none); repeat until the void ratio falls below
//! the target. Every choice is written out in `docs/model.md`, "Structure".
//!
//! - [`ball`]: the cells within `r` of a cell, row by row.
//! - [`orientation`]: sign- and symmetry-aligned quaternion averaging, jitter.
//! - [`growth`]: the growth loop, one deterministic random stream per step.
//! - [`map`]: the paper's fig. 9, a slice coloured by orientation.

pub mod ball;
pub mod growth;
pub mod map;
pub mod orientation;

pub use growth::{draw_step, grow_structure, Growth, StepDraw, StepReport};
pub use map::{orientation_map, OrientationMap};

use glam::{Quat, Vec3};
use serde::Serialize;

/// What one cell of the grid holds.
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cell {
    /// The cell's centre is outside the ellipsoid: not part of the stone.
    Outside = 0,
    /// Inside the stone, no ordered crystal (the paper's void; potch in gem terms).
    Void = 1,
    /// Inside the stone, an FCC cluster with its own orientation.
    Cluster = 2,
}

/// Counts describing a grown structure.
#[derive(Clone, Debug, Serialize)]
pub struct StructureStats {
    /// Cells whose centre is inside the ellipsoid (voids + clusters).
    pub inside_cells: usize,
    /// Cluster cells.
    pub clusters: usize,
    /// Void cells.
    pub voids: usize,
    /// `voids / inside_cells`, in [0, 1]; just below the configured target after growth.
    pub void_ratio: f64,
    /// Growth steps taken (cells selected as neighbourhood centres).
    pub seeds_placed: usize,
    /// Mean of the neighbourhood radii drawn, in cells (expected: `mean_radius_cells`).
    pub mean_radius_cells: f64,
}

/// A grown opal structure: the cell grid with one orientation per cell.
#[derive(Clone, Debug)]
pub struct Structure {
    /// Cells along x, y, z: `[nx, ny, nz]`.
    pub grid: [usize; 3],
    /// The ellipsoid's semi-axes `a, b, c` along x, y, z, mm.
    pub semi_axes_mm: [f64; 3],
    /// Every cell, at [`Structure::index`]`(x, y, z) = x + nx·(y + ny·z)`.
    pub cells: Vec<Cell>,
    /// Lattice orientation of every cell (unit quaternion, lattice frame → stone frame);
    /// `Quat::IDENTITY` for cells that are not clusters.
    pub orientations: Vec<Quat>,
    /// Counts of the growth.
    pub stats: StructureStats,
}

/// The (111) stacking axis in the lattice frame, unit: `(1, 1, 1)/√3`.
pub const AXIS_111: Vec3 = Vec3::splat(0.577_350_26);

impl Structure {
    /// Edge lengths of one cell along x, y, z in mm: `2·semi_axis / n`.
    pub fn cell_size_mm(&self) -> [f64; 3] {
        std::array::from_fn(|axis| 2.0 * self.semi_axes_mm[axis] / self.grid[axis] as f64)
    }

    /// Index of cell `(x, y, z)` in [`Structure::cells`]: `x + nx·(y + ny·z)`.
    pub fn index(&self, x: usize, y: usize, z: usize) -> usize {
        x + self.grid[0] * (y + self.grid[1] * z)
    }

    /// The (111) plane normal of cell `index` in the stone frame, unit:
    /// `q·(1, 1, 1)/√3`. For non-cluster cells (identity orientation) this is `(1, 1, 1)/√3`.
    /// `n` and `−n` describe the same planes.
    pub fn normal(&self, index: usize) -> Vec3 {
        (self.orientations[index] * AXIS_111).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn axis_111_is_unit_diagonal() {
        let expected = Vec3::ONE / 3f32.sqrt();
        assert!((AXIS_111 - expected).length() < 1e-6, "{AXIS_111}");
    }
}

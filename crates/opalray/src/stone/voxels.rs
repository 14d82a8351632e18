//! The stone's voxel view: the cell grid the paper's two passes read, as the stone holds
//! it. For the paper's pattern the stone's domains are the growth's balls, and the grown
//! cells are the stone at the cell centres (each cell the latest ball covering its centre,
//! with that ball's orientation; `tests/stone_voxels.rs`), so the growth runs once and both
//! kinds of method read one stone. Any other stone (grains, one crystal) is read at the cell
//! centres of a grid over its box: a cell is outside where its centre is outside the
//! ellipsoid of that box (the growth's rule), else a cluster of the domain there, with its
//! orientation, or a void where there is none (potch, under a colour bar too, a triplet's
//! cap, and where the ellipsoid reaches beyond a cabochon's dome near the girdle: about a
//! fifth of its cells for a flat back). The passes render that ellipsoid, not the cut: no
//! flat back, cap or backing (`docs/architecture.md`, "One world").

use std::borrow::Cow;

use glam::Vec3;
use rayon::prelude::*;

use super::{Layout, Stone};
use crate::cancel::Cancel;
use crate::error::Result;
use crate::geometry::CellGrid;
use crate::scene::StructureConfig;
use crate::structure::{Cell, Growth, Structure};

impl Stone {
    /// The cells of the stone's growth (paper §2.4), `None` if its domains are not the
    /// paper's balls (grains, or [`Stone::single_crystal`]).
    pub fn voxels(&self) -> Option<&Structure> {
        match &self.layout {
            Layout::Balls(balls) => Some(balls.cells()),
            _ => None,
        }
    }

    /// The stone on the cell grid of `config`: the growth's own cells where the stone grew
    /// them ([`Stone::voxels`], on the grid it grew them on, `config` unread), else
    /// [`Stone::sample_voxels`].
    pub fn voxel_view(&self, config: &StructureConfig) -> Result<Cow<'_, Structure>> {
        match self.voxels() {
            Some(cells) => Ok(Cow::Borrowed(cells)),
            None => self.sample_voxels(config).map(Cow::Owned),
        }
    }

    /// The stone read at the centres of `config`'s cells (`config.grid` over the box of
    /// `config.semi_axes_mm`): outside the ellipsoid of those semi-axes, a cluster with the
    /// orientation of the domain at the centre, or a void where no domain is. The counts of
    /// [`Structure::stats`] are of the cells; no growth step was taken.
    pub fn sample_voxels(&self, config: &StructureConfig) -> Result<Structure> {
        // The growth's grid before its first step: every cell inside the ellipsoid a void.
        let mut structure = Growth::new(config)?.finish();
        let half = Vec3::from_array(config.semi_axes_mm.map(|v| v as f32));
        let grid = CellGrid::centered(config.grid, half);
        let [nx, ny, _] = config.grid;
        let slab = nx * ny;
        let slabs = structure
            .cells
            .chunks_mut(slab)
            .zip(structure.orientations.chunks_mut(slab));
        // A slab of z at a time, the cancel flag looked at between them.
        for (z, (cells, orientations)) in slabs.enumerate() {
            Cancel::check_current()?;
            cells
                .par_chunks_mut(nx)
                .zip(orientations.par_chunks_mut(nx))
                .enumerate()
                .for_each(|(y, (cells, orientations))| {
                    let row = cells.iter_mut().zip(orientations).enumerate();
                    for (x, (cell, orientation)) in row {
                        if *cell == Cell::Outside {
                            continue;
                        }
                        let at = Vec3::new(x as f32, y as f32, z as f32) + 0.5;
                        if let Some(domain) = self.domain_at(grid.min + at * grid.cell) {
                            *cell = Cell::Cluster;
                            *orientation = self.domains[domain as usize].orientation;
                        }
                    }
                });
        }
        let stats = &mut structure.stats;
        stats.clusters = structure
            .cells
            .iter()
            .filter(|&&c| c == Cell::Cluster)
            .count();
        stats.voids = stats.inside_cells - stats.clusters;
        stats.void_ratio = if stats.inside_cells > 0 {
            stats.voids as f64 / stats.inside_cells as f64
        } else {
            0.0
        };
        Ok(structure)
    }
}

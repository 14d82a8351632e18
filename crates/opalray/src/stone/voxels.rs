//! The stone's voxel view: the cell grid the paper's two passes read, as the stone holds
//! it. For the paper's pattern the stone's domains are the growth's balls, and the grown
//! cells are the stone at the cell centres (each cell the latest ball covering its centre,
//! with that ball's orientation; `tests/stone_voxels.rs`), so the growth runs once and both
//! kinds of method read one stone. A grain stone has no cell view.

use super::{Layout, Stone};
use crate::structure::Structure;

impl Stone {
    /// The cells of the stone's growth (paper §2.4), `None` if its domains are not the
    /// paper's balls (grains, or [`Stone::single_crystal`]).
    pub fn voxels(&self) -> Option<&Structure> {
        match &self.layout {
            Layout::Balls(balls) => Some(balls.cells()),
            _ => None,
        }
    }
}

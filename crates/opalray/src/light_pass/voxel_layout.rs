//! The voxels (the growth's cells, [`Stone::voxels`](crate::stone::Stone::voxels)) laid out
//! as both passes read them, whatever the light: storage slots, the volume of each cell
//! inside the stone, the patches of one orientation and their (111) normals, and per cell the
//! one record a light ray reads. Input: the [`Structure`] → output: [`VoxelLayout`], computed
//! once per stone (the frames of a sweep share it).

use glam::Vec3;
use rayon::prelude::*;

use super::{NO_PATCH, NO_SLOT};
use crate::geometry::{CellGrid, Ellipsoid};
use crate::structure::{Cell, Structure};

/// The voxels' cell grid and ellipsoid in the opal frame (origin at the centre, mm).
pub fn voxel_geometry(structure: &Structure) -> (Ellipsoid, CellGrid) {
    let half = Vec3::from_array(structure.semi_axes_mm.map(|v| v as f32));
    (
        Ellipsoid::new(half),
        CellGrid::centered(structure.grid, half),
    )
}

/// Sub-samples per axis used to measure how much of a surface cell lies inside the stone.
const VOLUME_SAMPLES: usize = 4;

/// For every slot, `1 / (volume of its cell inside the ellipsoid)`, mm⁻³: track lengths in a
/// cell cut by the surface only run through its inside part, so dividing by the whole cell's
/// volume would darken the stone's rim. Cells with all eight corners inside are whole; the
/// others are measured on a 4 × 4 × 4 sub-grid.
fn inverse_inside_volumes(
    grid: &CellGrid,
    ellipsoid: &Ellipsoid,
    cell_of_slot: &[usize],
) -> Vec<f32> {
    let [nx, ny, _] = grid.n;
    cell_of_slot
        .par_iter()
        .map(|&cell| {
            let (x, y, z) = (cell % nx, cell / nx % ny, cell / (nx * ny));
            let corner = grid.min + Vec3::new(x as f32, y as f32, z as f32) * grid.cell;
            let whole = (0..8).all(|k| {
                let offset =
                    Vec3::new((k & 1) as f32, ((k >> 1) & 1) as f32, ((k >> 2) & 1) as f32);
                ellipsoid.contains(corner + offset * grid.cell)
            });
            if whole {
                return whole_inverse_volume(grid);
            }
            let n = VOLUME_SAMPLES;
            let inside = (0..n * n * n)
                .filter(|&k| {
                    let u = Vec3::new((k % n) as f32, (k / n % n) as f32, (k / (n * n)) as f32);
                    ellipsoid.contains(corner + (u + 0.5) / n as f32 * grid.cell)
                })
                .count();
            let fraction = (inside.max(1) as f32) / (n * n * n) as f32;
            1.0 / (fraction * grid.cell_volume())
        })
        .collect()
}

/// 1 / (the volume of a cell wholly inside the stone), as [`inverse_inside_volumes`] gives
/// it for such a cell.
fn whole_inverse_volume(grid: &CellGrid) -> f32 {
    1.0 / grid.cell_volume()
}

/// The voxels laid out as the passes read them, whatever the light: computed once per stone
/// (the frames of a sweep share it).
#[derive(Clone, Debug)]
pub struct VoxelLayout {
    /// The stone's surface, in the opal frame (mm).
    pub ellipsoid: Ellipsoid,
    /// The cell grid over it.
    pub grid: CellGrid,
    /// Storage slot of each cell, or [`NO_SLOT`] outside the stone.
    pub slot_of_cell: Vec<u32>,
    /// The cell of each slot.
    pub cell_of_slot: Vec<usize>,
    /// Per cell, what a light ray crossing it reads.
    pub(crate) sites: Vec<Site>,
    /// The (111) normal of each patch: a patch is every cluster cell of one orientation (one
    /// growth step's ball, less what later balls overwrote), numbered in the order of its
    /// first cell. (Two patches may share a normal: the planes of a close-packed stack keep
    /// their normal under turns about it.)
    pub patch_normals: Vec<Vec3>,
    /// Per slot, 1 / (the cell's volume inside the stone), mm⁻³.
    pub inv_volume: Vec<f32>,
    /// 1 / (the volume of a cell wholly inside the stone), mm⁻³.
    pub whole_inv_volume: f32,
}

impl VoxelLayout {
    /// Lay out the cells of `structure`.
    pub fn new(structure: &Structure) -> Self {
        let (ellipsoid, grid) = voxel_geometry(structure);
        // Storage slots: one per inside cell, numbered in cell order.
        let mut slot_of_cell = vec![NO_SLOT; structure.cells.len()];
        let mut cell_of_slot = Vec::new();
        for (cell, kind) in structure.cells.iter().enumerate() {
            if *kind != Cell::Outside {
                slot_of_cell[cell] = cell_of_slot.len() as u32;
                cell_of_slot.push(cell);
            }
        }
        let inv_volume = inverse_inside_volumes(&grid, &ellipsoid, &cell_of_slot);
        let whole_inv_volume = whole_inverse_volume(&grid);
        // Patches: the distinct orientations (a growth step gives all the cells of its ball
        // one), found mostly by comparing with the cell before; their normals are formed once
        // each.
        let mut patch_normals = Vec::new();
        let mut patch_of = std::collections::HashMap::new();
        let mut last = ([u32::MAX; 4], NO_PATCH);
        let sites = structure
            .cells
            .iter()
            .enumerate()
            .zip(&slot_of_cell)
            .map(|((index, &cell), &slot)| {
                let mut patch = NO_PATCH;
                if cell == Cell::Cluster {
                    let key = structure.orientations[index].to_array().map(f32::to_bits);
                    if key != last.0 {
                        let id = *patch_of.entry(key).or_insert_with(|| {
                            patch_normals.push(structure.normal(index));
                            (patch_normals.len() - 1) as u32
                        });
                        last = (key, id);
                    }
                    patch = last.1;
                }
                let whole = slot != NO_SLOT && inv_volume[slot as usize] == whole_inv_volume;
                Site::new(cell, patch, slot, whole)
            })
            .collect();
        VoxelLayout {
            ellipsoid,
            grid,
            slot_of_cell,
            cell_of_slot,
            sites,
            patch_normals,
            inv_volume,
            whole_inv_volume,
        }
    }

    /// The (111) normal of cell `cell` if it is a cluster, else zero.
    pub fn normal(&self, cell: usize) -> Vec3 {
        match self.sites[cell].patch() {
            NO_PATCH => Vec3::ZERO,
            patch => self.patch_normals[patch as usize],
        }
    }

    /// The patch of cell `cell`: the index of its normal in [`VoxelLayout::patch_normals`], or
    /// [`NO_PATCH`] if it is not a cluster.
    pub fn patch(&self, cell: usize) -> u32 {
        self.sites[cell].patch()
    }

    /// Storage slots: inside cells.
    pub fn slots(&self) -> usize {
        self.cell_of_slot.len()
    }

    /// The default scene with a `grid` of cells, prepared, and its voxels laid out (for tests).
    #[cfg(test)]
    pub(crate) fn of_default_scene(grid: [usize; 3]) -> (crate::render::Prepared, Self) {
        let mut scene = crate::scene::Scene::default();
        scene.structure.grid = grid;
        let prepared = crate::render::prepare(&scene).expect("the default scene is valid");
        let voxels = VoxelLayout::new(prepared.structure().unwrap());
        (prepared, voxels)
    }
}

/// What a ray crossing a cell reads about it, in one 8-byte record (one memory access instead
/// of one per array, eight records to a cache line): the cell's storage slot, its kind,
/// whether it lies wholly inside the stone, and for a cluster its patch, the index of its
/// (111) normal in [`VoxelLayout::patch_normals`](super::VoxelLayout::patch_normals).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) struct Site {
    /// The slot, with [`Site::CLUSTER`] set for a cluster and [`Site::WHOLE`] for a cell whose
    /// inside volume is a whole cell's; [`NO_SLOT`] outside.
    tag: u32,
    /// A cluster's patch ([`NO_PATCH`] for voids and outside).
    patch: u32,
}

impl Site {
    /// Marks a cluster's slot.
    const CLUSTER: u32 = 1 << 31;
    /// Marks a cell wholly inside the stone (slots stay below it: the grid's size is checked).
    const WHOLE: u32 = 1 << 30;

    /// The site of a cell stored at `slot`, in `patch` if a cluster.
    pub fn new(cell: Cell, patch: u32, slot: u32, whole: bool) -> Self {
        assert!(
            cell == Cell::Outside || slot < Site::WHOLE,
            "slots stay below 2³⁰ (the grid's size is checked)"
        );
        let whole = if whole { Site::WHOLE } else { 0 };
        match cell {
            Cell::Cluster => Site {
                tag: slot | whole | Site::CLUSTER,
                patch,
            },
            Cell::Void => Site {
                tag: slot | whole,
                patch: NO_PATCH,
            },
            Cell::Outside => Site {
                tag: NO_SLOT,
                patch: NO_PATCH,
            },
        }
    }

    /// The cell's kind.
    #[inline(always)]
    pub fn cell(&self) -> Cell {
        if self.tag == NO_SLOT {
            Cell::Outside
        } else if self.tag & Site::CLUSTER != 0 {
            Cell::Cluster
        } else {
            Cell::Void
        }
    }

    /// The cell's storage slot (meaningless outside).
    #[inline(always)]
    pub fn slot(&self) -> usize {
        (self.tag & !(Site::CLUSTER | Site::WHOLE)) as usize
    }

    /// Whether the cell lies wholly inside the stone (meaningless outside).
    #[inline(always)]
    pub fn whole(&self) -> bool {
        self.tag & Site::WHOLE != 0
    }

    /// A cluster's patch: the index of its normal.
    #[inline(always)]
    pub fn patch(&self) -> u32 {
        self.patch
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_site_holds_its_cells_slot_kind_volume_and_normal() {
        // The paper's grid: a stone of many patches.
        let (prepared, voxels) = VoxelLayout::of_default_scene([100, 75, 25]);
        let structure = prepared.structure().unwrap();
        let (mut whole, mut cut) = (0, 0);
        for (cell, site) in voxels.sites.iter().enumerate() {
            assert_eq!(site.cell(), structure.cells[cell], "cell {cell}");
            let slot = voxels.slot_of_cell[cell];
            if slot == NO_SLOT {
                continue;
            }
            assert_eq!(site.slot(), slot as usize, "cell {cell}");
            let inv_volume = voxels.inv_volume[slot as usize];
            if site.whole() {
                whole += 1;
                assert_eq!(inv_volume.to_bits(), voxels.whole_inv_volume.to_bits());
            } else {
                cut += 1;
                assert!(
                    inv_volume > voxels.whole_inv_volume,
                    "cell {cell}: {inv_volume}"
                );
            }
            match site.cell() {
                Cell::Cluster => {
                    let normal = voxels.patch_normals[site.patch() as usize];
                    assert_eq!(normal.to_array(), structure.normal(cell).to_array());
                    assert_eq!(voxels.normal(cell), normal);
                }
                _ => {
                    assert_eq!(site.patch(), NO_PATCH);
                    assert_eq!(voxels.normal(cell), Vec3::ZERO);
                }
            }
        }
        assert!(
            whole > 1000 && cut > 100,
            "{whole} whole cells, {cut} cut by the surface"
        );
        // One patch per orientation: its cells share one, and no two patches have the same.
        let mut orientation_of = vec![None; voxels.patch_normals.len()];
        for (cell, site) in voxels.sites.iter().enumerate() {
            if site.cell() == Cell::Cluster {
                let key = structure.orientations[cell].to_array().map(f32::to_bits);
                let seen = orientation_of[site.patch() as usize].get_or_insert(key);
                assert_eq!(*seen, key, "cell {cell}");
            }
        }
        let mut keys: Vec<[u32; 4]> = orientation_of
            .into_iter()
            .map(|k| k.expect("every patch has a cell"))
            .collect();
        keys.sort_unstable();
        keys.dedup();
        assert_eq!(keys.len(), voxels.patch_normals.len());
        assert!(keys.len() > 20, "{} patches", keys.len());
    }
}

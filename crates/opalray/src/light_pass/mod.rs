//! Light pass (paper §3.2, fig. 6): rays from the light sources, stored per cell.
//!
//! Input: the structure, the cluster optics and a light → output: a [`LightField`], the light
//! crossing every inside cell as a fluence spectrum (power per area per nm: the track-length
//! estimate Σ Φ·ℓ / V, so it converges as rays are added and does not scale with their
//! number) in three lobes, each with its power-weighted mean direction: the *direct* light,
//! refracted once at the surface and since only filtered, and the *scattered* light, reflected
//! inside at least once (Bragg reflections, internal reflections at the surface), split into
//! light travelling down (−z) and up. The view pass needs the direction to place each
//! cluster's Bragg reflection (eq. 2's θ'); a mean over opposite directions would be
//! meaningless, and keeping the direct beam apart keeps its direction exact however weak or
//! strong the rest is.
//!
//! Rays are drawn on a jittered lattice over the beam, each with its own random stream
//! `(seed, LIGHT, index)`; the deposits of tiles of rays are added in tile order, so the
//! result is the same at any thread count.

mod accumulate;
mod direct;
mod interaction;
mod smooth;
mod source;
mod walk;

pub use interaction::{ClusterOptics, Split, Transmission};
pub use source::{LightSource, RayLattice};

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

use glam::Vec3;
use rayon::prelude::*;
use serde::Serialize;

use crate::geometry::{CellGrid, Ellipsoid};
use crate::optics::OpticsTables;
use crate::scene::LightConfig;
use crate::spectrum::WavelengthGrid;
use crate::structure::{Cell, Structure};
use accumulate::{OrderedSums, TileSums};
use walk::{Scratch, Site, Walker};

/// Lobes stored per cell: 0 = direct light; light reflected inside at least once,
/// 1 = travelling down (−z), 2 = travelling up (+z).
pub const LOBES: usize = 3;
/// Lobes the rays store (1 and 2); lobe 0, the direct light, is solved per cell.
const SCATTERED_LOBES: usize = 2;
/// Marks a cell with no storage (outside the stone).
pub const NO_SLOT: u32 = u32::MAX;
/// The patch of a cell that is not a cluster (see [`StoneCells::patch_normals`]).
pub const NO_PATCH: u32 = u32::MAX;
/// Work items are square tiles of the ray lattice, this many rays on a side: neighbouring
/// rays cross the same cells, so a tile's deposits stay in cache.
const TILE: u64 = 32;

/// Where the energy of the light pass went:
/// `emitted = reflected + escaped + stored + absorbed + truncated` to rounding.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct EnergyLedger {
    /// Power of the rays that met the stone.
    pub emitted: f64,
    /// Reflected by the outer surface on entry (the gloss).
    pub reflected: f64,
    /// Left the stone from inside.
    pub escaped: f64,
    /// Scattered diffusely by clusters and by the potch, stored where it happened.
    pub stored: f64,
    /// Absorbed by the potch (and by clusters, if their tables absorb).
    pub absorbed: f64,
    /// Cut: branches too weak to follow, or trapped by total internal reflection. Under
    /// [`Termination::Roulette`], the power roulette ended less the power it added to the
    /// survivors (zero on average), plus the light still trapped after the most surface
    /// reflections followed.
    pub truncated: f64,
    /// Rays traced: one per lattice cell, more where the light is trapped.
    pub rays: u64,
    /// Cells crossed by all rays and branches (work done, not energy).
    pub cells_crossed: u64,
    /// Branches followed (refracted rays, Bragg reflections, internal reflections).
    pub branches: u64,
}

impl EnergyLedger {
    fn add(mut self, o: EnergyLedger) -> Self {
        self.emitted += o.emitted;
        self.reflected += o.reflected;
        self.escaped += o.escaped;
        self.stored += o.stored;
        self.absorbed += o.absorbed;
        self.truncated += o.truncated;
        self.rays += o.rays;
        self.cells_crossed += o.cells_crossed;
        self.branches += o.branches;
        self
    }

    /// Everything booked as leaving: reflected + escaped + stored + absorbed + truncated,
    /// to compare with `emitted`.
    pub fn accounted(&self) -> f64 {
        self.reflected + self.escaped + self.stored + self.absorbed + self.truncated
    }
}

/// The light of one source, seen from the opal's frame.
#[derive(Clone, Debug)]
pub struct LightSetup<'a> {
    /// Where the light comes from.
    pub source: LightSource,
    /// The light's spectrum per bin, scaled so that irradiance 1 has luminance 1.
    pub spectrum: &'a [f32],
    /// Cells of the ray lattice (rounded to a square): one ray each, more where the light
    /// is trapped.
    pub rays: u64,
    /// Seed of the ray streams.
    pub seed: u64,
    /// Single-scattering albedo of the potch in voids (see `RenderConfig::body_albedo`).
    pub body_albedo: f32,
    /// Extinction of the potch, per mm.
    pub body_extinction_per_mm: f32,
    /// How weak light ends.
    pub termination: Termination,
}

/// How the light pass ends light too weak to follow: below `fraction` of its ray's entering
/// power (after the entry's reflection), a branch is cut, or plays Russian roulette.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Termination {
    /// Cut and booked as truncated: no noise, but the weak light is missing (the default
    /// render is darker than the unbiased estimate; `docs/model.md` gives the numbers).
    Cutoff(f32),
    /// Russian roulette: light below the fraction goes on with probability
    /// power / threshold, raised to the threshold, else ends. Unbiased, noisier and slower.
    Roulette(f32),
}

impl Termination {
    /// The default: cut at [`LightConfig::DEFAULT_CUTOFF`] (2 %).
    pub const DEFAULT: Termination = Termination::Cutoff(LightConfig::DEFAULT_CUTOFF as f32);

    /// The termination a scene's `light.cutoff` and `light.roulette` ask for.
    pub fn of(cutoff: f64, roulette: bool) -> Self {
        if roulette {
            Termination::Roulette(cutoff as f32)
        } else {
            Termination::Cutoff(cutoff as f32)
        }
    }
}

/// The light stored in every inside cell (clusters and voids).
#[derive(Clone, Debug)]
pub struct LightField {
    /// Wavelength bins of the spectra.
    pub grid: WavelengthGrid,
    /// Storage slot of each cell, or [`NO_SLOT`] outside the stone.
    pub slot_of_cell: Vec<u32>,
    /// Fluence spectra, power per mm² per nm, `slots × LOBES` entries of `bins + 4` values:
    /// each spectrum is followed by the sums its direction was found from (left in place:
    /// packing the spectra would cost a pass over the whole field). Read through
    /// [`LightField::fluence`].
    pub fluence: Vec<f32>,
    /// Mean direction of travel per slot and lobe (zero where no light arrived).
    pub directions: Vec<Vec3>,
    /// Mean resultant length of the directions per slot and lobe, |Σ P·w| / Σ P in [0, 1]:
    /// 1 when all the light came from one direction, smaller the more it is spread.
    pub concentration: Vec<f32>,
    /// Energy bookkeeping, with the rays traced.
    pub ledger: EnergyLedger,
}

impl LightField {
    /// Fluence spectrum of `slot`, `lobe`.
    pub fn fluence(&self, slot: usize, lobe: usize) -> &[f32] {
        let b = self.grid.bins;
        let start = (slot * LOBES + lobe) * (b + 4);
        &self.fluence[start..start + b]
    }
}

/// The stone's cell grid and shape in the opal frame (origin at the centre, mm).
pub fn stone_geometry(structure: &Structure) -> (Ellipsoid, CellGrid) {
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
fn inverse_inside_volumes(grid: &CellGrid, shape: &Ellipsoid, cell_of_slot: &[usize]) -> Vec<f32> {
    let [nx, ny, _] = grid.n;
    cell_of_slot
        .par_iter()
        .map(|&cell| {
            let (x, y, z) = (cell % nx, cell / nx % ny, cell / (nx * ny));
            let corner = grid.min + Vec3::new(x as f32, y as f32, z as f32) * grid.cell;
            let whole = (0..8).all(|k| {
                let offset =
                    Vec3::new((k & 1) as f32, ((k >> 1) & 1) as f32, ((k >> 2) & 1) as f32);
                shape.contains(corner + offset * grid.cell)
            });
            if whole {
                return whole_inverse_volume(grid);
            }
            let n = VOLUME_SAMPLES;
            let inside = (0..n * n * n)
                .filter(|&k| {
                    let u = Vec3::new((k % n) as f32, (k / n % n) as f32, (k / (n * n)) as f32);
                    shape.contains(corner + (u + 0.5) / n as f32 * grid.cell)
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

/// The stone's cells as the passes read them, whatever the light: computed once per stone
/// (the frames of a sweep share it).
#[derive(Clone, Debug)]
pub struct StoneCells {
    /// The stone's surface, in the opal frame (mm).
    pub shape: Ellipsoid,
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

impl StoneCells {
    /// Lay out the cells of `structure`.
    pub fn new(structure: &Structure) -> Self {
        let (shape, grid) = stone_geometry(structure);
        // Storage slots: one per inside cell, numbered in cell order.
        let mut slot_of_cell = vec![NO_SLOT; structure.cells.len()];
        let mut cell_of_slot = Vec::new();
        for (cell, kind) in structure.cells.iter().enumerate() {
            if *kind != Cell::Outside {
                slot_of_cell[cell] = cell_of_slot.len() as u32;
                cell_of_slot.push(cell);
            }
        }
        let inv_volume = inverse_inside_volumes(&grid, &shape, &cell_of_slot);
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
        StoneCells {
            shape,
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

    /// The patch of cell `cell`: the index of its normal in [`StoneCells::patch_normals`], or
    /// [`NO_PATCH`] if it is not a cluster.
    pub fn patch(&self, cell: usize) -> u32 {
        self.sites[cell].patch()
    }

    /// Storage slots: inside cells.
    pub fn slots(&self) -> usize {
        self.cell_of_slot.len()
    }

    /// The default scene with a `grid` of cells, prepared, and its cells laid out (for tests).
    #[cfg(test)]
    pub(crate) fn of_default_scene(grid: [usize; 3]) -> (crate::render::Prepared, Self) {
        let mut scene = crate::scene::Scene::default();
        scene.structure.grid = grid;
        let prepared = crate::render::prepare(&scene).expect("the default scene is valid");
        let cells = StoneCells::new(&prepared.structure);
        (prepared, cells)
    }
}

impl<'a> Walker<'a> {
    /// The light rays' view of `cells`, `optics` and the light `setup`.
    fn new(cells: &'a StoneCells, optics: &'a OpticsTables, setup: &LightSetup<'a>) -> Self {
        let StoneCells { shape, grid, .. } = *cells;
        Walker {
            sites: &cells.sites,
            patch_normals: &cells.patch_normals,
            cell_of_slot: &cells.cell_of_slot,
            optics: ClusterOptics::new(optics),
            shape,
            grid,
            n_eff: optics.n_eff as f32,
            spectrum: setup.spectrum,
            bin_width_nm: optics.grid.bin_width_nm() as f32,
            source: setup.source,
            lattice: RayLattice::new(setup.source, &shape, setup.rays),
            body_albedo: setup.body_albedo,
            body_extinction_per_mm: setup.body_extinction_per_mm,
            inv_volume: &cells.inv_volume,
            whole_inv_volume: cells.whole_inv_volume,
            seed: setup.seed,
            termination: setup.termination,
        }
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
fn heaviest_first(walker: &Walker, side: u64, tiles_per_row: u64) -> Vec<u64> {
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

/// Trace the light pass (paper §3.2) through `structure`, whose cells `cells` lays out
/// ([`StoneCells::new`] of the same structure).
pub fn trace_light(
    structure: &Structure,
    cells: &StoneCells,
    optics: &OpticsTables,
    setup: &LightSetup,
) -> LightField {
    assert_eq!(
        cells.slot_of_cell.len(),
        structure.cells.len(),
        "the cells must be laid out from this structure"
    );
    let slots = cells.slots();
    let bins = optics.grid.bins;
    let walker = Walker::new(cells, optics, setup);
    let side = walker.lattice.side();
    let tiles_per_row = side.div_ceil(TILE);
    let order = heaviest_first(&walker, side, tiles_per_row);
    let tasks = order.len() as u64;
    // Workers pull tiles, heaviest first, from a shared counter and hand each finished tile to
    // the one shared sum, which adds the tiles in that order (see `accumulate`).
    let next_task = AtomicU64::new(0);
    let shared = Mutex::new(OrderedSums::new(
        slots * SCATTERED_LOBES,
        bins,
        LOBES,
        SCATTERED_LOBES,
        1,
    ));
    let lock = || {
        shared
            .lock()
            .expect("no worker panics while holding the sums")
    };
    let ledger = (0..rayon::current_num_threads())
        .into_par_iter()
        .map(|_| {
            let mut spare = None;
            let mut ledger = EnergyLedger::default();
            let mut scratch = Scratch::default();
            loop {
                let task = next_task.fetch_add(1, Ordering::Relaxed);
                if task >= tasks {
                    break;
                }
                let mut tile = spare
                    .take()
                    .unwrap_or_else(|| TileSums::new(slots * SCATTERED_LOBES, bins));
                let tile_index = order[task as usize];
                let at = (
                    tile_index % tiles_per_row * TILE,
                    tile_index / tiles_per_row * TILE,
                );
                // One copy of the walk per termination.
                match walker.termination {
                    Termination::Cutoff(_) => {
                        walker.trace_tile::<false>(at, side, &mut tile, &mut ledger, &mut scratch)
                    }
                    Termination::Roulette(_) => {
                        walker.trace_tile::<true>(at, side, &mut tile, &mut ledger, &mut scratch)
                    }
                }
                let mut sums = lock();
                sums.submit(task, tile);
                spare = sums.take_spare();
            }
            ledger
        })
        .reduce(EnergyLedger::default, EnergyLedger::add);
    let sums = shared
        .into_inner()
        .expect("no worker panicked while holding the sums");
    let stride = sums.stride();
    let mut sums = sums.into_sums();
    walker.fill_direct(&mut sums, stride, LOBES);
    let (directions, concentration) = smooth::smooth_sums(&mut sums, cells, stride);
    LightField {
        grid: optics.grid,
        slot_of_cell: cells.slot_of_cell.clone(),
        fluence: sums,
        directions,
        concentration,
        ledger,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn each_site_holds_its_cells_slot_kind_volume_and_normal() {
        // The paper's grid: a stone of many patches.
        let (prepared, cells) = StoneCells::of_default_scene([100, 75, 25]);
        let structure = &prepared.structure;
        let (mut whole, mut cut) = (0, 0);
        for (cell, site) in cells.sites.iter().enumerate() {
            assert_eq!(site.cell(), structure.cells[cell], "cell {cell}");
            let slot = cells.slot_of_cell[cell];
            if slot == NO_SLOT {
                continue;
            }
            assert_eq!(site.slot(), slot as usize, "cell {cell}");
            let inv_volume = cells.inv_volume[slot as usize];
            if site.whole() {
                whole += 1;
                assert_eq!(inv_volume.to_bits(), cells.whole_inv_volume.to_bits());
            } else {
                cut += 1;
                assert!(
                    inv_volume > cells.whole_inv_volume,
                    "cell {cell}: {inv_volume}"
                );
            }
            match site.cell() {
                Cell::Cluster => {
                    let normal = cells.patch_normals[site.patch() as usize];
                    assert_eq!(normal.to_array(), structure.normal(cell).to_array());
                    assert_eq!(cells.normal(cell), normal);
                }
                _ => {
                    assert_eq!(site.patch(), NO_PATCH);
                    assert_eq!(cells.normal(cell), Vec3::ZERO);
                }
            }
        }
        assert!(
            whole > 1000 && cut > 100,
            "{whole} whole cells, {cut} cut by the surface"
        );
        // One patch per orientation: its cells share one, and no two patches have the same.
        let mut orientation_of = vec![None; cells.patch_normals.len()];
        for (cell, site) in cells.sites.iter().enumerate() {
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
        assert_eq!(keys.len(), cells.patch_normals.len());
        assert!(keys.len() > 20, "{} patches", keys.len());
    }

    #[test]
    fn every_tile_is_traced_once_the_rim_first() {
        let (prepared, cells) = StoneCells::of_default_scene([40, 30, 10]);
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
        let walker = Walker::new(&cells, &prepared.optics, &setup);
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

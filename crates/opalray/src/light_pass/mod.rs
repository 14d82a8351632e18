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
pub(crate) mod direct;
mod interaction;
mod shape;
mod smooth;
mod source;
mod tiles;
mod voxel_layout;
mod walk;

pub use interaction::{ClusterOptics, Split, Transmission};
pub use source::{LightSource, RayLattice};
pub use voxel_layout::{voxel_geometry, VoxelLayout};

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Mutex;

use glam::Vec3;
use rayon::prelude::*;
use serde::Serialize;

use crate::optics::OpticsTables;
use crate::scene::LightConfig;
use crate::spectrum::WavelengthGrid;
use crate::structure::Structure;
use accumulate::{OrderedSums, TileSums};
use tiles::heaviest_first;
use walk::{Scratch, Walker};

/// Lobes stored per cell: 0 = direct light; light reflected inside at least once,
/// 1 = travelling down (−z), 2 = travelling up (+z).
pub const LOBES: usize = 3;
/// Lobes the rays store (1 and 2); lobe 0, the direct light, is solved per cell.
const SCATTERED_LOBES: usize = 2;
/// Marks a cell with no storage (outside the stone).
pub const NO_SLOT: u32 = u32::MAX;
/// The patch of a cell that is not a cluster (see [`VoxelLayout::patch_normals`]).
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

/// Trace the light pass (paper §3.2) through `structure`, whose voxels `voxels` lays out
/// ([`VoxelLayout::new`] of the same structure).
pub fn trace_light(
    structure: &Structure,
    voxels: &VoxelLayout,
    optics: &OpticsTables,
    setup: &LightSetup,
) -> LightField {
    assert_eq!(
        voxels.slot_of_cell.len(),
        structure.cells.len(),
        "the voxels must be laid out from this structure"
    );
    let slots = voxels.slots();
    let bins = optics.grid.bins;
    let walker = Walker::new(voxels, optics, setup);
    let (sums, ledger) = trace_tiles(&walker, slots, bins);
    let stride = sums.stride();
    let mut sums = sums.into_sums();
    walker.fill_direct(&mut sums, stride, LOBES);
    let (directions, concentration) = smooth::smooth_sums(&mut sums, voxels, stride);
    LightField {
        grid: optics.grid,
        slot_of_cell: voxels.slot_of_cell.clone(),
        fluence: sums,
        directions,
        concentration,
        ledger,
    }
}

/// Trace every tile of `walker`'s ray lattice, heaviest first, on every thread: the scattered
/// light's sums over `slots` slots of `bins` bins, the tiles added in task order, and the sum
/// of the tiles' ledgers, added in task order too.
fn trace_tiles(walker: &Walker, slots: usize, bins: usize) -> (OrderedSums, EnergyLedger) {
    let side = walker.lattice.side();
    let tiles_per_row = side.div_ceil(TILE);
    let order = heaviest_first(walker, side, tiles_per_row);
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
    // Each tile keeps its own ledger, and the ledgers are added in task order: the energy
    // figures, like the image, are the same at any thread count.
    // A stopped pass takes no more tiles (its sums are never used).
    let cancel = crate::cancel::Cancel::current();
    let mut ledgers: Vec<(u64, EnergyLedger)> = (0..rayon::current_num_threads())
        .into_par_iter()
        .map(|_| {
            let mut spare = None;
            let mut ledgers = Vec::new();
            let mut scratch = Scratch::default();
            loop {
                let task = next_task.fetch_add(1, Ordering::Relaxed);
                if task >= tasks || cancel.is_cancelled() {
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
                let mut ledger = EnergyLedger::default();
                trace_tile(walker, at, side, &mut tile, &mut ledger, &mut scratch);
                ledgers.push((task, ledger));
                let mut sums = lock();
                sums.submit(task, tile);
                spare = sums.take_spare();
            }
            ledgers
        })
        .flatten()
        .collect();
    ledgers.sort_unstable_by_key(|&(task, _)| task);
    let ledger = ledgers
        .into_iter()
        .fold(EnergyLedger::default(), |sum, (_, l)| sum.add(l));
    let sums = shared
        .into_inner()
        .expect("no worker panicked while holding the sums");
    (sums, ledger)
}

/// Trace the tile of the lattice (of `side` rays a side) whose first ray is `at` into `tile`
/// and `ledger`, in the copy of the walk compiled for the walker's termination.
#[inline(always)]
fn trace_tile(
    walker: &Walker,
    at: (u64, u64),
    side: u64,
    tile: &mut TileSums,
    ledger: &mut EnergyLedger,
    scratch: &mut Scratch,
) {
    match walker.termination {
        Termination::Cutoff(_) => walker.trace_tile::<false>(at, side, tile, ledger, scratch),
        Termination::Roulette(_) => walker.trace_tile::<true>(at, side, tile, ledger, scratch),
    }
}

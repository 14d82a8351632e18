//! One light ray through the stone (paper §3.2, fig. 6): refraction at the surface, then cell
//! by cell: store the light crossing each cell, split it at clusters into the Bragg-reflected
//! branch, the transmitted ray and the diffuse part; attenuate it in voids; reflect it
//! internally (Fresnel, total internal reflection) at the surface until it leaves or fades.
//! The walk is an outline; its steps, and the one place its energy is booked, are in
//! `walk/steps.rs`.

use glam::Vec3;

use super::accumulate::TileSums;
use super::interaction::ClusterOptics;
use super::source::{LightSource, RayLattice};
use super::voxel_layout::{Site, VoxelLayout};
use super::{EnergyLedger, LightSetup, Termination, TILE};
use crate::geometry::{fresnel_dielectric, refract, CellGrid, Ellipsoid, Ray};
use crate::optics::OpticsTables;
use crate::sampling::{stage, Rng};
use crate::spectrum;
use crate::structure::Cell;

mod steps;

use steps::{Booking, Budget, Carried, Fractions, PatchSplit};

/// Surface interactions after which a branch is ended (light trapped by total internal
/// reflection); its power is booked as truncated.
const MAX_SURFACE_BOUNCES: u32 = 24;
/// Lattice cells whose light would be trapped by total internal reflection are traced with
/// this many rays on a side, each carrying its share of the cell's power.
const TRAPPED_SPLIT: u64 = 2;

/// Everything a light ray needs to know, shared by all threads.
pub(crate) struct Walker<'a> {
    /// Per cell, what a crossing ray reads: its slot, kind and patch.
    pub sites: &'a [Site],
    /// The (111) normal of each patch.
    pub patch_normals: &'a [Vec3],
    pub cell_of_slot: &'a [usize],
    pub optics: ClusterOptics<'a>,
    pub ellipsoid: Ellipsoid,
    pub grid: CellGrid,
    pub n_eff: f32,
    pub spectrum: &'a [f32],
    pub bin_width_nm: f32,
    pub source: LightSource,
    pub lattice: RayLattice,
    pub body_albedo: f32,
    pub body_extinction_per_mm: f32,
    /// Per slot, 1 / (the cell's volume inside the stone), mm⁻³.
    pub inv_volume: &'a [f32],
    /// The same for a cell wholly inside (no memory access for most cells).
    pub whole_inv_volume: f32,
    pub seed: u64,
    /// How light too weak to follow ends.
    pub termination: Termination,
}

impl<'a> Walker<'a> {
    /// The light rays' view of `voxels`, `optics` and the light `setup`.
    pub fn new(voxels: &'a VoxelLayout, optics: &'a OpticsTables, setup: &LightSetup<'a>) -> Self {
        let VoxelLayout {
            ellipsoid, grid, ..
        } = *voxels;
        Walker {
            sites: &voxels.sites,
            patch_normals: &voxels.patch_normals,
            cell_of_slot: &voxels.cell_of_slot,
            optics: ClusterOptics::new(optics),
            ellipsoid,
            grid,
            n_eff: optics.n_eff as f32,
            spectrum: setup.spectrum,
            bin_width_nm: optics.grid.bin_width_nm() as f32,
            source: setup.source,
            lattice: RayLattice::new(setup.source, &ellipsoid, setup.rays),
            body_albedo: setup.body_albedo,
            body_extinction_per_mm: setup.body_extinction_per_mm,
            inv_volume: &voxels.inv_volume,
            whole_inv_volume: voxels.whole_inv_volume,
            seed: setup.seed,
            termination: setup.termination,
        }
    }
}

/// Per-thread scratch space reused from ray to ray.
#[derive(Default)]
pub(crate) struct Scratch {
    r: Vec<f32>,
    t: Vec<f32>,
    d: Vec<f32>,
    stack: Vec<Branch>,
    pool: Vec<Vec<f32>>,
}

impl Scratch {
    /// The reflectance, transmittance and diffuse scratch as one [`Fractions`], the stack of
    /// branches waiting and the pool of spare spectra.
    #[inline(always)]
    fn split(&mut self) -> (Fractions<'_>, &mut Vec<Branch>, &mut Vec<Vec<f32>>) {
        let Scratch {
            r,
            t,
            d,
            stack,
            pool,
        } = self;
        (Fractions { r, t, d }, stack, pool)
    }
}

/// A branch's spectrum is `scale × shape`: filters flat in wavelength (most clusters, voids,
/// the surface) change the scale only, a Bragg line the bins of its window.
struct Branch {
    origin: Vec3,
    direction: Vec3,
    shape: Vec<f32>,
    scale: f32,
    power: f32,
    bounces: u32,
    lobe: usize,
}

/// Lobe of light that has come straight from the light, refracted once at the surface.
const DIRECT: usize = 0;
/// Marks a branch reflected inside (Bragg or at the surface) at least once; its lobe is
/// then 1 (travelling down, −z) or 2 (travelling up).
const SCATTERED: usize = 1;

fn lobe_of(kind: usize, direction: Vec3) -> usize {
    match kind {
        DIRECT => DIRECT,
        _ => 1 + usize::from(direction.z >= 0.0),
    }
}

impl Walker<'_> {
    /// Radiant power of a spectrum (sum over bins × bin width).
    pub fn power(&self, spectrum: &[f32]) -> f32 {
        spectrum::sum(spectrum) * self.bin_width_nm
    }

    /// Trace the light of lattice cell `index`, adding what it deposits to `acc` and its
    /// energy to `ledger`: one ray jittered in the cell, or, where the cell's light would be
    /// trapped, [`TRAPPED_SPLIT`]² rays jittered in its sub-cells.
    #[inline(always)]
    fn trace<const ROULETTE: bool>(
        &self,
        index: u64,
        acc: &mut TileSums,
        ledger: &mut EnergyLedger,
        scratch: &mut Scratch,
    ) {
        let bins = self.spectrum.len();
        scratch.r.resize(bins, 0.0);
        scratch.t.resize(bins, 0.0);
        scratch.d.resize(bins, 0.0);
        let mut rng = Rng::new(self.seed, stage::LIGHT, index);
        // Roulette's own stream; the cut never draws from it, so it takes a copy.
        let mut chance = if ROULETTE {
            Rng::new(self.seed, stage::ROULETTE, index)
        } else {
            rng.clone()
        };
        let trapped = self.is_trapped(index);
        let m = if trapped { TRAPPED_SPLIT } else { 1 };
        let share = 1.0 / (m * m) as f32;
        // One call site of `trace_ray`, so that it and its walk inline once.
        for k in 0..m * m {
            let ray = if trapped {
                let fu = ((k % m) as f32 + rng.uniform_f32()) / m as f32;
                let fv = ((k / m) as f32 + rng.uniform_f32()) / m as f32;
                self.lattice.ray_in(index, fu, fv)
            } else {
                self.lattice.ray(index, &mut rng)
            };
            self.trace_ray::<ROULETTE>(ray, share, acc, ledger, scratch, &mut chance);
        }
    }

    /// Trace the lattice cells of the tile whose first cell is `(x0, y0)`, on a lattice of
    /// `side` cells a side, in row order, in the copy compiled for the processor's widest
    /// vectors (`simd`).
    #[inline(always)]
    pub fn trace_tile<const ROULETTE: bool>(
        &self,
        (x0, y0): (u64, u64),
        side: u64,
        acc: &mut TileSums,
        ledger: &mut EnergyLedger,
        scratch: &mut Scratch,
    ) {
        crate::simd::widest(
            #[inline(always)]
            || {
                for y in y0..(y0 + TILE).min(side) {
                    for x in x0..(x0 + TILE).min(side) {
                        self.trace::<ROULETTE>(y * side + x, acc, ledger, scratch);
                    }
                }
            },
        )
    }

    /// Whether light of `power` goes on, and the factor its power is raised by: 1 at or
    /// above `threshold` (if positive); below it, see [`Walker::roulette`].
    #[inline(always)]
    fn carry_on<const ROULETTE: bool>(power: f32, threshold: f32, rng: &mut Rng) -> Option<f32> {
        if power > 0.0 && power >= threshold {
            Some(1.0)
        } else {
            Self::roulette::<ROULETTE>(power, threshold, rng)
        }
    }

    /// Light of `power` below `threshold`: with roulette, the factor taking it to the
    /// threshold, with probability power / threshold (so that its expected power is
    /// unchanged), else `None`: it ends. Without (a constant parameter, so that the cut's walk
    /// has no roulette in it), always `None`.
    #[inline(always)]
    fn roulette<const ROULETTE: bool>(power: f32, threshold: f32, rng: &mut Rng) -> Option<f32> {
        if !ROULETTE {
            return None;
        }
        // Uniform in (0, 1): a draw of zero must not keep light of no power.
        let u = rng.uniform_f32() + 0.5 / 16_777_216.0;
        (power > 0.0 && u * threshold < power).then(|| threshold / power)
    }

    /// Trace one ray carrying `share` of its lattice cell's power.
    #[inline(always)]
    fn trace_ray<const ROULETTE: bool>(
        &self,
        ray: Ray,
        share: f32,
        acc: &mut TileSums,
        ledger: &mut EnergyLedger,
        scratch: &mut Scratch,
        rng: &mut Rng,
    ) {
        ledger.rays += 1;
        let Some((t_hit, _)) = self.ellipsoid.intersect(&ray) else {
            return;
        };
        if t_hit <= 0.0 {
            return;
        }
        // Refract into the stone; the Fresnel-reflected part is the surface's gloss.
        let p = ray.at(t_hit);
        let normal = self.ellipsoid.normal(p);
        let weight = share * self.lattice.power_per_ray * self.source.irradiance_at(p);
        let p_in = self.power(self.spectrum) * weight;
        let fresnel = fresnel_dielectric(-ray.direction.dot(normal), 1.0, self.n_eff);
        ledger.book(Booking::Entered {
            emitted: p_in,
            reflected: p_in * fresnel,
        });
        let Some(direction) = refract(ray.direction, normal, 1.0, self.n_eff) else {
            return;
        };
        let mut shape = scratch.pool.pop().unwrap_or_default();
        shape.clear();
        shape.extend_from_slice(self.spectrum);
        let fraction = match self.termination {
            Termination::Cutoff(f) | Termination::Roulette(f) => f,
        };
        let threshold = fraction * p_in * (1.0 - fresnel);
        scratch.stack.push(Branch {
            origin: p,
            direction,
            power: p_in * (1.0 - fresnel),
            shape,
            scale: weight * (1.0 - fresnel),
            bounces: 0,
            lobe: DIRECT,
        });
        let mut budget = Budget {
            threshold,
            rng,
            ledger,
        };
        while let Some(branch) = scratch.stack.pop() {
            self.walk::<ROULETTE>(branch, acc, &mut budget, scratch);
        }
    }

    /// Follow one branch from its origin to where it leaves the stone or fades: cell by cell
    /// (store, attenuate or split, roulette), then leave or reflect at the surface.
    #[inline(always)]
    fn walk<const ROULETTE: bool>(
        &self,
        branch: Branch,
        acc: &mut TileSums,
        budget: &mut Budget,
        scratch: &mut Scratch,
    ) {
        let Branch {
            origin,
            direction,
            shape,
            scale,
            power,
            bounces,
            lobe: kind,
        } = branch;
        let lobe = lobe_of(kind, direction);
        let ray = Ray { origin, direction };
        let Some((t0, t1)) = self.ellipsoid.intersect(&ray) else {
            budget.ledger.book(Booking::Escaped(power));
            scratch.pool.push(shape);
            return;
        };
        budget.ledger.branches += 1;
        let mut carried = Carried {
            shape,
            scale,
            power,
        };
        let mut alive = true;
        let mut last = PatchSplit::NONE;
        let (mut fractions, stack, pool) = scratch.split();
        self.grid.traverse(
            &ray,
            t0.max(0.0),
            t1,
            #[inline(always)]
            |seg| {
                budget.ledger.cells_crossed += 1;
                let site = self.sites[seg.index];
                let cell = site.cell();
                let Some((track, kept)) = self.track(cell, seg.t_exit - seg.t_enter) else {
                    return true;
                };
                if kind != DIRECT {
                    let at = (site.slot(), site.whole());
                    self.deposit(acc, at, lobe, &carried, (track, direction));
                }
                if cell == Cell::Void {
                    self.attenuate(&mut carried, kept, budget.ledger);
                } else {
                    if site.patch() != last.patch {
                        last = self.split_for(site.patch(), direction, &mut fractions);
                    }
                    let f = &fractions;
                    if let Some(reflected) =
                        self.split_at_cluster::<ROULETTE>(&mut carried, last.split, f, pool, budget)
                    {
                        let span = (seg.t_enter, seg.t_exit);
                        stack.push(Self::reflected_branch(
                            &ray,
                            span,
                            last.normal,
                            reflected,
                            bounces,
                        ));
                    }
                }
                alive = Self::survives::<ROULETTE>(&mut carried, budget);
                alive
            },
        );
        let exit = alive.then(|| (ray.at(t1), direction));
        self.end_branch::<ROULETTE>(exit, carried, bounces, (pool, stack), budget);
    }

    /// End a branch's walk: one that faded (`exit` `None`) returns its shape to `pool`; one
    /// that reached the surface at `exit` (point, direction) leaves or reflects there, the
    /// reflection pushed on `stack`.
    #[inline(always)]
    fn end_branch<const ROULETTE: bool>(
        &self,
        exit: Option<(Vec3, Vec3)>,
        carried: Carried,
        bounces: u32,
        (pool, stack): (&mut Vec<Vec<f32>>, &mut Vec<Branch>),
        budget: &mut Budget,
    ) {
        let Some(exit) = exit else {
            pool.push(carried.shape);
            return;
        };
        if let Some(next) = self.leave_or_reflect::<ROULETTE>(exit, carried, bounces, pool, budget)
        {
            stack.push(next);
        }
    }
}

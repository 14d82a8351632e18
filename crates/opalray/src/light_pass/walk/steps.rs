//! The steps of a light branch's walk ([`Walker::walk`]), one a cell or a surface: the track
//! through a cell, the light stored there, the potch's attenuation, the split at a cluster,
//! roulette, and leaving or reflecting at the surface. Every change of a branch's power is
//! booked in one place, [`EnergyLedger::book`].

use glam::Vec3;

use super::super::accumulate::TileSums;
use super::super::interaction::Split;
use super::super::shape::{filter_window, reflected_shape, window_sums};
use super::super::{EnergyLedger, NO_PATCH, SCATTERED_LOBES};
use super::{Branch, Walker, MAX_SURFACE_BOUNCES, SCATTERED};
use crate::geometry::{fresnel_dielectric, reflect, Ray};
use crate::sampling::Rng;
use crate::structure::Cell;

/// Where a branch's power goes, as the ledger books it.
#[derive(Clone, Copy, Debug)]
pub(super) enum Booking {
    /// A ray met the stone with power `emitted`; `reflected` of it is the surface's gloss.
    Entered { emitted: f32, reflected: f32 },
    /// Left the stone (or missed it).
    Escaped(f32),
    /// Lost in the potch: the albedo's share stored, the rest absorbed.
    Potch { lost: f64, albedo: f32 },
    /// Split at a cluster: `diffuse` stored where it happened, `absorbed` absorbed.
    Cluster { diffuse: f32, absorbed: f32 },
    /// Ended: too weak to follow, or trapped.
    Truncated(f32),
    /// Raised by roulette from `before` to `after` (its expected power unchanged): the
    /// power added is taken from the truncated.
    Raised { before: f32, after: f32 },
}

impl EnergyLedger {
    /// Book `entry`: the one place the walk's energy is counted.
    #[inline(always)]
    pub(super) fn book(&mut self, entry: Booking) {
        match entry {
            Booking::Entered { emitted, reflected } => {
                self.emitted += f64::from(emitted);
                self.reflected += f64::from(reflected);
            }
            Booking::Escaped(power) => self.escaped += f64::from(power),
            Booking::Potch { lost, albedo } => {
                self.stored += f64::from(albedo) * lost;
                self.absorbed += f64::from(1.0 - albedo) * lost;
            }
            Booking::Cluster { diffuse, absorbed } => {
                self.stored += f64::from(diffuse);
                self.absorbed += f64::from(absorbed);
            }
            Booking::Truncated(power) => self.truncated += f64::from(power),
            Booking::Raised { before, after } => {
                self.truncated -= f64::from(after) - f64::from(before);
            }
        }
    }
}

/// The light a branch carries: its spectrum `scale × shape` and its power.
pub(super) struct Carried {
    /// The spectrum's shape (bins), filtered by the Bragg lines crossed.
    pub shape: Vec<f32>,
    /// The spectrum's scale.
    pub scale: f32,
    /// Radiant power.
    pub power: f32,
}

/// The budget of a walk: below `threshold` light plays roulette (drawing from `rng`) or
/// ends; what it gains or loses goes to `ledger`.
pub(super) struct Budget<'w> {
    /// Power below which a branch is not simply followed.
    pub threshold: f32,
    /// Roulette's stream.
    pub rng: &'w mut Rng,
    /// Where the energy is booked.
    pub ledger: &'w mut EnergyLedger,
}

/// The split last computed along a walk: cells of one patch, met one after another, split
/// the light alike (the scratch `r`, `t`, `d` still hold its window).
pub(super) struct PatchSplit {
    /// The patch it was computed for.
    pub patch: u32,
    /// That patch's (111) normal.
    pub normal: Vec3,
    /// The split.
    pub split: Split,
}

impl PatchSplit {
    /// No patch met yet.
    pub const NONE: PatchSplit = PatchSplit {
        patch: NO_PATCH,
        normal: Vec3::ZERO,
        split: Split::Flat {
            r: 0.0,
            t: 1.0,
            d: 0.0,
        },
    };
}

/// The per-bin split fractions of the last window, the walk's scratch.
pub(super) struct Fractions<'s> {
    /// Specular reflectance per bin.
    pub r: &'s mut [f32],
    /// Transmittance per bin.
    pub t: &'s mut [f32],
    /// Diffuse fraction per bin.
    pub d: &'s mut [f32],
}

/// A branch reflected by a cluster: its shape, scale and power.
type Reflected = (Vec<f32>, f32, f32);

impl Walker<'_> {
    /// The split of light travelling along `direction` at the planes of `patch`, its
    /// window's fractions written into `f`.
    #[inline(always)]
    pub(super) fn split_for(&self, patch: u32, direction: Vec3, f: &mut Fractions) -> PatchSplit {
        let normal = self.patch_normals[patch as usize];
        let cos = direction.dot(normal).abs();
        let split = self.optics.split(cos, f.r, f.t, f.d);
        PatchSplit {
            patch,
            normal,
            split,
        }
    }

    /// The light's track through a cell of `length` mm and the fraction of it kept: the chord
    /// in a cluster; in a void (potch) ∫₀ˡ e^(−σs) ds under exponential attenuation, and its
    /// limit ℓ for a clear body. `None` outside the stone.
    #[inline(always)]
    pub(super) fn track(&self, cell: Cell, length: f32) -> Option<(f32, f32)> {
        let sigma = self.body_extinction_per_mm;
        match cell {
            Cell::Outside => None,
            Cell::Cluster => Some((length, 1.0)),
            Cell::Void => {
                let kept = (-sigma * length).exp();
                if sigma * length > 1e-4 {
                    Some(((1.0 - kept) / sigma, kept))
                } else {
                    Some((length, kept))
                }
            }
        }
    }

    /// Store the light of `carried` crossing the cell of `slot` over `track` mm along
    /// `direction`, in scattered lobe `lobe` (the direct light is computed per cell,
    /// `direct.rs`, not stored).
    #[inline(always)]
    pub(super) fn deposit(
        &self,
        acc: &mut TileSums,
        (slot, whole): (usize, bool),
        lobe: usize,
        carried: &Carried,
        (track, direction): (f32, Vec3),
    ) {
        let inv_volume = if whole {
            self.whole_inv_volume
        } else {
            self.inv_volume[slot]
        };
        acc.deposit(
            slot * SCATTERED_LOBES + lobe - 1,
            &carried.shape,
            carried.scale * track * inv_volume,
            direction,
            carried.power * track * inv_volume,
        );
    }

    /// The potch dims `carried` to `kept` of it; what is lost is booked.
    #[inline(always)]
    pub(super) fn attenuate(&self, carried: &mut Carried, kept: f32, ledger: &mut EnergyLedger) {
        let lost = f64::from(carried.power * (1.0 - kept));
        ledger.book(Booking::Potch {
            lost,
            albedo: self.body_albedo,
        });
        carried.scale *= kept;
        carried.power *= kept;
    }

    /// Split `carried` at a cluster by `split` (its window's fractions in `f`): the diffuse
    /// part stored, the rest absorbed, `carried` left with the transmitted ray. Returns the
    /// Bragg-reflected branch where it is strong enough (or roulette keeps it).
    #[inline(always)]
    pub(super) fn split_at_cluster<const ROULETTE: bool>(
        &self,
        carried: &mut Carried,
        split: Split,
        f: &Fractions,
        pool: &mut Vec<Vec<f32>>,
        budget: &mut Budget,
    ) -> Option<Reflected> {
        let power = carried.power;
        let (p_r, p_d, p_t);
        let mut reflected: Option<Reflected> = None;
        match split {
            Split::Flat { r, t, d } => {
                p_r = power * r;
                p_d = power * d;
                p_t = power * t;
                if let Some(boost) = Self::carry_on::<ROULETTE>(p_r, budget.threshold, budget.rng) {
                    let (v, _) = reflected_shape(pool, &carried.shape, None, false);
                    reflected = Some((v, carried.scale * r * boost, p_r * boost));
                }
                carried.scale *= t;
            }
            Split::Window {
                lo,
                hi,
                r: rb,
                t: tb,
                d: db,
            } => {
                let bw = self.bin_width_nm;
                let (r, t, d) = (&f.r[lo..hi], &f.t[lo..hi], &f.d[lo..hi]);
                let inside = &carried.shape[lo..hi];
                let k = carried.scale * bw;
                let [s_in, s_r, s_d, s_t] = window_sums(inside, r, d, t);
                let p_out = power - s_in * k;
                p_r = rb * p_out + s_r * k;
                p_d = db * p_out + s_d * k;
                p_t = tb * p_out + s_t * k;
                if let Some(boost) = Self::carry_on::<ROULETTE>(p_r, budget.threshold, budget.rng) {
                    // Chains of Bragg reflections that roulette keeps would grow the shape
                    // without bound: it is renormalised.
                    let window = Some((lo, r, rb));
                    let (v, k) = reflected_shape(pool, &carried.shape, window, boost != 1.0);
                    reflected = Some((v, carried.scale * k * boost, p_r * boost));
                }
                carried.scale *= filter_window(&mut carried.shape, lo, t, tb);
            }
        }
        budget.ledger.book(Booking::Cluster {
            diffuse: p_d,
            absorbed: power - p_r - p_d - p_t,
        });
        carried.power = p_t;
        match reflected {
            Some((v, k, p)) => {
                if ROULETTE {
                    budget.ledger.book(Booking::Raised {
                        before: p_r,
                        after: p,
                    });
                }
                Some((v, k, p))
            }
            None => {
                budget.ledger.book(Booking::Truncated(p_r));
                None
            }
        }
    }

    /// After a cell: light below the threshold plays roulette (raised, or ended and booked
    /// as truncated). Whether the branch goes on.
    #[inline(always)]
    pub(super) fn survives<const ROULETTE: bool>(
        carried: &mut Carried,
        budget: &mut Budget,
    ) -> bool {
        let power = carried.power;
        if power < budget.threshold {
            match Self::roulette::<ROULETTE>(power, budget.threshold, budget.rng) {
                Some(boost) => {
                    budget.ledger.book(Booking::Raised {
                        before: power,
                        after: power * boost,
                    });
                    carried.scale *= boost;
                    carried.power *= boost;
                }
                None => {
                    budget.ledger.book(Booking::Truncated(power));
                    return false;
                }
            }
        }
        true
    }

    /// At the surface point `exit` of a branch travelling along `direction`: the part that
    /// leaves is booked as escaped; the internally reflected part (totally beyond the
    /// critical angle) goes on as a new branch, unless it has bounced too often or is too
    /// weak (booked as truncated). `carried.shape` is returned to `pool` where it ends.
    #[inline(always)]
    pub(super) fn leave_or_reflect<const ROULETTE: bool>(
        &self,
        ray: (Vec3, Vec3),
        carried: Carried,
        bounces: u32,
        pool: &mut Vec<Vec<f32>>,
        budget: &mut Budget,
    ) -> Option<Branch> {
        let (exit, direction) = ray;
        let normal = self.ellipsoid.normal(exit);
        let fresnel = fresnel_dielectric(direction.dot(normal), self.n_eff, 1.0);
        let Carried {
            shape,
            scale,
            power,
        } = carried;
        budget
            .ledger
            .book(Booking::Escaped(power * (1.0 - fresnel)));
        let inner = power * fresnel;
        if fresnel <= 0.0 {
            pool.push(shape);
            return None;
        }
        let boost = (bounces < MAX_SURFACE_BOUNCES)
            .then(|| Self::carry_on::<ROULETTE>(inner, budget.threshold, budget.rng))
            .flatten();
        let Some(boost) = boost else {
            budget.ledger.book(Booking::Truncated(inner));
            pool.push(shape);
            return None;
        };
        if ROULETTE {
            budget.ledger.book(Booking::Raised {
                before: inner,
                after: inner * boost,
            });
        }
        Some(Branch {
            origin: exit,
            direction: reflect(direction, normal),
            shape,
            scale: scale * fresnel * boost,
            power: inner * boost,
            bounces: bounces + 1,
            lobe: SCATTERED,
        })
    }

    /// The Bragg-reflected branch `reflected` leaving the middle of the cell `[t_enter,
    /// t_exit]` of `ray` by the patch's `normal`.
    #[inline(always)]
    pub(super) fn reflected_branch(
        ray: &Ray,
        (t_enter, t_exit): (f32, f32),
        normal: Vec3,
        (shape, scale, power): Reflected,
        bounces: u32,
    ) -> Branch {
        Branch {
            origin: ray.at(0.5 * (t_enter + t_exit)),
            direction: reflect(ray.direction, normal),
            shape,
            scale,
            power,
            bounces,
            lobe: SCATTERED,
        }
    }
}

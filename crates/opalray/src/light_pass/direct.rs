//! The direct light, computed per cell without rays: for every inside cell, the one refracted
//! path from the light to the cell's centre, and the light's spectrum filtered by every
//! cluster and void it crosses on the way.
//!
//! A collimated beam refracted at a locally flat surface element carries, perpendicular to
//! its new direction, the irradiance `E · (1 − F) · cos θᵢ / cos θₜ` (the element's power
//! `E cos θᵢ dA`, less the Fresnel part, through the cross-section `cos θₜ dA`), and the
//! fluence of a collimated beam is that irradiance. This is what the track-length estimate of
//! the light-pass rays converges to for the direct lobe (less the focusing by the surface's
//! curvature, which a flat element ignores), but exact at every cell: no ray-lattice noise.
//! The rays still run the direct path, for the light they scatter, but store none of it.

use glam::Vec3;
use rayon::prelude::*;

use super::walk::Walker;
use super::NO_SLOT;
use crate::geometry::{fresnel_dielectric, refract, Ray};
use crate::structure::Cell;

/// Fixed-point iterations of the entry point; the refracted direction changes by less than
/// 10⁻⁶ after a few on a smooth stone.
const ENTRY_ITERATIONS: usize = 8;

impl Walker<'_> {
    /// Where the light that reaches `target` straight (refracted once) enters the stone:
    /// `(entry point, refracted direction, irradiance across the beam inside)`, or `None`
    /// where the surface facing the light does not see `target`.
    fn entry(&self, target: Vec3) -> Option<(Vec3, Vec3, f32)> {
        // Start from the unrefracted line to the light, then move the entry point until the
        // refracted direction at it points at the target.
        let mut d = -self.source.direction_to_light(target);
        let mut found = None;
        for _ in 0..ENTRY_ITERATIONS {
            let back = Ray::new(target, -d);
            let (_, t_far) = self.shape.intersect(&back)?;
            let p = back.at(t_far.max(0.0));
            let normal = self.shape.normal(p);
            let incoming = -self.source.direction_to_light(p);
            let cos_i = -incoming.dot(normal);
            if cos_i <= 0.0 {
                return None;
            }
            let refracted = refract(incoming, normal, 1.0, self.n_eff)?;
            let converged = (refracted - d).length_squared() < 1e-12;
            d = refracted;
            found = Some((p, normal, cos_i));
            if converged {
                break;
            }
        }
        let (p, normal, cos_i) = found?;
        let cos_t = -d.dot(normal);
        if cos_t <= 0.0 {
            return None;
        }
        let fresnel = fresnel_dielectric(cos_i, 1.0, self.n_eff);
        let irradiance = self.source.irradiance_at(p) * (1.0 - fresnel) * cos_i / cos_t;
        Some((p, d, irradiance))
    }

    /// The direct light of the cell `cell` (centre `centre`): its fluence spectrum is written
    /// into `out` (power per mm² per nm) and its direction of travel returned; both zero where
    /// no direct light arrives.
    fn direct_at(&self, cell: usize, centre: Vec3, out: &mut [f32]) -> Vec3 {
        out.fill(0.0);
        let Some((p, d, irradiance)) = self.entry(centre) else {
            return Vec3::ZERO;
        };
        for (o, s) in out.iter_mut().zip(self.spectrum) {
            *o = s * irradiance;
        }
        let ray = Ray::new(p, d);
        let reach = (centre - p).length() + self.grid.cell.length();
        self.grid.traverse(&ray, 0.0, reach, |seg| {
            let length = seg.t_exit - seg.t_enter;
            let own = seg.index == cell;
            match self.cells[seg.index] {
                Cell::Outside => {}
                Cell::Void => {
                    let sigma = self.body_extinction_per_mm;
                    let kept = (-sigma * length).exp();
                    // In its own cell, the mean over the chord, ∫₀ˡ e^(−σs) ds / ℓ; before
                    // it, what passes the whole chord.
                    let factor = if !own {
                        kept
                    } else if sigma * length > 1e-4 {
                        (1.0 - kept) / (sigma * length)
                    } else {
                        1.0
                    };
                    out.iter_mut().for_each(|s| *s *= factor);
                }
                // The light crossing a cluster is what reaches it; it is split only on leaving.
                Cell::Cluster if own => {}
                Cell::Cluster => {
                    self.optics
                        .transmit(d.dot(self.normals[seg.index]).abs(), out);
                }
            }
            !own
        });
        d
    }

    /// Write the direct light of every slot into `sums` (`slots × LOBES × stride` values,
    /// lobe 0; each entry's spectrum, then its direction and weight), replacing what was
    /// there.
    pub(crate) fn fill_direct(&self, sums: &mut [f32], stride: usize, lobes: usize) {
        let bins = self.spectrum.len();
        let [nx, ny, _] = self.grid.n;
        // Slots are numbered in cell order.
        let cells: Vec<usize> = (0..self.slot_of_cell.len())
            .filter(|&c| self.slot_of_cell[c] != NO_SLOT)
            .collect();
        sums.par_chunks_mut(stride * lobes)
            .zip(cells.par_iter())
            .for_each(|(entry, &cell)| {
                let centre = self
                    .grid
                    .cell_center(cell % nx, cell / nx % ny, cell / (nx * ny));
                let (spectrum, rest) = entry[..stride].split_at_mut(bins);
                let direction = self.direct_at(cell, centre, spectrum);
                // Direction sums with a unit weight: one exact direction (ρ = 1).
                rest[..3].copy_from_slice(&direction.to_array());
                rest[3] = direction.length();
            });
    }
}

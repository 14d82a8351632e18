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

use super::interaction::Transmission;
use super::walk::Walker;
use super::NO_PATCH;
use crate::geometry::{refracted_entry, Ray};
use crate::structure::Cell;

/// The light's spectrum as `top × shape`, the shape's maximum 1 at bin `peak`: where every
/// cell's direct light starts, formed once.
struct UnitSpectrum {
    shape: Vec<f32>,
    peak: usize,
    top: f32,
}

impl UnitSpectrum {
    fn new(spectrum: &[f32]) -> Self {
        let (peak, top) =
            spectrum.iter().enumerate().fold(
                (0, 0.0f32),
                |(a, m), (k, &v)| if v > m { (k, v) } else { (a, m) },
            );
        let mut shape: Vec<f32> = spectrum.iter().map(|&s| s / top).collect();
        if top > 0.0 {
            shape[peak] = 1.0;
        }
        UnitSpectrum { shape, peak, top }
    }
}

impl Walker<'_> {
    /// [`refracted_entry`] for this walker's stone and light.
    #[inline(always)]
    fn entry(&self, target: Vec3, guess: Option<Vec3>) -> Option<(Vec3, Vec3, f32)> {
        refracted_entry(&self.ellipsoid, &self.source, self.n_eff, target, guess)
    }

    /// The direct light of the cell `cell` (centre `centre`): its fluence spectrum is written
    /// into `out` (power per mm² per nm) and its direction of travel returned; both zero where
    /// no direct light arrives. `guess` as for [`Walker::entry`]; `light` is the light's
    /// spectrum, formed once for all cells.
    #[inline(always)]
    fn direct_at(
        &self,
        cell: usize,
        centre: Vec3,
        out: &mut [f32],
        guess: Option<Vec3>,
        light: &UnitSpectrum,
        transmission: &mut Transmission,
    ) -> Vec3 {
        out.fill(0.0);
        let Some((p, d, irradiance)) = self.entry(centre, guess) else {
            return Vec3::ZERO;
        };
        if light.top <= 0.0 {
            return Vec3::ZERO;
        }
        // The spectrum is kept as `scale × out`: filters flat in wavelength change the scale
        // only, a Bragg line the bins of its window.
        out.copy_from_slice(&light.shape);
        let mut peak = light.peak;
        let mut scale = irradiance * light.top;
        let ray = Ray::new(p, d);
        let mut last_patch = NO_PATCH;
        let reach = (centre - p).length() + self.grid.cell.length();
        self.grid.traverse(
            &ray,
            0.0,
            reach,
            #[inline(always)]
            |seg| {
                let length = seg.t_exit - seg.t_enter;
                let own = seg.index == cell;
                let site = self.sites[seg.index];
                match site.cell() {
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
                        scale *= factor;
                    }
                    // The light crossing a cluster is what reaches it; it is split only on leaving.
                    Cell::Cluster if own => {}
                    Cell::Cluster => {
                        // Cells of one patch, met one after another, share the transmittance.
                        if site.patch() != last_patch {
                            last_patch = site.patch();
                            let normal = self.patch_normals[last_patch as usize];
                            self.optics.transmission(d.dot(normal).abs(), transmission);
                        }
                        scale *= transmission.apply(out, &mut peak);
                    }
                }
                !own
            },
        );
        out.iter_mut().for_each(|s| *s *= scale);
        d
    }

    /// Write the direct light of every slot into `sums` (`slots × LOBES × stride` values,
    /// lobe 0; each entry's spectrum, then its direction and weight), replacing what was
    /// there.
    pub(crate) fn fill_direct(&self, sums: &mut [f32], stride: usize, lobes: usize) {
        let light = UnitSpectrum::new(self.spectrum);
        // Runs of consecutive cells (mostly along x): each cell's entry search starts from
        // the direction found for the one before, or, after two neighbours in its row, from
        // the line through their directions: a few iterations fewer.
        const RUN: usize = 64;
        sums.par_chunks_mut(stride * lobes * RUN)
            .zip(self.cell_of_slot.par_chunks(RUN))
            .for_each(|(entries, cells)| {
                // Each run in the copy compiled for the processor's vector level (`simd`).
                crate::simd::widest(
                    #[inline(always)]
                    || self.direct_run(entries, cells, stride, lobes, &light),
                )
            });
    }

    /// [`Walker::fill_direct`] for one run of consecutive `cells`, whose entries are
    /// `entries` (`lobes × stride` values each).
    #[inline(always)]
    fn direct_run(
        &self,
        entries: &mut [f32],
        cells: &[usize],
        stride: usize,
        lobes: usize,
        light: &UnitSpectrum,
    ) {
        let bins = self.spectrum.len();
        let [nx, ny, _] = self.grid.n;
        // The directions found for the last two cells, with those cells.
        let mut last: [Option<(usize, Vec3)>; 2] = [None, None];
        let mut transmission = Transmission::default();
        for (values, &cell) in entries.chunks_exact_mut(stride * lobes).zip(cells) {
            let centre = self
                .grid
                .cell_center(cell % nx, cell / nx % ny, cell / (nx * ny));
            let (spectrum, rest) = values[..stride].split_at_mut(bins);
            let guess = match last {
                // Two cells just before this one in its row: extrapolate.
                [Some((c0, d0)), Some((c1, d1))]
                    if c1 + 1 == cell && c0 + 2 == cell && cell % nx >= 2 =>
                {
                    Some((2.0 * d1 - d0).normalize())
                }
                [_, Some((_, d1))] => Some(d1),
                _ => None,
            };
            let direction = self.direct_at(cell, centre, spectrum, guess, light, &mut transmission);
            last = [
                last[1],
                (direction != Vec3::ZERO).then_some((cell, direction)),
            ];
            // Direction sums with a unit weight: one exact direction (ρ = 1).
            rest[..3].copy_from_slice(&direction.to_array());
            rest[3] = direction.length();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{Ellipsoid, LightSource};

    #[test]
    fn the_entry_point_refracts_the_light_onto_the_target() {
        // The paper's stone under light at 30°: for targets throughout it, the solved path
        // must obey Snell's law at its entry point and pass through the target.
        let shape = Ellipsoid::new(Vec3::new(10.0, 7.5, 2.5));
        let n_eff = 1.43;
        let angle = 30f32.to_radians();
        let source = LightSource::Directional {
            direction: Vec3::new(angle.sin(), 0.0, -angle.cos()),
        };
        let (mut inside, mut solved, mut guess) = (0, 0, None);
        for k in 0..40_000 {
            let u = Vec3::new(
                (k % 50) as f32 / 49.0 * 2.0 - 1.0,
                (k / 50 % 40) as f32 / 39.0 * 2.0 - 1.0,
                (k / 2000) as f32 / 19.0 * 2.0 - 1.0,
            );
            let target = u * shape.semi_axes() * 0.999;
            if !shape.contains(target) {
                continue;
            }
            inside += 1;
            let Some((p, d, irradiance)) = refracted_entry(&shape, &source, n_eff, target, guess)
            else {
                continue;
            };
            guess = Some(d);
            // Snell: the refracted direction of the incoming light at p.
            let normal = shape.normal(p);
            let incoming = -source.direction_to_light(p);
            let sin_i = incoming.cross(normal).length();
            let sin_t = d.cross(normal).length();
            let snell = (sin_i - n_eff * sin_t).abs();
            // The target on the line p + t·d.
            let miss = (target - p).cross(d).length();
            assert!(irradiance > 0.0 && irradiance.is_finite());
            if snell < 1e-4 && miss < 1e-3 {
                solved += 1;
            }
        }
        let share = solved as f64 / inside as f64;
        assert!(share > 0.97, "{solved} of {inside} targets reached");
    }
}

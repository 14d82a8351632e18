//! The eye-independent half of eq. (2), computed once per light: for each cluster and stored
//! lobe, the Bragg-reflected spectrum and its direction; for each cell, its diffuse glow.

use glam::Vec3;
use rayon::prelude::*;

use crate::light_pass::{LightField, LOBES};
use crate::optics::OpticsTables;
use crate::structure::{Cell, Structure};

/// Stored light meeting the planes more obliquely than this (|cos θ| below it, θ > 80°) adds
/// no specular term: near grazing incidence the stack's reflection turns the light by under
/// 20°, a near-forward deflection that a Phong lobe about the mirror direction cannot
/// represent (and the evanescent regime past 85.6° would show as white specks).
const MIN_SPECULAR_COS: f32 = 0.173_648_18; // cos 80°

/// Per-slot shading terms, in units where a white Lambertian diffuser under unit irradiance
/// has the light's spectrum (π × radiance).
#[derive(Clone, Debug)]
pub struct Shading {
    /// Bins per spectrum.
    pub bins: usize,
    /// Specular spectra `slots × LOBES × bins`: E · R(θ) · (n + 2) / 2, the peak of the
    /// normalised Phong lobe `(n + 2)/(2π) cosⁿ θ'` times π.
    pub specular: Vec<f32>,
    /// Direction of the Bragg-reflected light per slot and lobe (zero: nothing stored).
    pub mirror: Vec<Vec3>,
    /// Phong exponent per slot and lobe, widened from `n` by the spread of the stored
    /// light's directions (Toksvig 2005): `n' = ρ n / (ρ + n (1 − ρ))`, ρ the mean resultant
    /// length. Light stored from one direction keeps `n`; light mixed from many directions
    /// reflects into a broad, dim lobe instead of a spurious sharp one.
    pub exponent: Vec<f32>,
    /// Diffuse spectra `slots × bins`: clusters Σ E · D(θ) · cos θ (eq. 2's first sum);
    /// voids the potch's single scattering a · Σ E / 4, to be weighted by the fraction of
    /// the view ray the void intercepts.
    pub diffuse: Vec<f32>,
}

impl Shading {
    /// Shade every stored slot of `light`.
    pub fn new(
        structure: &Structure,
        optics: &OpticsTables,
        light: &LightField,
        phong_exponent: f32,
        body_albedo: f32,
    ) -> Self {
        let bins = light.grid.bins;
        let slots = light.directions.len() / LOBES;
        let mut cell_of_slot = vec![0usize; slots];
        for (cell, &slot) in light.slot_of_cell.iter().enumerate() {
            if slot != crate::light_pass::NO_SLOT {
                cell_of_slot[slot as usize] = cell;
            }
        }
        let mut specular = vec![0.0f32; slots * LOBES * bins];
        let mut mirror = vec![Vec3::ZERO; slots * LOBES];
        let mut exponent = vec![phong_exponent; slots * LOBES];
        let mut diffuse = vec![0.0f32; slots * bins];
        specular
            .par_chunks_mut(LOBES * bins)
            .zip(
                mirror
                    .par_chunks_mut(LOBES)
                    .zip(exponent.par_chunks_mut(LOBES)),
            )
            .zip(diffuse.par_chunks_mut(bins))
            .enumerate()
            .for_each_init(
                || (vec![0.0f32; bins], vec![0.0f32; bins], vec![0.0f32; bins]),
                |(r, t, d), (slot, ((spec, (mir, exp)), diff))| {
                    let cell = cell_of_slot[slot];
                    match structure.cells[cell] {
                        Cell::Cluster => {
                            let normal = structure.normal(cell);
                            for lobe in 0..LOBES {
                                let w = light.directions[slot * LOBES + lobe];
                                if w == Vec3::ZERO {
                                    continue;
                                }
                                let e = light.fluence(slot, lobe);
                                let cos = w.dot(normal).abs();
                                optics.lookup(cos, r, t, d);
                                for ((g, &e), &d) in diff.iter_mut().zip(e).zip(d.iter()) {
                                    *g += e * d * cos;
                                }
                                if cos < MIN_SPECULAR_COS {
                                    continue;
                                }
                                mir[lobe] = crate::geometry::reflect(w, normal);
                                let rho = light.concentration[slot * LOBES + lobe];
                                let n = phong_exponent;
                                exp[lobe] =
                                    rho * n / (rho + n * (1.0 - rho)).max(f32::MIN_POSITIVE);
                                let peak = 0.5 * (exp[lobe] + 2.0);
                                let out = &mut spec[lobe * bins..(lobe + 1) * bins];
                                for ((o, &e), &r) in out.iter_mut().zip(e).zip(r.iter()) {
                                    *o = e * r * peak;
                                }
                            }
                        }
                        Cell::Void => {
                            for lobe in 0..LOBES {
                                let e = light.fluence(slot, lobe);
                                for b in 0..bins {
                                    diff[b] += 0.25 * body_albedo * e[b];
                                }
                            }
                        }
                        Cell::Outside => {}
                    }
                },
            );
        Shading {
            bins,
            specular,
            mirror,
            exponent,
            diffuse,
        }
    }
}

//! The eye-independent half of eq. (2), computed once per light: for each cluster and stored
//! lobe, the Bragg-reflected spectrum and its direction; for each cell, its diffuse glow.

use glam::Vec3;
use rayon::prelude::*;

use crate::light_pass::{LightField, LOBES};
use crate::optics::OpticsTables;
use crate::structure::{Cell, Structure};

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
        let mut diffuse = vec![0.0f32; slots * bins];
        let peak = 0.5 * (phong_exponent + 2.0);
        specular
            .par_chunks_mut(LOBES * bins)
            .zip(mirror.par_chunks_mut(LOBES))
            .zip(diffuse.par_chunks_mut(bins))
            .enumerate()
            .for_each_init(
                || (vec![0.0f32; bins], vec![0.0f32; bins], vec![0.0f32; bins]),
                |(r, t, d), (slot, ((spec, mir), diff))| {
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
                                mir[lobe] = crate::geometry::reflect(w, normal);
                                let out = &mut spec[lobe * bins..(lobe + 1) * bins];
                                for b in 0..bins {
                                    out[b] = e[b] * r[b] * peak;
                                    diff[b] += e[b] * d[b] * cos;
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
            diffuse,
        }
    }
}

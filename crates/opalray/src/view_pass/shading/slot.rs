//! One stored slot shaded: a cluster's glow (eq. 2's first sum, `Σ E · D(θ) · cos θ`) and the
//! specular spectra `E · R(θ) · peak` of its lobes; a void's single scattering `a · Σ E / 4`.

use glam::Vec3;

use super::{ClusterShade, GLOW_FLOOR};
use crate::light_pass::{ClusterOptics, LightField, LOBES};
use crate::structure::Cell;

/// One stored slot as the shading reads it.
#[derive(Clone, Copy)]
pub(super) struct Slot {
    /// Its index in the light's slots.
    pub(super) index: usize,
    /// Its cell: a cluster or a void.
    pub(super) cell: Cell,
    /// The cell's (111) normal (a cluster's).
    pub(super) normal: Vec3,
}

/// What every slot is shaded from: the clusters' optics, the stored light and the body's
/// albedo (voids).
pub(super) struct ShadeSources<'a> {
    /// The clusters' optics.
    pub(super) optics: &'a ClusterOptics<'a>,
    /// The stored light.
    pub(super) light: &'a LightField,
    /// The body's single-scattering albedo (voids).
    pub(super) body_albedo: f32,
}

/// The glow of `at` into `glow`, and the specular spectra of its lobes that have one, each
/// into the next chunk of `spec`; `d` is scratch space of `bins` values.
#[inline(always)]
pub(super) fn shade_slot<'s>(
    at: Slot,
    shade: &ClusterShade,
    stored: &ShadeSources,
    glow: &mut [f32],
    spec: &mut impl Iterator<Item = &'s mut [f32]>,
    d: &mut [f32],
) {
    let ShadeSources {
        optics,
        light,
        body_albedo,
    } = *stored;
    let (slot, normal) = (at.index, at.normal);
    match at.cell {
        Cell::Cluster => {
            for (lobe, l) in shade.lobes.iter().enumerate() {
                let w = light.directions[slot * LOBES + lobe];
                if w == Vec3::ZERO {
                    continue;
                }
                let e = light.fluence(slot, lobe);
                let cos = w.dot(normal).abs();
                match optics.diffuse(cos, d) {
                    // Flat rows: away from the stop band D is about 10⁻⁵.
                    Some(d) if d * cos < GLOW_FLOOR => {}
                    Some(d) => {
                        for (g, &e) in glow.iter_mut().zip(e) {
                            *g += e * d * cos;
                        }
                    }
                    None => {
                        for ((g, &e), &d) in glow.iter_mut().zip(e).zip(d.iter()) {
                            *g += e * d * cos;
                        }
                    }
                }
                if !l.has_spectrum() {
                    continue;
                }
                let peak = 0.5 * (l.exponent + 2.0);
                let spec = spec
                    .next()
                    .expect("a packed spectrum per lobe that has one");
                // `d` is free again: it takes the reflectance.
                match optics.reflectance(cos, d) {
                    Some(r) => {
                        for (s, &e) in spec.iter_mut().zip(e) {
                            *s = e * r * peak;
                        }
                    }
                    None => {
                        for ((s, &e), &r) in spec.iter_mut().zip(e).zip(d.iter()) {
                            *s = e * r * peak;
                        }
                    }
                }
            }
        }
        Cell::Void => {
            for lobe in 0..LOBES {
                let e = light.fluence(slot, lobe);
                for (g, &e) in glow.iter_mut().zip(e) {
                    *g += 0.25 * body_albedo * e;
                }
            }
        }
        Cell::Outside => {}
    }
}

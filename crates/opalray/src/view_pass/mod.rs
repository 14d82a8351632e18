//! View pass (paper §3.3, fig. 7): rays from the camera, shaded from the stored light.
//!
//! Input: the structure, optics, the [`LightField`] and a camera → output: a
//! [`SpectralImage`]. Each camera ray meets the stone (Fresnel: the gloss of the light and a
//! refracted ray), walks the cells, and at each cluster adds eq. (2),
//! `I = Σ I_kd cos θ + Σ I_sp cosⁿ θ'`, with the cluster's spectral reflectance, while its own
//! spectrum is filtered by the cluster's transmittance. Voids hold potch that absorbs and
//! scatters by the body tone. At the far surface the ray sees the backdrop through the stone
//! and reflects internally.

mod shading;

pub use shading::{Lobe, Shading, LOBE_CUTOFF};

use rayon::prelude::*;

use crate::geometry::{fresnel_dielectric, reflect, refract, Camera, Ray};
use crate::light_pass::{stone_geometry, ClusterOptics, LightField, LightSource, LOBES};
use crate::optics::OpticsTables;
use crate::spectrum::SpectralImage;
use crate::structure::{Cell, Structure};

/// Exponent of the polished surface's Blinn–Phong highlight.
const GLOSS_EXPONENT: f32 = 3000.0;
/// Internal reflections followed per camera ray.
const MAX_VIEW_BOUNCES: u32 = 4;
/// The camera ray stops once its throughput falls below this at every wavelength: what lies
/// behind would change the default image by 0.45 % RMS (measured against 10⁻³).
const MIN_THROUGHPUT: f32 = 4e-3;

/// Camera, light and look of the view pass, all in the opal's frame.
#[derive(Clone, Debug)]
pub struct ViewSetup<'a> {
    /// The camera.
    pub camera: Camera,
    /// Image width, pixels.
    pub width: usize,
    /// Image height, pixels.
    pub height: usize,
    /// The light (for the surface gloss).
    pub source: LightSource,
    /// The light's spectrum per bin (irradiance 1 ↔ luminance 1).
    pub light_spectrum: &'a [f32],
    /// Phong exponent `n` of eq. (2).
    pub phong_exponent: f32,
    /// Scale of the surface gloss.
    pub gloss: f32,
    /// Backdrop reflectance (grey).
    pub background: f32,
    /// Extinction of the potch in voids, per mm.
    pub body_extinction_per_mm: f32,
}

/// Render the spectral image (paper §3.3).
pub fn trace_view(
    structure: &Structure,
    optics: &OpticsTables,
    light: &LightField,
    shading: &Shading,
    setup: &ViewSetup,
) -> SpectralImage {
    let (shape, grid) = stone_geometry(structure);
    let cluster_optics = ClusterOptics::new(optics);
    let bins = light.grid.bins;
    let n_eff = optics.n_eff as f32;
    let mut image = SpectralImage::new(setup.width, setup.height, light.grid);
    image
        .data
        .par_chunks_mut(setup.width * bins)
        .enumerate()
        .for_each_init(
            || (vec![0.0f32; bins], vec![0.0f32; bins], vec![0.0f32; bins]),
            |(thr, t, r), (y, row)| {
                for (x, pixel) in row.chunks_exact_mut(bins).enumerate() {
                    let ray = setup.camera.ray(x as f32 + 0.5, y as f32 + 0.5);
                    let Some((t_hit, _)) = shape.intersect(&ray).filter(|h| h.0 > 0.0) else {
                        for (p, s) in pixel.iter_mut().zip(setup.light_spectrum) {
                            *p = setup.background * s;
                        }
                        continue;
                    };
                    // Surface: the gloss of the light, and the refracted ray.
                    let p = ray.at(t_hit);
                    let normal = shape.normal(p);
                    let to_eye = -ray.direction;
                    let fresnel = fresnel_dielectric(to_eye.dot(normal), 1.0, n_eff);
                    let to_light = setup.source.direction_to_light(p);
                    let cos_l = to_light.dot(normal);
                    let mut glint = 0.0;
                    if cos_l > 0.0 && setup.gloss > 0.0 {
                        let h = (to_light + to_eye).normalize();
                        glint = setup.gloss
                            * fresnel_dielectric(h.dot(to_light), 1.0, n_eff)
                            * setup.source.irradiance_at(p)
                            * cos_l
                            * (GLOSS_EXPONENT + 8.0)
                            / 8.0
                            * normal.dot(h).max(0.0).powf(GLOSS_EXPONENT);
                    }
                    for (px, s) in pixel.iter_mut().zip(setup.light_spectrum) {
                        *px = glint * s;
                    }
                    let Some(mut dir) = refract(ray.direction, normal, 1.0, n_eff) else {
                        continue;
                    };
                    // Radiance leaving the stone is scaled by (1 − F) / n² (étendue).
                    thr.fill((1.0 - fresnel) / (n_eff * n_eff));
                    let mut origin = p;
                    for _ in 0..MAX_VIEW_BOUNCES {
                        let inner = Ray {
                            origin,
                            direction: dir,
                        };
                        let Some((t0, t1)) = shape.intersect(&inner) else {
                            break;
                        };
                        let to_eye = -dir;
                        let mut live = true;
                        grid.traverse(&inner, t0.max(0.0), t1, |seg| {
                            let slot = light.slot_of_cell[seg.index] as usize;
                            match structure.cells[seg.index] {
                                Cell::Outside => return true,
                                Cell::Void => {
                                    let kept = (-setup.body_extinction_per_mm
                                        * (seg.t_exit - seg.t_enter))
                                        .exp();
                                    let glow = &shading.diffuse[slot * bins..(slot + 1) * bins];
                                    let seen = 1.0 - kept;
                                    for ((p, t), g) in
                                        pixel.iter_mut().zip(thr.iter_mut()).zip(glow)
                                    {
                                        *p += *t * g * seen;
                                        *t *= kept;
                                    }
                                }
                                Cell::Cluster => {
                                    for lobe in 0..LOBES {
                                        let l = shading.lobes[slot * LOBES + lobe];
                                        let c = l.mirror.dot(to_eye);
                                        if c <= l.cos_min {
                                            continue;
                                        }
                                        // Eq. (2)'s specular term: E · R(θ) · cosⁿ' θ'.
                                        let k = l.peak * c.powf(l.exponent);
                                        let e = light.fluence(slot, lobe);
                                        match cluster_optics.reflectance(l.cos_incidence, r) {
                                            Some(r) => {
                                                let k = k * r;
                                                for ((p, t), e) in
                                                    pixel.iter_mut().zip(thr.iter()).zip(e)
                                                {
                                                    *p += *t * e * k;
                                                }
                                            }
                                            None => {
                                                for (((p, t), e), r) in pixel
                                                    .iter_mut()
                                                    .zip(thr.iter())
                                                    .zip(e)
                                                    .zip(r.iter())
                                                {
                                                    *p += *t * e * r * k;
                                                }
                                            }
                                        }
                                    }
                                    if shading.glows[slot] {
                                        let glow = &shading.diffuse[slot * bins..(slot + 1) * bins];
                                        for ((p, t), g) in
                                            pixel.iter_mut().zip(thr.iter()).zip(glow)
                                        {
                                            *p += *t * g;
                                        }
                                    }
                                    let normal = shading.normals[slot];
                                    match cluster_optics.transmittance(dir.dot(normal).abs(), t) {
                                        Some(t) => thr.iter_mut().for_each(|v| *v *= t),
                                        None => {
                                            thr.iter_mut().zip(t.iter()).for_each(|(v, t)| *v *= t)
                                        }
                                    }
                                }
                            }
                            live = thr.iter().any(|&v| v > MIN_THROUGHPUT);
                            live
                        });
                        if !live {
                            break;
                        }
                        // Far surface: the backdrop through the stone, and internal reflection.
                        let q = inner.at(t1);
                        let n_q = shape.normal(q);
                        let f_out = fresnel_dielectric(dir.dot(n_q), n_eff, 1.0);
                        let seen = (1.0 - f_out) * n_eff * n_eff * setup.background;
                        for ((p, t), l) in pixel
                            .iter_mut()
                            .zip(thr.iter_mut())
                            .zip(setup.light_spectrum)
                        {
                            *p += *t * seen * l;
                            *t *= f_out;
                        }
                        dir = reflect(dir, n_q);
                        origin = q;
                        if !thr.iter().any(|&v| v > MIN_THROUGHPUT) {
                            break;
                        }
                    }
                }
            },
        );
    image
}

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

use glam::Vec3;
use rayon::prelude::*;

use crate::geometry::{fresnel_dielectric, reflect, refract, Camera, CellGrid, Ellipsoid, Ray};
use crate::light_pass::{
    stone_geometry, ClusterOptics, LightField, LightSource, Transmission, LOBES,
};
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
    let ctx = View {
        structure,
        light,
        shading,
        setup,
        shape,
        grid,
        optics: cluster_optics,
        bins,
        n_eff,
    };
    let mut image = SpectralImage::new(setup.width, setup.height, light.grid);
    image
        .data
        .par_chunks_mut(setup.width * bins)
        .enumerate()
        .for_each_init(
            || (vec![0.0f32; bins], Transmission::default()),
            |(shape_thr, transmission), (y, row)| {
                for (x, pixel) in row.chunks_exact_mut(bins).enumerate() {
                    ctx.shade_pixel(x, y, pixel, shape_thr, transmission);
                }
            },
        );
    image
}

/// Everything a camera ray needs, shared by all threads.
struct View<'a> {
    structure: &'a Structure,
    light: &'a LightField,
    shading: &'a Shading,
    setup: &'a ViewSetup<'a>,
    shape: Ellipsoid,
    grid: CellGrid,
    optics: ClusterOptics<'a>,
    bins: usize,
    n_eff: f32,
}

impl View<'_> {
    /// The spectrum seen through pixel `(x, y)`, written into `pixel`; `shape_thr` and
    /// `transmission` are scratch space for the shape of the ray's throughput and a cluster's
    /// transmittance. (Not inlined: one call per pixel costs nothing, and profiles can tell
    /// the view pass apart.)
    #[inline(never)]
    fn shade_pixel(
        &self,
        x: usize,
        y: usize,
        pixel: &mut [f32],
        shape_thr: &mut [f32],
        transmission: &mut Transmission,
    ) {
        let ray = self.setup.camera.ray(x as f32 + 0.5, y as f32 + 0.5);
        let Some((t_hit, _)) = self.shape.intersect(&ray).filter(|h| h.0 > 0.0) else {
            for (p, s) in pixel.iter_mut().zip(self.setup.light_spectrum) {
                *p = self.setup.background * s;
            }
            return;
        };
        // Surface: the gloss of the light, and the refracted ray.
        let p = ray.at(t_hit);
        let normal = self.shape.normal(p);
        let to_eye = -ray.direction;
        let fresnel = fresnel_dielectric(to_eye.dot(normal), 1.0, self.n_eff);
        let to_light = self.setup.source.direction_to_light(p);
        let cos_l = to_light.dot(normal);
        let mut glint = 0.0;
        if cos_l > 0.0 && self.setup.gloss > 0.0 {
            let h = (to_light + to_eye).normalize();
            glint = self.setup.gloss
                * fresnel_dielectric(h.dot(to_light), 1.0, self.n_eff)
                * self.setup.source.irradiance_at(p)
                * cos_l
                * (GLOSS_EXPONENT + 8.0)
                / 8.0
                * normal.dot(h).max(0.0).powf(GLOSS_EXPONENT);
        }
        for (px, s) in pixel.iter_mut().zip(self.setup.light_spectrum) {
            *px = glint * s;
        }
        let Some(mut dir) = refract(ray.direction, normal, 1.0, self.n_eff) else {
            return;
        };
        // Radiance leaving the stone is scaled by (1 − F) / n² (étendue). The ray's throughput
        // is `scale × shape`: filters flat in wavelength (most clusters, voids, the surface)
        // change only the scale; the shape changes only in the bins of a Bragg line, and is
        // kept at a maximum of 1, so the ray lives while `scale` exceeds MIN_THROUGHPUT.
        let mut scale = (1.0 - fresnel) / (self.n_eff * self.n_eff);
        shape_thr.fill(1.0);
        let mut peak = 0;
        let mut origin = p;
        for _ in 0..MAX_VIEW_BOUNCES {
            let inner = Ray {
                origin,
                direction: dir,
            };
            let Some((t0, t1)) = self.shape.intersect(&inner) else {
                break;
            };
            let to_eye = -dir;
            // Along one segment, cells of one patch meet the ray at the same angle and share
            // their transmittance.
            let mut last_normal = Vec3::NAN;
            self.grid.traverse(&inner, t0.max(0.0), t1, |seg| {
                let slot = self.light.slot_of_cell[seg.index] as usize;
                match self.structure.cells[seg.index] {
                    Cell::Outside => return true,
                    Cell::Void => {
                        let kept =
                            (-self.setup.body_extinction_per_mm * (seg.t_exit - seg.t_enter)).exp();
                        let glow = &self.shading.diffuse[slot * self.bins..(slot + 1) * self.bins];
                        add_filtered(pixel, shape_thr, glow, scale * (1.0 - kept));
                        scale *= kept;
                    }
                    Cell::Cluster => {
                        for lobe in 0..LOBES {
                            let l = self.shading.lobes[slot * LOBES + lobe];
                            let c = l.mirror.dot(to_eye);
                            if c <= l.cos_min {
                                continue;
                            }
                            // Eq. (2)'s specular term: E · R(θ) · peak · cosⁿ' θ'.
                            let entry = (slot * LOBES + lobe) * self.bins;
                            let spectrum = &self.shading.specular[entry..entry + self.bins];
                            add_filtered(pixel, shape_thr, spectrum, scale * c.powf(l.exponent));
                        }
                        if self.shading.glows[slot] {
                            let glow =
                                &self.shading.diffuse[slot * self.bins..(slot + 1) * self.bins];
                            add_filtered(pixel, shape_thr, glow, scale);
                        }
                        let normal = self.shading.normals[slot];
                        if normal != last_normal {
                            self.optics
                                .transmission(dir.dot(normal).abs(), transmission);
                            last_normal = normal;
                        }
                        scale *= transmission.apply(shape_thr, &mut peak);
                    }
                }
                scale > MIN_THROUGHPUT
            });
            if scale <= MIN_THROUGHPUT {
                break;
            }
            // Far surface: the backdrop through the stone, and internal reflection.
            let q = inner.at(t1);
            let n_q = self.shape.normal(q);
            let f_out = fresnel_dielectric(dir.dot(n_q), self.n_eff, 1.0);
            let seen = (1.0 - f_out) * self.n_eff * self.n_eff * self.setup.background;
            add_filtered(pixel, shape_thr, self.setup.light_spectrum, scale * seen);
            scale *= f_out;
            dir = reflect(dir, n_q);
            origin = q;
            if scale <= MIN_THROUGHPUT {
                break;
            }
        }
    }
}

/// `pixel += k · shape ⊙ spectrum`.
#[inline(always)]
fn add_filtered(pixel: &mut [f32], shape: &[f32], spectrum: &[f32], k: f32) {
    for ((p, s), e) in pixel.iter_mut().zip(shape).zip(spectrum) {
        *p += k * s * e;
    }
}

//! The stored method (`integrator.method = "stored"`): the paper's two passes on the stone
//! model. Light is stored per grid cell of the stone, then gathered from the eye by eq. (2)
//! with each domain's plane families, mosaic lobe and half-vector law: a deterministic,
//! noise-free preview of what the path tracer converges to, less what it finds by two or
//! more scattering events.
//!
//! Input: a [`Stone`] and a [`StoredSetup`] → output: a [`StoredImage`].
//!
//! 1. [`store_light`] ([`light`]): at every cell centre inside the stone, the direction and
//!    irradiance of the light arriving straight from the scene's light (refracted at the
//!    surface, dimmed by the potch on the way) and the Bragg lines of the domains crossed.
//! 2. [`gather_view`] ([`view`]): `spp` camera rays per pixel at stratified positions fixed by
//!    the seed, each refracted in (Fresnel) and walked through the domains; at every crossing
//!    the stored light's single reflection by every line, at every piece of potch its single
//!    scattering, the lines' spectra integrated at fixed wavelengths, never binned before
//!    colour.
//!
//! The gloss shows the backdrop and the light's disc (the path tracer's half-degree disc of a
//! directional or point light; a point of zero size has no mirror image but that disc).
//! Rows are rendered in parallel into pre-sized buffers: the same scene and seed give the
//! same bytes at any thread count.

mod config;
pub mod light;
mod lines;
mod method;
pub mod view;

use rayon::prelude::*;
use serde::Serialize;

use crate::film::SpectralSampler;
use crate::geometry::Camera;
use crate::lights::{Environment, Lamp};
use crate::sampling::{stage, Rng};
use crate::spectrum::SpectralImage;
use crate::stone::Stone;

pub use config::StoredConfig;
pub use light::{Arrival, LightStats, Notch, StoredLight};
pub use lines::Lines;
pub use method::{StoredMethod, MAX_STORED_CELLS};
use view::{Gather, Sums};

/// Everything the stored method needs besides the stone.
pub struct StoredSetup<'a> {
    /// The camera.
    pub camera: Camera,
    /// Image width, pixels.
    pub width: usize,
    /// Image height, pixels.
    pub height: usize,
    /// Camera rays per pixel (1 ..= [`crate::scene::MAX_SPP`]), at stratified positions.
    pub spp: u32,
    /// The scene's light (directional or point) and the radius of its disc in the gloss.
    pub light: Lamp,
    /// The backdrop (`environment.kind = "none"`: `render.background` behind the stone).
    pub environment: &'a Environment,
    /// Scale of the surface's gloss.
    pub gloss: f32,
    /// Seed of the sub-pixel positions.
    pub seed: u64,
    /// Edge of the light's grid cells, mm (`integrator.cell_mm`).
    pub cell_mm: f64,
    /// The light's spectrum and the colour-matching functions.
    pub spectral: &'a SpectralSampler,
}

/// The stored method's image.
pub struct StoredImage {
    /// CIE XYZ per pixel, row-major (Y = 1: a white diffuser under the light).
    pub xyz: Vec<[f32; 3]>,
    /// The spectral image (bin averages).
    pub spectral: SpectralImage,
}

/// What the stored method rendered.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct StoredStats {
    /// Camera rays per pixel.
    pub spp: u32,
    /// The light pass's grid.
    pub light: LightStats,
}

/// The light pass: the scene's light stored on the cells of `stone`.
pub fn store_light(stone: &Stone, setup: &StoredSetup) -> StoredLight {
    let light = &setup.light;
    StoredLight::trace(stone, light.source, light.intensity, setup.cell_mm)
}

/// The view pass: the image of `stone` lit by its stored light `light`.
pub fn gather_view(stone: &Stone, light: &StoredLight, setup: &StoredSetup) -> StoredImage {
    let (w, h) = (setup.width, setup.height);
    let grid = setup.spectral.grid;
    let bins = grid.bins;
    let mut xyz = vec![[0.0f32; 3]; w * h];
    let mut spectral = SpectralImage::new(w, h, grid);
    let spp = setup.spp.max(1) as usize;
    let white_xyz = setup.spectral.white_xyz;
    let white_bins = &setup.spectral.white_bins;
    // A stopped render gathers no more rows (its image is never shown).
    let cancel = crate::cancel::Cancel::current();
    xyz.par_chunks_mut(w)
        .zip(spectral.data.par_chunks_mut(w * bins))
        .enumerate()
        .for_each(|(y, (xyz_row, bins_row))| {
            if cancel.is_cancelled() {
                return;
            }
            let mut gather = Gather::new(stone, light, setup);
            let mut order = vec![0usize; spp];
            for (x, (out, out_bins)) in xyz_row
                .iter_mut()
                .zip(bins_row.chunks_mut(bins))
                .enumerate()
            {
                let pixel = (y * w + x) as u64;
                let mut rng = Rng::new(setup.seed, stage::STORED, pixel);
                // Stratified in x and y at once: sample k in column k, its row shuffled.
                for (k, o) in order.iter_mut().enumerate() {
                    *o = k;
                }
                for k in (1..spp).rev() {
                    order.swap(k, rng.below(k as u64 + 1) as usize);
                }
                let mut sums = Sums {
                    white: 0.0,
                    xyz: [0.0; 3],
                    bins: out_bins,
                };
                for (k, &row) in order.iter().enumerate() {
                    let px = x as f32 + (k as f32 + rng.uniform_f32()) / spp as f32;
                    let py = y as f32 + (row as f32 + rng.uniform_f32()) / spp as f32;
                    gather.sample(setup.camera.ray(px, py), &mut sums);
                }
                gather.finish_pixel(&mut sums);
                let scale = 1.0 / spp as f64;
                for c in 0..3 {
                    out[c] = ((sums.xyz[c] + sums.white * white_xyz[c]) * scale) as f32;
                }
                for (b, wb) in sums.bins.iter_mut().zip(white_bins) {
                    *b = ((f64::from(*b) + sums.white * f64::from(*wb)) * scale) as f32;
                }
            }
        });
    StoredImage { xyz, spectral }
}

/// [`store_light`] then [`gather_view`].
pub fn trace_stored(stone: &Stone, setup: &StoredSetup) -> (StoredImage, StoredStats) {
    let light = store_light(stone, setup);
    let image = gather_view(stone, &light, setup);
    let stats = StoredStats {
        spp: setup.spp,
        light: light.stats(),
    };
    (image, stats)
}

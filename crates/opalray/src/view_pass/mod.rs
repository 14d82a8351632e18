//! View pass (paper §3.3, fig. 7): rays from the camera, shaded from the stored light.
//!
//! Input: the structure, optics, the [`LightField`] and a camera → output: a
//! [`SpectralImage`]. Each camera ray meets the stone (Fresnel: the gloss of the light and a
//! refracted ray), walks the cells, and at each cluster adds eq. (2),
//! `I = Σ I_kd cos θ + Σ I_sp cosⁿ θ'`, with the cluster's spectral reflectance, while its own
//! spectrum is filtered by the cluster's transmittance. Voids hold potch that absorbs and
//! scatters by the body tone. At the far surface the ray sees the backdrop through the stone
//! and reflects internally.

mod config;
mod method;
mod shading;
mod stats;
mod walk;

use walk::{RayBuffers, WalkStart};

pub use config::TwoPassConfig;
pub use method::TwoPass;
pub use shading::{CellTag, ClusterShade, Lobe, Shading, LOBE_CUTOFF};
pub use stats::TwoPassStats;

use glam::Vec3;
use rayon::prelude::*;

use crate::geometry::{fresnel_dielectric, refract, Camera, CellGrid, Ellipsoid};
use crate::light_pass::{voxel_geometry, ClusterOptics, LightField, LightSource, Transmission};
use crate::optics::OpticsTables;
use crate::spectrum::SpectralImage;
use crate::structure::Structure;
use walk::add_filtered;

/// Exponent of the polished surface's Blinn–Phong highlight.
const GLOSS_EXPONENT: f32 = 3000.0;
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
    /// Pixels on a side of the blocks whose weak internal reflections share one ray (1: none
    /// shared).
    pub reflection_block: usize,
}

/// Render the spectral image (paper §3.3).
pub fn trace_view(
    structure: &Structure,
    optics: &OpticsTables,
    light: &LightField,
    shading: &Shading,
    setup: &ViewSetup,
) -> SpectralImage {
    let (ellipsoid, grid) = voxel_geometry(structure);
    let cluster_optics = ClusterOptics::new(optics);
    let bins = light.grid.bins;
    let n_eff = optics.n_eff as f32;
    let ctx = View {
        shading,
        setup,
        ellipsoid,
        grid,
        optics: cluster_optics,
        bins,
        n_eff,
    };
    let block = setup.reflection_block.max(1);
    let mut image = SpectralImage::new(setup.width, setup.height, light.grid);
    // Square tiles of blocks, a strip of tiles per task (see `TILE_BLOCKS`).
    let side = TILE_BLOCKS * block;
    // A stopped pass shades no more strips (its image is never shown).
    let cancel = crate::cancel::Cancel::current();
    image
        .data
        .par_chunks_mut(side * setup.width * bins)
        .enumerate()
        .for_each_init(
            || BlockScratch::new(bins, block),
            |scratch, (strip, strip_rows)| {
                if cancel.is_cancelled() {
                    return;
                }
                for x_tile in (0..setup.width).step_by(side) {
                    let blocks = strip_rows.chunks_mut(block * setup.width * bins);
                    for (k, rows) in blocks.enumerate() {
                        for x0 in (x_tile..(x_tile + side).min(setup.width)).step_by(block) {
                            ctx.shade_block(x0, strip * side + k * block, block, rows, scratch);
                        }
                    }
                }
            },
        );
    image
}

/// Blocks per side of the square tiles the image is shaded in, tile by tile along a strip.
/// Neighbouring camera rays cross mostly the same cells (a cell spans about four pixels of the
/// default render), so the shading a ray reads is often still in the cache from the pixel
/// above it; shaded row by row across the whole image, that pixel was a full row, a megabyte
/// or more of shading reads, earlier. The image is the same (each pixel's sums do not depend
/// on the order); the view pass is faster (`BENCHMARKS.md`, ninth round).
const TILE_BLOCKS: usize = 8;

/// Internal reflections at the far surface weaker than this (the Fresnel fraction) are shaded
/// once per block of pixels ([`ViewSetup::reflection_block`]); stronger ones, near and beyond
/// the critical angle at the rim, per pixel.
const SHARED_REFLECTION: f32 = 0.2;
/// The reflected rays of a block's pixels are shaded together only if every one is within this
/// cosine of their mean direction (about 2°).
const SHARED_SPREAD_COS: f32 = 0.999_4;

/// A camera ray stopped at its first internal reflection, to be finished with its block.
#[derive(Clone, Copy, Debug)]
struct Deferred {
    /// Where it reflects and where it goes on.
    origin: Vec3,
    direction: Vec3,
    /// Throughput scale after the reflection (the shape is kept in `BlockScratch::shapes`).
    scale: f32,
    /// Bin of the shape's maximum.
    peak: usize,
}

/// Which segment a walk starts with, and whether a weak first reflection is returned (to be
/// shaded with the block's) instead of followed.
#[derive(Clone, Copy, Debug)]
struct Path {
    first: u32,
    defer: bool,
}

/// A walk that starts after the first internal reflection.
const REFLECTED: Path = Path {
    first: 1,
    defer: false,
};

/// Per-thread scratch space of the view pass.
struct BlockScratch {
    /// The throughput shape of the ray being walked.
    shape: Vec<f32>,
    /// Throughput shapes of the block's deferred rays, `block² × bins`.
    shapes: Vec<f32>,
    /// The deferred rays, each with its pixel within the block's rows (`x + width · row`).
    deferred: Vec<(usize, Deferred)>,
    /// The radiance of the block's shared reflected path.
    shared: Vec<f32>,
    transmission: Transmission,
}

impl BlockScratch {
    fn new(bins: usize, block: usize) -> Self {
        BlockScratch {
            shape: vec![0.0; bins],
            shapes: vec![0.0; block * block * bins],
            deferred: Vec::with_capacity(block * block),
            shared: vec![0.0; bins],
            transmission: Transmission::default(),
        }
    }
}

/// Everything a camera ray needs, shared by all threads.
struct View<'a> {
    shading: &'a Shading,
    setup: &'a ViewSetup<'a>,
    ellipsoid: Ellipsoid,
    grid: CellGrid,
    optics: ClusterOptics<'a>,
    bins: usize,
    n_eff: f32,
}

impl View<'_> {
    /// Shade the `block × block` pixels whose top-left corner is `(x0, y0)`; `rows` holds
    /// the block's rows of the image. Each pixel's ray is walked through the stone to the far
    /// surface. Where it reflects there only weakly (a few per cent, most of the stone), the
    /// reflected path is walked once for the block, from the mean of its pixels' reflected
    /// rays, and each pixel takes it through its own throughput: the reflected view, a few
    /// per cent of the image, is resolved at `block` pixels instead of one. Strong
    /// reflections (total internal reflection at the rim), and blocks whose reflected rays
    /// spread by more than about 2°, are walked per pixel.
    fn shade_block(
        &self,
        x0: usize,
        y0: usize,
        block: usize,
        rows: &mut [f32],
        scratch: &mut BlockScratch,
    ) {
        self.shade_block_pixels((x0, y0), block, rows, scratch);
        if scratch.deferred.is_empty() {
            return;
        }
        let n = scratch.deferred.len() as f32;
        let origin = scratch.deferred.iter().map(|(_, d)| d.origin).sum::<Vec3>() / n;
        let direction = scratch
            .deferred
            .iter()
            .map(|(_, d)| d.direction)
            .sum::<Vec3>()
            .normalize_or_zero();
        let together = scratch
            .deferred
            .iter()
            .all(|(_, d)| d.direction.dot(direction) >= SHARED_SPREAD_COS);
        if together {
            self.walk_reflections_together(origin, direction, rows, scratch);
        } else {
            self.walk_reflections_apart(rows, scratch);
        }
    }

    /// Shade each pixel of the block at `(x0, y0)` (see [`View::shade_block`]), keeping in
    /// `scratch.deferred` and `scratch.shapes` the weak first reflections to be walked later.
    fn shade_block_pixels(
        &self,
        (x0, y0): (usize, usize),
        block: usize,
        rows: &mut [f32],
        scratch: &mut BlockScratch,
    ) {
        let (width, bins) = (self.setup.width, self.bins);
        let x1 = (x0 + block).min(width);
        let y1 = (y0 + block).min(self.setup.height);
        let share = block > 1;
        scratch.deferred.clear();
        for y in y0..y1 {
            for x in x0..x1 {
                let at = x + width * (y - y0);
                let pixel = &mut rows[at * bins..(at + 1) * bins];
                if let Some(d) = self.shade_pixel(
                    x,
                    y,
                    share,
                    pixel,
                    &mut scratch.shape,
                    &mut scratch.transmission,
                ) {
                    let k = scratch.deferred.len();
                    scratch.shapes[k * bins..(k + 1) * bins].copy_from_slice(&scratch.shape);
                    scratch.deferred.push((at, d));
                }
            }
        }
    }

    /// Walk the block's deferred reflections once, from their mean `origin` along their mean
    /// `direction`, and add what that path sees to each deferred pixel through its own
    /// throughput.
    fn walk_reflections_together(
        &self,
        origin: Vec3,
        direction: Vec3,
        rows: &mut [f32],
        scratch: &mut BlockScratch,
    ) {
        let bins = self.bins;
        let s0 = scratch
            .deferred
            .iter()
            .fold(0.0f32, |m, (_, d)| m.max(d.scale));
        scratch.shape.fill(1.0);
        scratch.shared.fill(0.0);
        let mut peak = 0;
        let start = WalkStart {
            origin,
            direction,
            scale: s0,
        };
        let buffers = RayBuffers {
            pixel: &mut scratch.shared,
            shape_thr: &mut scratch.shape,
            transmission: &mut scratch.transmission,
        };
        self.walk(start, &mut peak, REFLECTED, buffers);
        for (k, &(at, d)) in scratch.deferred.iter().enumerate() {
            let pixel = &mut rows[at * bins..(at + 1) * bins];
            let shape = &scratch.shapes[k * bins..(k + 1) * bins];
            add_filtered(pixel, shape, &scratch.shared, d.scale / s0);
        }
    }

    /// Walk each of the block's deferred reflections on its own, into its pixel.
    fn walk_reflections_apart(&self, rows: &mut [f32], scratch: &mut BlockScratch) {
        let bins = self.bins;
        for (k, &(at, d)) in scratch.deferred.iter().enumerate() {
            let pixel = &mut rows[at * bins..(at + 1) * bins];
            scratch
                .shape
                .copy_from_slice(&scratch.shapes[k * bins..(k + 1) * bins]);
            let mut peak = d.peak;
            let start = WalkStart {
                origin: d.origin,
                direction: d.direction,
                scale: d.scale,
            };
            let buffers = RayBuffers {
                pixel,
                shape_thr: &mut scratch.shape,
                transmission: &mut scratch.transmission,
            };
            self.walk(start, &mut peak, REFLECTED, buffers);
        }
    }

    /// The spectrum seen through pixel `(x, y)`, written into `pixel`; `shape_thr` and
    /// `transmission` are scratch space for the shape of the ray's throughput and a cluster's
    /// transmittance. With `share`, returns the ray's first internal reflection where that is
    /// weak enough to be shaded with its block's (its throughput shape left in `shape_thr`).
    /// (Not inlined: one call per pixel costs nothing, and profiles can tell the view pass
    /// apart.)
    #[inline(never)]
    fn shade_pixel(
        &self,
        x: usize,
        y: usize,
        share: bool,
        pixel: &mut [f32],
        shape_thr: &mut [f32],
        transmission: &mut Transmission,
    ) -> Option<Deferred> {
        let ray = self.setup.camera.ray(x as f32 + 0.5, y as f32 + 0.5);
        let Some((t_hit, _)) = self.ellipsoid.intersect(&ray).filter(|h| h.0 > 0.0) else {
            for (p, s) in pixel.iter_mut().zip(self.setup.light_spectrum) {
                *p = self.setup.background * s;
            }
            return None;
        };
        // Surface: the gloss of the light, and the refracted ray.
        let p = ray.at(t_hit);
        let normal = self.ellipsoid.normal(p);
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
        let dir = refract(ray.direction, normal, 1.0, self.n_eff)?;
        // Radiance leaving the stone is scaled by (1 − F) / n² (étendue). The ray's throughput
        // is `scale × shape`: filters flat in wavelength (most clusters, voids, the surface)
        // change only the scale; the shape changes only in the bins of a Bragg line, and is
        // kept at a maximum of 1, so the ray lives while `scale` exceeds MIN_THROUGHPUT.
        let scale = (1.0 - fresnel) / (self.n_eff * self.n_eff);
        shape_thr.fill(1.0);
        let mut peak = 0;
        let path = Path {
            first: 0,
            defer: share,
        };
        let start = WalkStart {
            origin: p,
            direction: dir,
            scale,
        };
        let buffers = RayBuffers {
            pixel,
            shape_thr,
            transmission,
        };
        self.walk(start, &mut peak, path, buffers)
    }
}

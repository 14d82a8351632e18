//! The lobe integrator's passes over the image: a ray through every pixel's centre, then
//! `spp − 1` more, stratified, through each pixel whose centre differs from one of its four
//! neighbours' ([`EDGE_CONTRAST`]), reading back the reflections its centre ray followed out
//! ([`Reuse`]). The image is done in bands of [`BAND_ROWS`] rows, each band's edges after
//! the next band's centres, so that the centres' reflections are kept for two bands at most.

use std::ops::Range;

use rayon::prelude::*;

use super::trace::{Followed, Lit, Mode, Reuse, Scattered, Sums, Tracer};
use super::{Irradiance, LineColours, LobeImage, LobeSetup};
use crate::cancel::Cancel;
use crate::integrator::{Passes, RowCounter};
use crate::sampling::{stage, Rng};
use crate::spectrum::SpectralImage;
use crate::stone::Stone;

/// Two neighbouring first rays differing by more than this in any of √X, √Y, √Z (about
/// the perceptual steps of an sRGB image) mark both pixels as an edge.
const EDGE_CONTRAST: f32 = 0.02;

/// Rows of a band.
const BAND_ROWS: usize = 32;

/// What the passes read besides the pixels.
pub(super) struct Tables<'a> {
    pub colours: &'a LineColours,
    pub irradiance: &'a Irradiance,
    pub lit: Lit<'a>,
}

/// Render `stone` as `setup` says, telling `passes.on_rows` of every row done: band by band,
/// its centres' rows, then (for `spp` > 1) the band before's edges' rows.
pub(super) fn render(
    stone: &Stone,
    setup: &LobeSetup,
    tables: &Tables,
    passes: &Passes,
) -> LobeImage {
    let (w, h) = (setup.width, setup.height);
    let spp = setup.spp.max(1) as usize;
    let mut image = LobeImage {
        xyz: vec![[0.0f32; 3]; w * h],
        spectral: SpectralImage::new(w, h, setup.spectral.grid),
    };
    let bands = Bands {
        stone,
        setup,
        tables,
        rows: RowCounter::new(passes, if spp == 1 { h } else { 2 * h }),
        cancel: Cancel::current(),
    };
    let mut kept = Kept::new(w, h, spp > 1);
    let count = h.div_ceil(BAND_ROWS);
    let band = |b: usize| b * BAND_ROWS..((b + 1) * BAND_ROWS).min(h);
    for b in 0..=count {
        // A stopped render traces no more rows (its image is never shown).
        if bands.cancel.is_cancelled() {
            break;
        }
        if b < count {
            bands.centres_of(&mut image, &mut kept, band(b));
        }
        if b > 0 && spp > 1 {
            bands.edges_of(&mut image, &mut kept, band(b - 1));
        }
    }
    image
}

/// What the passes over the bands read.
struct Bands<'a, 'b> {
    stone: &'a Stone,
    setup: &'a LobeSetup<'a>,
    tables: &'b Tables<'a>,
    rows: RowCounter<'b>,
    cancel: Cancel,
}

/// What the centres leave for the edges (nothing at one ray a pixel).
struct Kept {
    /// The centres' √X, √Y, √Z, as the edges are found from.
    tones: Vec<[f32; 3]>,
    /// Per row, the reflections its centres' rays followed (kept until its edges are done).
    followed: Vec<RowFollowed>,
}

impl Kept {
    fn new(w: usize, h: usize, edges: bool) -> Self {
        let (pixels, rows) = if edges { (w * h, h) } else { (0, 0) };
        Kept {
            tones: vec![[0.0f32; 3]; pixels],
            followed: (0..rows).map(|_| RowFollowed::new()).collect(),
        }
    }
}

impl Bands<'_, '_> {
    fn tracer(&self) -> Tracer<'_> {
        let t = self.tables;
        Tracer::new(self.stone, self.setup, t.colours, t.irradiance, t.lit)
    }

    /// The rays through the centres of `rows`' pixels.
    fn centres_of(&self, image: &mut LobeImage, kept: &mut Kept, rows: Range<usize>) {
        let (w, bins) = (self.setup.width, self.setup.spectral.grid.bins);
        let edges = !kept.tones.is_empty();
        let mode = if edges && self.setup.reuse {
            Mode::Record
        } else {
            Mode::Off
        };
        let xyz = &mut image.xyz[rows.start * w..rows.end * w];
        let spectral = &mut image.spectral.data[rows.start * w * bins..rows.end * w * bins];
        let per_row = xyz.par_chunks_mut(w).zip(spectral.par_chunks_mut(w * bins));
        let centre_row = |k: usize, (xyz_row, bins_row): (&mut [[f32; 3]], &mut [f32])| {
            let y = rows.start + k;
            let mut tracer = self.tracer();
            let mut row_followed = RowFollowed::new();
            for (x, (out, out_bins)) in xyz_row
                .iter_mut()
                .zip(bins_row.chunks_mut(bins))
                .enumerate()
            {
                tracer.reuse.start(mode);
                pixel(
                    &mut tracer,
                    self.setup,
                    &[(x as f32 + 0.5, y as f32 + 0.5)],
                    out,
                    out_bins,
                );
                row_followed.push(&tracer.reuse);
            }
            self.rows.row_done();
            row_followed
        };
        if edges {
            per_row
                .zip(kept.followed[rows.clone()].par_iter_mut())
                .enumerate()
                .for_each(|(k, (row, row_followed))| {
                    if !self.cancel.is_cancelled() {
                        *row_followed = centre_row(k, row);
                    }
                });
            let tone = |v: [f32; 3]| v.map(|c| c.max(0.0).sqrt());
            for (t, v) in kept.tones[rows.start * w..rows.end * w]
                .iter_mut()
                .zip(&image.xyz[rows.start * w..rows.end * w])
            {
                *t = tone(*v);
            }
        } else {
            per_row.enumerate().for_each(|(k, row)| {
                if !self.cancel.is_cancelled() {
                    centre_row(k, row);
                }
            });
        }
    }

    /// The pixels of `rows` at an edge, again with `spp` stratified rays (the centre's among
    /// them); the rows' centres and those of the rows either side are done.
    fn edges_of(&self, image: &mut LobeImage, kept: &mut Kept, rows: Range<usize>) {
        let (w, h) = (self.setup.width, self.setup.height);
        let bins = self.setup.spectral.grid.bins;
        let spp = self.setup.spp.max(1) as usize;
        let edges = edge_pixels(&kept.tones, w, h, rows.clone());
        let xyz = &mut image.xyz[rows.start * w..rows.end * w];
        let spectral = &mut image.spectral.data[rows.start * w * bins..rows.end * w * bins];
        xyz.par_chunks_mut(w)
            .zip(spectral.par_chunks_mut(w * bins))
            .zip(edges.par_chunks(w))
            .zip(kept.followed[rows.clone()].par_iter())
            .enumerate()
            .for_each(|(k, (((xyz_row, bins_row), edge_row), row_followed))| {
                let y = rows.start + k;
                if self.cancel.is_cancelled() {
                    return;
                }
                let mut tracer = self.tracer();
                let mut positions = vec![(0.0f32, 0.0f32); spp - 1];
                let mut centre_bins = vec![0.0f32; bins];
                for (x, ((out, out_bins), _)) in xyz_row
                    .iter_mut()
                    .zip(bins_row.chunks_mut(bins))
                    .zip(edge_row)
                    .enumerate()
                    .filter(|(_, (_, &edge))| edge)
                {
                    let mut rng = Rng::new(self.setup.seed, stage::LOBE, (y * w + x) as u64);
                    stratified(&mut rng, x, y, &mut positions);
                    if self.setup.reuse {
                        tracer
                            .reuse
                            .start_from(row_followed.of(x), row_followed.single(x));
                    } else {
                        tracer.reuse.start(Mode::Off);
                    }
                    let centre = *out;
                    centre_bins.copy_from_slice(out_bins);
                    out_bins.iter_mut().for_each(|b| *b = 0.0);
                    pixel(&mut tracer, self.setup, &positions, out, out_bins);
                    // The centre's ray counts as one of the pixel's `spp`.
                    let k = (spp - 1) as f32;
                    for (v, c) in out.iter_mut().zip(centre) {
                        *v = (*v * k + c) / spp as f32;
                    }
                    for (v, c) in out_bins.iter_mut().zip(&centre_bins) {
                        *v = (*v * k + c) / spp as f32;
                    }
                }
                self.rows.row_done();
            });
        for row in &mut kept.followed[rows] {
            *row = RowFollowed::new();
        }
    }
}

/// The reflections each pixel's centre ray followed out in one row, pixel after pixel, and
/// the body's single scattering each found, by segment.
struct RowFollowed {
    followed: Vec<Followed>,
    /// Where each pixel's reflections start in `followed`, and after the last pixel's, where
    /// they end.
    starts: Vec<u32>,
    singles: Vec<Scattered>,
    /// Where each pixel's single scatterings start in `singles`, as `starts`.
    single_starts: Vec<u32>,
}

impl RowFollowed {
    fn new() -> Self {
        RowFollowed {
            followed: Vec::new(),
            starts: vec![0],
            singles: Vec::new(),
            single_starts: vec![0],
        }
    }

    /// The next pixel's reflections and single scattering: those `reuse` kept.
    fn push(&mut self, reuse: &Reuse) {
        self.followed.extend_from_slice(reuse.followed());
        self.starts.push(self.followed.len() as u32);
        self.singles.extend_from_slice(reuse.single());
        self.single_starts.push(self.singles.len() as u32);
    }

    fn of(&self, x: usize) -> &[Followed] {
        &self.followed[self.starts[x] as usize..self.starts[x + 1] as usize]
    }

    fn single(&self, x: usize) -> &[Scattered] {
        &self.singles[self.single_starts[x] as usize..self.single_starts[x + 1] as usize]
    }
}

/// Per pixel of `rows`, whether its first ray's `tones` differ from one of its four
/// neighbours' (left, right, above, below) by more than [`EDGE_CONTRAST`].
fn edge_pixels(tones: &[[f32; 3]], w: usize, h: usize, rows: Range<usize>) -> Vec<bool> {
    let mut edges = vec![false; w * rows.len()];
    edges.par_chunks_mut(w).enumerate().for_each(|(k, row)| {
        let y = rows.start + k;
        for (x, edge) in row.iter_mut().enumerate() {
            let here = tones[y * w + x];
            for (dx, dy) in [(-1i64, 0i64), (1, 0), (0, -1), (0, 1)] {
                let (nx, ny) = (x as i64 + dx, y as i64 + dy);
                if nx < 0 || ny < 0 || nx >= w as i64 || ny >= h as i64 {
                    continue;
                }
                let there = tones[ny as usize * w + nx as usize];
                if (0..3).any(|c| (here[c] - there[c]).abs() > EDGE_CONTRAST) {
                    *edge = true;
                    break;
                }
            }
        }
    });
    edges
}

/// `positions.len()` positions in pixel `(x, y)`, stratified in x and y at once: position k
/// in column k, its row shuffled by `rng`, jittered within its cell.
fn stratified(rng: &mut Rng, x: usize, y: usize, positions: &mut [(f32, f32)]) {
    let n = positions.len();
    let mut order: Vec<usize> = (0..n).collect();
    for k in (1..n).rev() {
        order.swap(k, rng.below(k as u64 + 1) as usize);
    }
    for (k, (p, &row)) in positions.iter_mut().zip(&order).enumerate() {
        *p = (
            x as f32 + (k as f32 + rng.uniform_f32()) / n as f32,
            y as f32 + (row as f32 + rng.uniform_f32()) / n as f32,
        );
    }
}

/// The mean of the camera rays through `positions` (pixel coordinates) into `out` (XYZ) and
/// `out_bins` (zeroed by the caller).
fn pixel(
    tracer: &mut Tracer,
    setup: &LobeSetup,
    positions: &[(f32, f32)],
    out: &mut [f32; 3],
    out_bins: &mut [f32],
) {
    let mut sums = Sums {
        white: 0.0,
        xyz: [0.0; 3],
        bins: out_bins,
    };
    for &(px, py) in positions {
        tracer.sample(setup.camera.ray(px, py), &mut sums);
    }
    let scale = 1.0 / positions.len() as f64;
    let white_xyz = setup.spectral.white_xyz;
    for c in 0..3 {
        out[c] = ((sums.xyz[c] + sums.white * white_xyz[c]) * scale) as f32;
    }
    for (b, wb) in sums.bins.iter_mut().zip(&setup.spectral.white_bins) {
        *b = ((f64::from(*b) + sums.white * f64::from(*wb)) * scale) as f32;
    }
}

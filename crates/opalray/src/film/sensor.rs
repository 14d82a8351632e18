//! The film's sensor: the light's spectrum times the CIE 1931 colour-matching functions on a
//! fine table, what a wavelength or the light's white adds to a pixel's XYZ and spectral bins,
//! and the wavelength draws of a path's first reflection (a truncated Cauchy law over the line
//! mixed with a uniform one, stratified; `path::spectral` notes why).
//!
//! Input: the scene's illuminant, the spectral image's grid and the number of wavelengths a
//! path carries → output: a [`SpectralSampler`], which the path tracer, the stored method and
//! the lobe integrator deposit their light through.

use crate::color::{cmf_at, illuminant_samples};
use crate::optics::BraggLine;
use crate::scene::Illuminant;
use crate::spectrum::WavelengthGrid;
use crate::stone::ironstone_reflectance;

/// Step of the light × colour-matching table, nm.
pub(crate) const TABLE_STEP_NM: f64 = 0.25;
/// Share of wavelength draws from the line's law (the rest uniform over the range).
const LINE_SHARE: f64 = 0.9;
/// Most ironstone reflections a path carries.
pub const MAX_TINTS: usize = 3;

/// Default wavelengths per contribution (the path tracer's `integrator.wavelengths`); the
/// stored and lobe methods' sampler is built with it (they draw no wavelengths).
pub const DEFAULT_WAVELENGTHS: u32 = 4;

/// [`SpectralSampler::table_bins`] of a point outside the spectral image's grid.
pub(crate) const NO_BIN: u16 = u16::MAX;

/// The light's spectrum and the colour-matching functions on a fine table, and the grid of the
/// spectral image.
#[derive(Clone, Debug)]
pub struct SpectralSampler {
    pub(crate) lo_nm: f64,
    pub(crate) hi_nm: f64,
    /// `(S x̄, S ȳ, S z̄, S)` every [`TABLE_STEP_NM`], S scaled to luminance 1 over the range.
    pub(crate) table: Vec<[f32; 4]>,
    /// The spectral image's bin of each point of `table` (`grid.bin_of` of its wavelength),
    /// [`NO_BIN`] outside the grid.
    pub(crate) table_bins: Vec<u16>,
    /// XYZ of the light itself (Y = 1).
    pub white_xyz: [f64; 3],
    /// The light's spectrum averaged over each bin of the image grid (luminance 1).
    pub white_bins: Vec<f32>,
    /// The spectral image's grid.
    pub grid: WavelengthGrid,
    pub(crate) draws: usize,
    /// XYZ and bins of the light after k = 1 ..= [`MAX_TINTS`] ironstone reflections.
    tinted: Vec<([f64; 3], Vec<f32>)>,
}

/// What one contribution adds to its pixel.
pub struct Sample {
    /// Tristimulus values.
    pub xyz: [f64; 3],
}

impl SpectralSampler {
    /// XYZ and bins of the light after `k` ironstone reflections (1 ..= [`MAX_TINTS`]).
    pub fn tinted_white(&self, k: usize) -> (&[f64; 3], &[f32]) {
        let (xyz, bins) = &self.tinted[k.clamp(1, MAX_TINTS) - 1];
        (xyz, bins)
    }

    /// The wavelength range it covers, nm.
    pub fn range_nm(&self) -> (f64, f64) {
        (self.lo_nm, self.hi_nm)
    }

    /// For light of `illuminant` on `grid`, with `draws` wavelengths per contribution.
    pub fn new(illuminant: Illuminant, grid: &WavelengthGrid, draws: usize) -> Self {
        let (lo, hi) = (grid.min_nm, grid.max_nm);
        let n = ((hi - lo) / TABLE_STEP_NM).round() as usize + 1;
        let light = illuminant_samples(illuminant);
        let mut raw: Vec<[f64; 4]> = (0..n)
            .map(|i| {
                let w = lo + i as f64 * TABLE_STEP_NM;
                let s = piecewise_linear(light, w);
                let [x, y, z] = cmf_at(w);
                [s * x, s * y, s * z, s]
            })
            .collect();
        // Trapezoid integral of S ȳ over the range: the light's luminance.
        let integral = |k: usize, raw: &[[f64; 4]]| {
            raw.windows(2)
                .map(|p| 0.5 * (p[0][k] + p[1][k]) * TABLE_STEP_NM)
                .sum::<f64>()
        };
        let y = integral(1, &raw);
        let scale = if y > 0.0 { 1.0 / y } else { 0.0 };
        for v in &mut raw {
            for c in v.iter_mut() {
                *c *= scale;
            }
        }
        // XYZ and bin averages of a table: the light's, and the light's after ironstone.
        let summary = |table: &[[f64; 4]]| -> ([f64; 3], Vec<f32>) {
            let xyz = [integral(0, table), integral(1, table), integral(2, table)];
            let bins = (0..grid.bins)
                .map(|b| {
                    let (a, z) = grid.edges_nm(b);
                    let k = 64;
                    (0..k)
                        .map(|j| {
                            let w = a + (z - a) * (j as f64 + 0.5) / k as f64;
                            lookup(table, lo, w)[3]
                        })
                        .sum::<f64>() as f32
                        / k as f32
                })
                .collect();
            (xyz, bins)
        };
        let (white_xyz, white_bins) = summary(&raw);
        let tinted = (1..=MAX_TINTS as i32)
            .map(|k| {
                let tinted: Vec<[f64; 4]> = raw
                    .iter()
                    .enumerate()
                    .map(|(i, v)| {
                        let r = ironstone_reflectance(lo + i as f64 * TABLE_STEP_NM).powi(k);
                        v.map(|c| c * r)
                    })
                    .collect();
                summary(&tinted)
            })
            .collect();
        let table_bins = (0..raw.len())
            .map(|i| {
                let bin = grid.bin_of(lo + i as f64 * TABLE_STEP_NM);
                bin.map_or(NO_BIN, |b| u16::try_from(b).expect("bins fit in u16"))
            })
            .collect();
        SpectralSampler {
            lo_nm: lo,
            hi_nm: hi,
            table: raw.iter().map(|v| v.map(|c| c as f32)).collect(),
            table_bins,
            white_xyz,
            white_bins,
            grid: *grid,
            draws,
            tinted,
        }
    }

    /// `(S x̄, S ȳ, S z̄, S)` at `w` nm (S of luminance 1 over the range), linear between the
    /// table's steps.
    pub fn at(&self, w: f64) -> [f32; 4] {
        let x = ((w - self.lo_nm) / TABLE_STEP_NM).max(0.0);
        let i = (x as usize).min(self.table.len() - 2);
        let f = (x - i as f64).min(1.0) as f32;
        let (a, b) = (self.table[i], self.table[i + 1]);
        std::array::from_fn(|c| a[c] + (b[c] - a[c]) * f)
    }

    /// The `j`-th of the stratified wavelength draws from `line`'s law (module notes) with
    /// offset `u` in [0, 1), and its density: `(λ, p(λ))`, nm and per nm.
    pub fn draw(&self, line: &BraggLine, j: usize, u: f64) -> (f64, f64) {
        let (lo, hi) = (self.lo_nm, self.hi_nm);
        let gamma = line.half_width_nm().max(0.05);
        let x0 = line.center_nm;
        let cdf = |w: f64| ((w - x0) / gamma).atan();
        let (c_lo, c_hi) = (cdf(lo), cdf(hi));
        let mass = c_hi - c_lo;
        let v = (j as f64 + u) / self.draws.max(1) as f64;
        let w = if v < LINE_SHARE && mass > 1e-12 {
            x0 + gamma * (c_lo + mass * v / LINE_SHARE).tan()
        } else {
            lo + (hi - lo) * ((v - LINE_SHARE).max(0.0) / (1.0 - LINE_SHARE)).min(1.0)
        };
        let w = w.clamp(lo, hi);
        let line_pdf = if mass > 1e-12 {
            1.0 / (gamma * mass * (1.0 + ((w - x0) / gamma).powi(2)))
        } else {
            0.0
        };
        (w, LINE_SHARE * line_pdf + (1.0 - LINE_SHARE) / (hi - lo))
    }

    /// Add `weight` × the light's white, after `tints` ironstone reflections.
    pub(crate) fn add_white(&self, tints: u8, weight: f64, xyz: &mut [f64; 3], bins: &mut [f32]) {
        let (white_xyz, white_bins) = match tints {
            0 => (&self.white_xyz, &self.white_bins),
            k => {
                let (x, b) = &self.tinted[usize::from(k) - 1];
                (x, b)
            }
        };
        for (v, w) in xyz.iter_mut().zip(white_xyz) {
            *v += weight * w;
        }
        for (b, w) in bins.iter_mut().zip(white_bins) {
            *b += (weight * f64::from(*w)) as f32;
        }
    }

    /// Add `f · S(λ) c̄(λ)` to `xyz` and `f · S(λ)` to λ's bin.
    #[inline]
    pub(crate) fn add_at(&self, w: f64, f: f64, xyz: &mut [f64; 3], bins: &mut [f32]) {
        let s = self.at(w);
        for (v, c) in xyz.iter_mut().zip(&s) {
            *v += f * f64::from(*c);
        }
        if let Some(b) = self.grid.bin_of(w) {
            bins[b] += (f * f64::from(s[3]) / self.grid.bin_width_nm()) as f32;
        }
    }
}

/// The piecewise-linear function through `samples` (sorted) at `x`; zero outside.
fn piecewise_linear(samples: &[(f64, f64)], x: f64) -> f64 {
    let i = samples.partition_point(|&(sx, _)| sx <= x);
    if i == 0 || i == samples.len() {
        return if i > 0 && x == samples[i - 1].0 {
            samples[i - 1].1
        } else {
            0.0
        };
    }
    let ((x0, y0), (x1, y1)) = (samples[i - 1], samples[i]);
    y0 + (y1 - y0) * (x - x0) / (x1 - x0)
}

fn lookup(raw: &[[f64; 4]], lo: f64, w: f64) -> [f64; 4] {
    let x = ((w - lo) / TABLE_STEP_NM).max(0.0);
    let i = (x as usize).min(raw.len() - 2);
    let f = (x - i as f64).min(1.0);
    std::array::from_fn(|c| raw[i][c] + (raw[i + 1][c] - raw[i][c]) * f)
}

//! The colour of a Bragg line without sampling its wavelengths: `∫ R(λ) S(λ) c̄(λ) dλ` as the
//! line's equivalent width times the light × colour-matching functions averaged over the
//! line's profile, read from a table over line centre and width built once per scene.
//!
//! - **Equivalent width.** A uniform grating of coupling ν reflects `∫ R dσ = π ν tanh ν`
//!   over its detuning σ = πN(λ_B/λ − 1) (the integrated reflectivity of a non-absorbing
//!   finite crystal in the Bragg case; Zachariasen 1945, §3.7: `π ν²` for a thin stack, the
//!   Darwin plateau's `π ν` for a thick one). With `dλ = λ_B dσ/(πN)` near the line, its
//!   unpolarised width is `W = (λ_B/N) (ν_s tanh ν_s + ν_p tanh ν_p)/2` nm.
//! - **Profile.** Each polarisation's line is taken as a Lorentzian of that width whose tails
//!   are the grating's own, `ν²/(2σ²)` beyond the stop band: half-width `γ = ν/(2 tanh ν)` in
//!   σ (`λ_B γ/(πN)` nm), height `2 tanh² ν`. Its core is narrower than the stop band's flat
//!   top, but a colour-matching function does not resolve a few nm; its tails, a third of a
//!   thick line's light, reach tens of nm, where `S c̄` changes (in the blue, ȳ triples over
//!   20 nm), and are kept. The light × colour-matching functions (`S x̄, S ȳ, S z̄, S`) are
//!   convolved with Lorentzians of [`WIDTHS`] half-widths, cut at [`REACH`] half-widths (the
//!   lines' own window, `optics::line`), every 0.25 nm, and read at the line's centre,
//!   interpolated in the width's logarithm.

use rayon::prelude::*;

use crate::film::SpectralSampler;
use crate::lights::env::filter::erf;
use crate::optics::BraggLine;

/// Step of the table in wavelength, nm.
const STEP_NM: f64 = 0.25;
/// Half-widths (nm) of the Lorentzians the table is convolved with, row by row: none, then
/// doubling from 1/32 nm.
const WIDTHS: [f64; 13] = [
    0.0, 0.03125, 0.0625, 0.125, 0.25, 0.5, 1.0, 2.0, 4.0, 8.0, 16.0, 32.0, 64.0,
];
/// Half-widths a kernel reaches on either side (a thick line's window is 80 of its γ).
const REACH: f64 = 80.0;
/// The first standard deviation (nm) of the Gaussians the table is convolved with as well,
/// row by row, for a line spread over its lobe ([`LineColours::in_lobe`]).
const FIRST_SPREAD_NM: f64 = 0.125;
/// Gaussian rows per doubling of the standard deviation: the blue's `S ȳ` grows tenfold over
/// 20 nm, and rows a doubling apart, interpolated, would read a 16 nm spread 30 % too bright.
const SPREADS_PER_OCTAVE: usize = 4;
/// Gaussian rows: from [`FIRST_SPREAD_NM`] to 64 nm.
const SPREADS: usize = 9 * SPREADS_PER_OCTAVE + 1;
/// Standard deviations a Gaussian kernel reaches on either side.
const GAUSS_REACH: f64 = 5.0;
/// A spread (nm) under which a line is read as it is.
const MIN_SPREAD_NM: f64 = 0.01;

/// Light × colour-matching functions smoothed over line widths: the colour of any line.
#[derive(Clone, Debug)]
pub struct LineColours {
    lo_nm: f64,
    hi_nm: f64,
    columns: usize,
    /// `WIDTHS.len()` rows of `columns` values `(S x̄, S ȳ, S z̄, S)`, S of luminance 1.
    table: Vec<[f32; 4]>,
    /// `SPREADS.len()` rows of the same, convolved with Gaussians.
    gauss: Vec<[f32; 4]>,
}

impl LineColours {
    /// The table of the light and range of `sampler`: each row's convolution runs in
    /// parallel over its columns, each column's sum in the kernel's order (the same bytes
    /// at any thread count).
    pub fn new(sampler: &SpectralSampler) -> Self {
        let (lo, hi) = sampler.range_nm();
        let columns = ((hi - lo) / STEP_NM).round() as usize + 1;
        // The light × colour-matching functions at every column; 0 beyond the range, whose
        // taps are left out of the sums (they would add 0).
        let samples: Vec<[f64; 4]> = (0..columns)
            .map(|i| sampler.at(lo + i as f64 * STEP_NM).map(f64::from))
            .collect();
        let mut table = vec![[0.0f32; 4]; WIDTHS.len() * columns];
        for (row, &gamma) in table.chunks_mut(columns).zip(&WIDTHS) {
            smooth(&samples, &lorentzian(gamma, columns), row);
        }
        let mut gauss = vec![[0.0f32; 4]; SPREADS * columns];
        for (k, row) in gauss.chunks_mut(columns).enumerate() {
            let sigma = FIRST_SPREAD_NM * (k as f64 / SPREADS_PER_OCTAVE as f64).exp2();
            smooth(&samples, &gaussian(sigma, columns), row);
        }
        LineColours {
            lo_nm: lo,
            hi_nm: hi,
            columns,
            table,
            gauss,
        }
    }

    /// `(XYZ, S)` of `line` reflected over a mosaic lobe: the planes' normal spread as a
    /// Gaussian of standard deviation `sigma` (rad, per axis) about the family normal, at
    /// `cos_theta` (the ray's angle to it, inside). A normal tilted by `δ` in the plane of
    /// incidence moves the line's centre by `λ tan θ δ`, and any tilt `α` by `−λ α²/2` on
    /// average: against an environment even over the lobe, the reflection is the line
    /// convolved with a Gaussian of `λ tan θ σ`, centred `λ σ²` to the blue (its area, the
    /// equivalent width, unchanged): the Lorentzian's and the Gaussian's convolution, a Voigt.
    /// `sharp` is the line's own colour and `profile` its [`LineProfile`] (as
    /// [`LineColours::of_profile`] reads them).
    pub fn in_lobe(
        &self,
        line: &BraggLine,
        sharp: ([f64; 3], f64),
        profile: &LineProfile,
        cos_theta: f64,
        sigma: f64,
    ) -> ([f64; 3], f64, f64) {
        let center = line.center_nm * (1.0 - sigma * sigma);
        let spread = mosaic_spread_nm(center, cos_theta, sigma);
        if spread < MIN_SPREAD_NM {
            return (sharp.0, sharp.1, line.center_nm);
        }
        // The Voigt of the line's Lorentzian (cut at REACH half-widths, as the line) and the
        // Gaussian: the Lorentzian's core, its mass within ±spread, spread as the Gaussian,
        // its tails beyond left as they are (a Gaussian moves them by less than their own
        // scale). The core is taken as all at the centre: its second moment, 2γσ/π, is a few
        // per cent of the Gaussian's where the spread matters.
        let mut core = 0.0;
        for &(width, gamma) in profile.parts() {
            core += width * ((spread / gamma).atan() / REACH.atan()).min(1.0);
        }
        let row = (SPREADS_PER_OCTAVE as f64 * (spread / FIRST_SPREAD_NM).log2())
            .clamp(0.0, (SPREADS - 1) as f64);
        let spread_out = self.read(&self.gauss, row, center, spread);
        let at_centre = self.at(line.center_nm, 0.0);
        let moved: [f64; 4] = std::array::from_fn(|c| core * (spread_out[c] - at_centre[c]));
        (
            std::array::from_fn(|c| sharp.0[c] + moved[c]),
            sharp.1 + moved[3],
            center,
        )
    }

    /// `(XYZ, S)` of `line`: `∫ R S c̄ dλ` and `∫ R S dλ` (relative to the light's luminance).
    pub fn of(&self, line: &BraggLine) -> ([f64; 3], f64) {
        self.of_profile(&LineProfile::of(line))
    }

    /// [`LineColours::of`] of the line whose [`LineProfile`] is `profile`.
    pub fn of_profile(&self, profile: &LineProfile) -> ([f64; 3], f64) {
        let mut out = ([0.0f64; 3], 0.0f64);
        for &(width, gamma) in profile.parts() {
            let v = self.at(profile.center_nm, gamma);
            for (o, x) in out.0.iter_mut().zip(v) {
                *o += width * x;
            }
            out.1 += width * v[3];
        }
        out
    }

    /// The Lorentzian rows at `center_nm` for a profile of half-width `gamma_nm`.
    fn at(&self, center_nm: f64, gamma_nm: f64) -> [f64; 4] {
        self.read(&self.table, row_of(gamma_nm), center_nm, gamma_nm)
    }

    /// `table`'s rows at `center_nm`, interpolated at the fractional row `row_f` (a kernel of
    /// width `width_nm`). A row weighed 0 is not read (it would add `0 × v`: the same sums).
    fn read(&self, table: &[[f32; 4]], row_f: f64, center_nm: f64, width_nm: f64) -> [f64; 4] {
        if !(center_nm > self.lo_nm - 4.0 * width_nm && center_nm < self.hi_nm + 4.0 * width_nm) {
            return [0.0; 4];
        }
        let x = (center_nm - self.lo_nm) / STEP_NM;
        if x < 0.0 || x > (self.columns - 1) as f64 {
            return [0.0; 4];
        }
        let rows = table.len() / self.columns;
        // `row_f as usize` is `row_f.floor() as usize` for every value (a negative one or NaN
        // gives 0 both ways), without the library call `floor` is before SSE4.1.
        let r0 = (row_f as usize).min(rows - 2);
        let fr = (row_f - r0 as f64).clamp(0.0, 1.0);
        let i = (x as usize).min(self.columns - 2);
        let f = x - i as f64;
        let read = |row: usize| -> [f64; 4] {
            let [a, b] = [
                table[row * self.columns + i],
                table[row * self.columns + i + 1],
            ];
            std::array::from_fn(|c| f64::from(a[c]) * (1.0 - f) + f64::from(b[c]) * f)
        };
        // The table holds no negative values, infinities or NaN: `v × 1 + w × 0` is `v`.
        if fr == 0.0 {
            return read(r0);
        }
        if fr == 1.0 {
            return read(r0 + 1);
        }
        let (a, b) = (read(r0), read(r0 + 1));
        std::array::from_fn(|c| a[c] * (1.0 - fr) + b[c] * fr)
    }
}

/// The standard deviation (nm) over which a mosaic of `sigma` (rad, per axis) spreads a
/// line centred at `center_nm` met at `cos_theta`: `λ tan θ σ` ([`LineColours::in_lobe`]).
pub(crate) fn mosaic_spread_nm(center_nm: f64, cos_theta: f64, sigma: f64) -> f64 {
    let c = cos_theta.clamp(1e-3, 1.0);
    center_nm * (1.0 - c * c).sqrt() / c * sigma
}

/// A line's profile as [`LineColours`] reads it: per polarisation with any light, its share
/// of the equivalent width (nm) and its Lorentzian's half-width (nm) (module notes). The
/// same for [`LineColours::of_profile`] and [`LineColours::in_lobe`], so formed once a line.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineProfile {
    /// The line's centre, nm.
    pub center_nm: f64,
    /// `(width, γ)` of the s and then the p polarisation, the first `count` of them.
    parts: [(f64, f64); 2],
    /// Polarisations with a positive width.
    count: usize,
}

impl LineProfile {
    /// The profile of `line`.
    pub fn of(line: &BraggLine) -> Self {
        Self::of_tanh(line, (line.nu_s.tanh(), line.nu_p.tanh()))
    }

    /// [`LineProfile::of`], given `tanh` of the s and the p coupling (a crossed line's,
    /// taken once for its profile, its band and its notch).
    pub(crate) fn of_tanh(line: &BraggLine, tanh: (f64, f64)) -> Self {
        let scale = line.center_nm / line.layers.max(1.0);
        let mut profile = LineProfile {
            center_nm: line.center_nm,
            parts: [(0.0, 0.0); 2],
            count: 0,
        };
        for (nu, t) in [(line.nu_s, tanh.0), (line.nu_p, tanh.1)] {
            // Half the light is each polarisation's.
            let width = 0.5 * scale * nu * t;
            if width <= 0.0 {
                continue;
            }
            let gamma = lorentz_half_width(nu, t) * scale / std::f64::consts::PI;
            profile.parts[profile.count] = (width, gamma);
            profile.count += 1;
        }
        profile
    }

    /// The polarisations' `(width, γ)`, nm.
    fn parts(&self) -> &[(f64, f64)] {
        &self.parts[..self.count]
    }
}

/// Columns of a row that one parallel task smooths.
const CHUNK: usize = 64;

/// The Lorentzian of half-width `gamma` (nm; 0: none) as taps every step, cut at [`REACH`]
/// half-widths or `columns` steps: its mass over each step (exact for steps finer than its
/// core).
fn lorentzian(gamma: f64, columns: usize) -> Vec<f64> {
    if gamma == 0.0 {
        return vec![1.0];
    }
    let reach = ((REACH * gamma / STEP_NM).ceil() as i64).min(columns as i64);
    (-reach..=reach)
        .map(|k| {
            let x = k as f64 * STEP_NM;
            ((x + 0.5 * STEP_NM) / gamma).atan() - ((x - 0.5 * STEP_NM) / gamma).atan()
        })
        .collect()
}

/// The Gaussian of standard deviation `sigma` (nm) as taps every step, cut at
/// [`GAUSS_REACH`] standard deviations or `columns` steps: its mass over each step.
fn gaussian(sigma: f64, columns: usize) -> Vec<f64> {
    let reach = ((GAUSS_REACH * sigma / STEP_NM).ceil() as i64).min(columns as i64);
    let z = sigma * std::f64::consts::SQRT_2;
    (-reach..=reach)
        .map(|k| {
            let x = k as f64 * STEP_NM;
            0.5 * (erf((x + 0.5 * STEP_NM) / z) - erf((x - 0.5 * STEP_NM) / z))
        })
        .collect()
}

/// `row` = `samples` convolved with `kernel` (an odd number of taps about its centre), the
/// taps beyond the range left out and the sum normalised over the whole kernel (a line near
/// the range's end loses the light beyond it).
fn smooth(samples: &[[f64; 4]], kernel: &[f64], row: &mut [[f32; 4]]) {
    let columns = samples.len() as i64;
    let reach = (kernel.len() / 2) as i64;
    let norm: f64 = kernel.iter().sum();
    row.par_chunks_mut(CHUNK)
        .enumerate()
        .for_each(|(chunk, cells)| {
            for (offset, cell) in cells.iter_mut().enumerate() {
                let i = (chunk * CHUNK + offset) as i64;
                // The taps that fall inside the range, in the kernel's order.
                let (first, last) = ((i - reach).max(0), (i + reach).min(columns - 1));
                let taps = &kernel[(first - (i - reach)) as usize..];
                let mut v = [0.0f64; 4];
                for (s, w) in samples[first as usize..=last as usize].iter().zip(taps) {
                    for c in 0..4 {
                        v[c] += w * s[c];
                    }
                }
                *cell = v.map(|c| (c / norm) as f32);
            }
        });
}

/// The fractional row of [`WIDTHS`] of a Lorentzian of half-width `gamma_nm`.
fn row_of(gamma_nm: f64) -> f64 {
    if gamma_nm <= WIDTHS[1] {
        return (gamma_nm / WIDTHS[1]).max(0.0);
    }
    // Rows 1.. double from WIDTHS[1].
    (1.0 + (gamma_nm / WIDTHS[1]).log2()).min((WIDTHS.len() - 1) as f64)
}

/// The half-width in detuning σ of the Lorentzian with a grating's tails `ν²/(2σ²)` and its
/// area `π ν tanh ν`: `ν / (2 tanh ν)` (½ for a thin stack), given `tanh = tanh ν`.
fn lorentz_half_width(nu: f64, tanh: f64) -> f64 {
    if nu < 1e-6 {
        0.5
    } else {
        nu / (2.0 * tanh)
    }
}

/// `∫ R dλ` of `line`, nm (module notes).
pub fn equivalent_width_nm(line: &BraggLine) -> f64 {
    let n = line.layers.max(1.0);
    let part = |nu: f64| nu * nu.tanh();
    line.center_nm / n * 0.5 * (part(line.nu_s) + part(line.nu_p))
}

#[cfg(test)]
mod tests;

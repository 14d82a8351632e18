//! The CIE 1931 2° colour-matching functions (the official 1 nm table, `data/cie/`) and their
//! averages over the bins of a wavelength grid (paper §3.4, fig. 8).

use std::sync::OnceLock;

use crate::spectrum::WavelengthGrid;

/// The CIE 1931 2° observer at 1 nm, 360–830 nm: `wavelength_nm,x_bar,y_bar,z_bar`.
const CIE1931_CSV: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../data/cie/cie1931_2deg_xyz_1nm.csv"
));

/// The CMF table as three piecewise-linear functions `(wavelength_nm, value)`, parsed once.
pub(crate) fn cmf_samples() -> &'static [Vec<(f64, f64)>; 3] {
    static TABLE: OnceLock<[Vec<(f64, f64)>; 3]> = OnceLock::new();
    TABLE.get_or_init(|| {
        let rows = parse_embedded_table(CIE1931_CSV, 3);
        [0, 1, 2].map(|k| rows.iter().map(|(w, v)| (*w, v[k])).collect())
    })
}

/// Parse one of the shipped CIE tables: a header line, then `wavelength,v1,…,vn` rows.
/// The tables are compiled in and checked by the tests, so a malformed one is a build defect.
pub(crate) fn parse_embedded_table(text: &str, columns: usize) -> Vec<(f64, Vec<f64>)> {
    text.lines()
        .skip(1)
        .filter(|line| !line.trim().is_empty())
        .map(|line| {
            let mut fields = line.split(',').map(|f| {
                f.trim()
                    .parse::<f64>()
                    .expect("shipped CIE table holds numbers")
            });
            let wavelength = fields
                .next()
                .expect("shipped CIE table row has a wavelength");
            let values: Vec<f64> = fields.collect();
            assert_eq!(values.len(), columns, "shipped CIE table row width");
            (wavelength, values)
        })
        .collect()
}

/// The colour-matching functions x̄ ȳ z̄ at `wavelength_nm`, linearly interpolated in the 1 nm
/// table; zero outside 360–830 nm.
pub fn cmf_at(wavelength_nm: f64) -> [f64; 3] {
    cmf_samples()
        .each_ref()
        .map(|s| interpolate(s, wavelength_nm))
}

/// The piecewise-linear function through `samples` (sorted by x) at `x`; zero outside.
pub(crate) fn interpolate(samples: &[(f64, f64)], x: f64) -> f64 {
    let i = samples.partition_point(|&(sx, _)| sx <= x);
    if i == 0 || (i == samples.len() && x > samples[i - 1].0) {
        return 0.0;
    }
    if i == samples.len() {
        return samples[i - 1].1;
    }
    let ((x0, y0), (x1, y1)) = (samples[i - 1], samples[i]);
    y0 + (y1 - y0) * (x - x0) / (x1 - x0)
}

/// The CIE 1931 2° colour-matching functions averaged over each bin of a wavelength grid,
/// pre-multiplied by the bin width, so that a bin-averaged spectrum `s` (see
/// [`crate::spectrum`]) has tristimulus values `X = Σ_b s_b · x̄_b · Δλ` (and Y, Z alike).
///
/// The bin averages are exact integrals of the piecewise-linear 1 nm table, so a 10 nm grid
/// loses nothing of the table; the only approximation is the spectrum's own binning.
#[derive(Clone, Debug, PartialEq)]
pub struct ColorMatcher {
    grid: WavelengthGrid,
    /// `x̄_b · Δλ`, `ȳ_b · Δλ`, `z̄_b · Δλ` per bin (nm).
    weights: [Vec<f32>; 3],
}

impl ColorMatcher {
    /// Average the CMFs over every bin of `grid`.
    pub fn new(grid: &WavelengthGrid) -> Self {
        let width = grid.bin_width_nm();
        let weights = cmf_samples().each_ref().map(|samples| {
            grid.bin_average(samples)
                .into_iter()
                .map(|v| (v * width) as f32)
                .collect()
        });
        ColorMatcher {
            grid: *grid,
            weights,
        }
    }

    /// The grid the matcher was built for.
    pub fn grid(&self) -> &WavelengthGrid {
        &self.grid
    }

    /// Per-bin weights `[x̄_b Δλ, ȳ_b Δλ, z̄_b Δλ]` (nm), one slice per component.
    pub fn weights(&self) -> &[Vec<f32>; 3] {
        &self.weights
    }

    /// Tristimulus values `[X, Y, Z]` of a bin-averaged spectrum (`grid.bins` values, in the
    /// spectrum's units × nm). Extra values beyond `grid.bins` are ignored; a shorter spectrum
    /// counts only its bins.
    #[inline]
    pub fn to_xyz(&self, spectrum: &[f32]) -> [f32; 3] {
        let [wx, wy, wz] = &self.weights;
        dot3(spectrum, wx, wy, wz)
    }
}

/// Lanes of the partial sums in [`dot3`]: wide enough for the compiler to use SIMD registers,
/// and a fixed summation order, so results never depend on the machine or thread count.
const LANES: usize = 8;

/// Three dot products of `s` with `a`, `b`, `c` (over the shortest length).
#[inline(always)]
pub(crate) fn dot3(s: &[f32], a: &[f32], b: &[f32], c: &[f32]) -> [f32; 3] {
    [dot(s, a), dot(s, b), dot(s, c)]
}

/// The dot product of `s` and `w` over the shorter length, summed in [`LANES`] independent
/// partial sums that the compiler keeps in vector registers.
#[inline(always)]
fn dot(s: &[f32], w: &[f32]) -> f32 {
    let n = s.len().min(w.len());
    let (s, w) = (&s[..n], &w[..n]);
    let lanes = |x: &[f32]| -> [f32; LANES] { x.try_into().expect("chunks_exact(LANES)") };
    let mut acc = [0.0f32; LANES];
    for (s, w) in s.chunks_exact(LANES).zip(w.chunks_exact(LANES)) {
        let (s, w) = (lanes(s), lanes(w));
        for l in 0..LANES {
            acc[l] += s[l] * w[l];
        }
    }
    let tail = n / LANES * LANES;
    let mut sum = acc.iter().sum::<f32>();
    for i in tail..n {
        sum += s[i] * w[i];
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cmf_table_matches_printed_cie_values() {
        // CIE 1931 2° observer, 1 nm table (ISO/CIE 11664-1): ȳ(555) = 1.0,
        // x̄(600) = 1.0622, ȳ(600) = 0.631, z̄(600) = 0.0008, x̄(700) = 0.01135916.
        assert_eq!(cmf_at(555.0)[1], 1.0);
        assert_eq!(cmf_at(600.0), [1.0622, 0.631, 0.0008]);
        assert_eq!(cmf_at(700.0)[0], 0.01135916);
        assert_eq!(cmf_samples()[0].len(), 471);
        assert_eq!(cmf_at(359.0), [0.0; 3]);
        assert_eq!(cmf_at(831.0), [0.0; 3]);
    }

    #[test]
    fn interpolate_is_linear_between_samples_and_zero_outside() {
        let s = [(1.0, 2.0), (3.0, 6.0)];
        assert_eq!(interpolate(&s, 2.0), 4.0);
        assert_eq!(interpolate(&s, 3.0), 6.0);
        assert_eq!(interpolate(&s, 0.5), 0.0);
        assert_eq!(interpolate(&s, 3.5), 0.0);
    }

    #[test]
    fn matcher_weights_sum_to_the_cmf_integrals() {
        // On a grid covering the whole table, Σ_b ȳ_b Δλ is the integral of ȳ: 106.857 nm
        // for the 1931 observer (the sum of the CIE's 1 nm ȳ column, 106.8569, less half
        // of its two end values, which are below 5e-6).
        let m = ColorMatcher::new(&WavelengthGrid::new(360.0, 830.0, 47).unwrap());
        let y: f64 = m.weights()[1].iter().map(|&v| v as f64).sum();
        assert!((y - 106.857).abs() < 0.01, "{y}");
    }

    #[test]
    fn dot3_matches_a_plain_sum_for_any_length() {
        for n in [0, 1, 7, 8, 9, 40, 41] {
            let s: Vec<f32> = (0..n).map(|i| i as f32 * 0.5).collect();
            let a: Vec<f32> = (0..n).map(|i| 1.0 + i as f32).collect();
            let plain: f32 = s.iter().zip(&a).map(|(x, y)| x * y).sum();
            let [x, y, z] = dot3(&s, &a, &a, &a);
            assert!((x - plain).abs() <= 1e-4 * plain.max(1.0));
            assert_eq!((x, x), (y, z));
        }
    }
}

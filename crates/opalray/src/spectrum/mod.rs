//! Spectral sampling: the wavelength grid that travels with every spectral buffer.
//!
//! A spectrum in opalray is a flat `[f32]` of `bins` values, one per wavelength bin of a
//! [`WavelengthGrid`]. Each value is the *average* of the underlying continuous quantity over
//! its bin (a reflectance averaged over 10 nm, a radiance per nm averaged over 10 nm), so
//! narrow features such as opal's Bragg lines are integrated, never point-sampled.

mod image;

pub use image::SpectralImage;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};

/// Largest bin count accepted (1 nm bins over 380–780 nm is 400).
pub const MAX_BINS: usize = 1000;
/// Bins of the default grid. The hottest spectral loops have a copy for this length known when
/// compiling ([`add_product`], [`add_scaled`]).
pub const DEFAULT_BINS: usize = 40;

/// Equal-width wavelength bins over `[min_nm, max_nm]`.
///
/// | field    | unit | default | valid range                 |
/// |----------|------|---------|-----------------------------|
/// | `min_nm` | nm   | 380     | 200 ≤ min_nm < max_nm        |
/// | `max_nm` | nm   | 780     | max_nm ≤ 2000                |
/// | `bins`   | –    | 40      | 1 ..= 1000                   |
#[derive(Clone, Copy, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct WavelengthGrid {
    /// Lower edge of the first bin, nm.
    pub min_nm: f64,
    /// Upper edge of the last bin, nm.
    pub max_nm: f64,
    /// Number of bins.
    pub bins: usize,
}

impl Default for WavelengthGrid {
    fn default() -> Self {
        WavelengthGrid {
            min_nm: 380.0,
            max_nm: 780.0,
            bins: DEFAULT_BINS,
        }
    }
}

impl WavelengthGrid {
    /// A grid of `bins` equal bins over `[min_nm, max_nm]`, validated.
    pub fn new(min_nm: f64, max_nm: f64, bins: usize) -> Result<Self> {
        let grid = WavelengthGrid {
            min_nm,
            max_nm,
            bins,
        };
        grid.validate("spectrum")?;
        Ok(grid)
    }

    /// Check the ranges in the table above; `prefix` is the field path used in errors.
    pub fn validate(&self, prefix: &str) -> Result<()> {
        if !(self.min_nm.is_finite() && (200.0..2000.0).contains(&self.min_nm)) {
            return Err(Error::field(
                format!("{prefix}.min_nm"),
                format!("must be in [200, 2000) nm, got {}; try 380", self.min_nm),
            ));
        }
        if !(self.max_nm.is_finite() && self.max_nm > self.min_nm && self.max_nm <= 2000.0) {
            return Err(Error::field(
                format!("{prefix}.max_nm"),
                format!(
                    "must be greater than min_nm ({}) and at most 2000 nm, got {}; try 780",
                    self.min_nm, self.max_nm
                ),
            ));
        }
        if !(1..=MAX_BINS).contains(&self.bins) {
            return Err(Error::field(
                format!("{prefix}.bins"),
                format!("must be in 1..={MAX_BINS}, got {}; try 40", self.bins),
            ));
        }
        Ok(())
    }

    /// Width of one bin, nm.
    pub fn bin_width_nm(&self) -> f64 {
        (self.max_nm - self.min_nm) / self.bins as f64
    }

    /// Centre wavelength of bin `i`, nm.
    pub fn center_nm(&self, i: usize) -> f64 {
        self.min_nm + (i as f64 + 0.5) * self.bin_width_nm()
    }

    /// Lower and upper edge of bin `i`, nm.
    pub fn edges_nm(&self, i: usize) -> (f64, f64) {
        let w = self.bin_width_nm();
        (self.min_nm + i as f64 * w, self.min_nm + (i + 1) as f64 * w)
    }

    /// All bin centres, nm.
    pub fn centers_nm(&self) -> Vec<f64> {
        (0..self.bins).map(|i| self.center_nm(i)).collect()
    }

    /// The bin holding `wavelength_nm`, or `None` outside the grid.
    pub fn bin_of(&self, wavelength_nm: f64) -> Option<usize> {
        if wavelength_nm < self.min_nm || wavelength_nm >= self.max_nm {
            return None;
        }
        Some((((wavelength_nm - self.min_nm) / self.bin_width_nm()) as usize).min(self.bins - 1))
    }

    /// Average a function sampled on a fine wavelength grid over each bin.
    ///
    /// `samples` are `(wavelength_nm, value)` pairs in increasing wavelength, any spacing; the
    /// function is taken as piecewise linear between them and zero outside. Returns one
    /// bin-averaged value per bin (the exact integral of the interpolant over the bin divided
    /// by the bin width).
    pub fn bin_average(&self, samples: &[(f64, f64)]) -> Vec<f64> {
        (0..self.bins)
            .map(|i| {
                let (lo, hi) = self.edges_nm(i);
                integrate_piecewise_linear(samples, lo, hi) / (hi - lo)
            })
            .collect()
    }
}

/// `n` zeros, written by all threads. `vec![0.0; n]` is one thread's `memset` where the
/// allocator reuses memory (every frame after the first): a render zeroes a few hundred
/// megabytes, and the other core would wait.
pub fn zeroed(n: usize) -> Vec<f32> {
    use rayon::prelude::*;
    let mut v = Vec::with_capacity(n);
    v.par_extend(rayon::iter::repeat_n(0.0f32, n));
    v
}

/// `acc += k · a ⊙ b`, element by element over `acc` (`a` and `b` at least as long).
///
/// With the loop's length known when compiling, the compiler turns it into a straight run of
/// vector instructions; a loop over slices of any length is vectorised 32 values at a time and
/// leaves the last 8 of 40 bins to scalar code. So spectra of [`DEFAULT_BINS`] values take a
/// copy of their own (the same operations in the same order: the same bits).
#[inline(always)]
pub fn add_product(acc: &mut [f32], a: &[f32], b: &[f32], k: f32) {
    const N: usize = DEFAULT_BINS;
    if let (Ok(acc), Some(Ok(a)), Some(Ok(b))) = (
        <&mut [f32; N]>::try_from(&mut *acc),
        a.get(..N).map(<&[f32; N]>::try_from),
        b.get(..N).map(<&[f32; N]>::try_from),
    ) {
        for i in 0..N {
            acc[i] += k * a[i] * b[i];
        }
        return;
    }
    for ((p, &x), &y) in acc.iter_mut().zip(a).zip(b) {
        *p += k * x * y;
    }
}

/// `acc += w · a`, element by element over `acc` (`a` at least as long); as [`add_product`],
/// with a copy for [`DEFAULT_BINS`] values.
#[inline(always)]
pub fn add_scaled(acc: &mut [f32], a: &[f32], w: f32) {
    const N: usize = DEFAULT_BINS;
    if let (Ok(acc), Some(Ok(a))) = (
        <&mut [f32; N]>::try_from(&mut *acc),
        a.get(..N).map(<&[f32; N]>::try_from),
    ) {
        for i in 0..N {
            acc[i] += a[i] * w;
        }
        return;
    }
    for (p, &x) in acc.iter_mut().zip(a) {
        *p += x * w;
    }
}

/// Sum of `values` with eight interleaved partial sums, in a fixed order (so the result is
/// reproducible) that the compiler turns into vector additions.
#[inline]
pub fn sum(values: &[f32]) -> f32 {
    dot_with(values, None)
}

/// `Σ a_i · b_i` with eight interleaved partial sums (see [`sum`]); `a` and `b` of equal
/// length.
#[inline]
pub fn dot(a: &[f32], b: &[f32]) -> f32 {
    dot_with(a, Some(b))
}

#[inline(always)]
fn dot_with(a: &[f32], b: Option<&[f32]>) -> f32 {
    let mut acc = [0.0f32; 8];
    let chunks = a.len() / 8;
    for c in 0..chunks {
        let x: &[f32; 8] = a[c * 8..c * 8 + 8].try_into().expect("8 values");
        match b {
            Some(b) => {
                let y: &[f32; 8] = b[c * 8..c * 8 + 8].try_into().expect("8 values");
                for k in 0..8 {
                    acc[k] += x[k] * y[k];
                }
            }
            None => {
                for k in 0..8 {
                    acc[k] += x[k];
                }
            }
        }
    }
    let mut tail = 0.0f32;
    for i in chunks * 8..a.len() {
        tail += a[i] * b.map_or(1.0, |b| b[i]);
    }
    ((acc[0] + acc[4]) + (acc[1] + acc[5])) + ((acc[2] + acc[6]) + (acc[3] + acc[7])) + tail
}

/// Exact integral over `[lo, hi]` of the piecewise-linear function through `samples`
/// (sorted by x), taken as zero outside the samples' range.
pub fn integrate_piecewise_linear(samples: &[(f64, f64)], lo: f64, hi: f64) -> f64 {
    let mut total = 0.0;
    for pair in samples.windows(2) {
        let ((x0, y0), (x1, y1)) = (pair[0], pair[1]);
        let a = x0.max(lo);
        let b = x1.min(hi);
        if b <= a || x1 <= x0 {
            continue;
        }
        let at = |x: f64| y0 + (y1 - y0) * (x - x0) / (x1 - x0);
        total += 0.5 * (at(a) + at(b)) * (b - a);
    }
    total
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spectral_sums_give_the_plain_loops_bits_at_any_length() {
        // The default length takes its own copy of each loop; others the general one. Both
        // must give exactly what the plain loop gives, in f32.
        for n in [DEFAULT_BINS, 7, DEFAULT_BINS + 1, 3 * DEFAULT_BINS] {
            let a: Vec<f32> = (0..n).map(|i| 0.3 + (i as f32 * 0.731).sin()).collect();
            let b: Vec<f32> = (0..n).map(|i| 1.1 + (i as f32 * 1.37).cos()).collect();
            let start: Vec<f32> = (0..n).map(|i| (i as f32 * 0.17).exp() * 1e-3).collect();
            let (k, w) = (0.618_034f32, 1.732_050_8f32);
            let (mut p, mut q) = (start.clone(), start.clone());
            add_product(&mut p, &a, &b, k);
            add_scaled(&mut q, &a, w);
            for i in 0..n {
                assert_eq!(
                    p[i].to_bits(),
                    (start[i] + k * a[i] * b[i]).to_bits(),
                    "{n}: {i}"
                );
                assert_eq!(q[i].to_bits(), (start[i] + a[i] * w).to_bits(), "{n}: {i}");
            }
        }
    }

    #[test]
    fn default_grid_has_10_nm_bins_centred_on_385() {
        let g = WavelengthGrid::default();
        assert_eq!(g.bin_width_nm(), 10.0);
        assert_eq!(g.center_nm(0), 385.0);
        assert_eq!(g.center_nm(39), 775.0);
        assert_eq!(g.bin_of(779.9), Some(39));
        assert_eq!(g.bin_of(780.0), None);
    }

    #[test]
    fn bin_average_of_a_line_is_its_value_at_the_bin_centre() {
        let g = WavelengthGrid::new(400.0, 500.0, 4).unwrap();
        let samples: Vec<(f64, f64)> = (390..=510).map(|x| (x as f64, 2.0 * x as f64)).collect();
        for (i, v) in g.bin_average(&samples).iter().enumerate() {
            assert!((v - 2.0 * g.center_nm(i)).abs() < 1e-9);
        }
    }

    #[test]
    fn a_narrow_line_keeps_its_area_when_binned() {
        // A 2 nm wide triangle of area 1 between 401 and 403 nm: the bin average over a
        // 10 nm bin must be area / width = 0.1, wherever the line falls in the bin.
        let g = WavelengthGrid::new(400.0, 410.0, 1).unwrap();
        let samples = [(401.0, 0.0), (402.0, 1.0), (403.0, 0.0)];
        assert!((g.bin_average(&samples)[0] - 0.1).abs() < 1e-12);
    }

    #[test]
    fn vector_sums_match_plain_sums() {
        let a: Vec<f32> = (0..43).map(|i| i as f32 * 0.25).collect();
        let b: Vec<f32> = (0..43).map(|i| 1.0 + i as f32).collect();
        let plain: f64 = a.iter().map(|&x| f64::from(x)).sum();
        let plain_dot: f64 = a
            .iter()
            .zip(&b)
            .map(|(&x, &y)| f64::from(x) * f64::from(y))
            .sum();
        assert!((f64::from(sum(&a)) - plain).abs() < 1e-4);
        assert!((f64::from(dot(&a, &b)) - plain_dot).abs() < 1e-2);
    }

    #[test]
    fn invalid_grids_are_refused_with_the_field() {
        let err = WavelengthGrid::new(500.0, 400.0, 10)
            .unwrap_err()
            .to_string();
        assert!(err.contains("spectrum.max_nm"), "{err}");
        let err = WavelengthGrid::new(f64::NAN, 400.0, 10)
            .unwrap_err()
            .to_string();
        assert!(err.contains("spectrum.min_nm"), "{err}");
        let err = WavelengthGrid::new(380.0, 780.0, 0)
            .unwrap_err()
            .to_string();
        assert!(err.contains("spectrum.bins"), "{err}");
    }
}

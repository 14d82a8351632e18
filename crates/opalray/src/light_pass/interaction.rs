//! What a cluster does to light crossing it, read from the optics tables with a fast path for
//! angles where the tables are flat in wavelength (no Bragg line in the visible).

use crate::optics::OpticsTables;

mod transmission;

pub use transmission::Transmission;

/// Largest spread over wavelength (max − min of R, T and D) for a table row to count as flat.
/// Away from its stop band a natural-opal cluster reflects about 2·10⁻⁴ at every wavelength
/// (the weak contrast of its layers); treating such rows as flat, at their mean values,
/// conserves the energy and changes the spectrum of a ray by less than 0.2 % per cluster,
/// while sparing two thirds of all crossings the per-wavelength work.
const FLAT_TOLERANCE: f32 = 2e-3;

/// `out = a + w (b − a)`, element by element (zipped slices: no bounds checks, vectorised).
#[inline(always)]
fn lerp(out: &mut [f32], a: &[f32], b: &[f32], w: f32) {
    for ((o, &a), &b) in out.iter_mut().zip(a).zip(b) {
        *o = a + w * (b - a);
    }
}

fn mean(v: &[f32]) -> f32 {
    v.iter().sum::<f32>() / v.len() as f32
}

/// The split of light meeting a cluster's (111) planes at one angle.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Split {
    /// The same fractions at every wavelength: specular `r`, transmitted `t`, diffuse `d`.
    Flat {
        /// Specular (Bragg) reflectance.
        r: f32,
        /// Transmittance.
        t: f32,
        /// Diffuse fraction.
        d: f32,
    },
    /// Fractions vary with wavelength only in the bins `lo..hi` (the Bragg line), where they
    /// were written into the caller's buffers; elsewhere they are the flat `r`, `t`, `d`.
    Window {
        /// First bin of the window.
        lo: usize,
        /// One past the last bin of the window.
        hi: usize,
        /// Specular reflectance outside the window.
        r: f32,
        /// Transmittance outside the window.
        t: f32,
        /// Diffuse fraction outside the window.
        d: f32,
    },
}

/// A table row that is flat except in a window of bins.
#[derive(Clone, Copy, Debug, PartialEq)]
struct RowWindow {
    lo: usize,
    hi: usize,
    background: (f32, f32, f32),
}

fn median(v: &[f32]) -> f32 {
    let mut s = v.to_vec();
    s.sort_by(f32::total_cmp);
    s[s.len() / 2]
}

/// What lies between table rows `i` and `i + 1`, read where a ray meets the planes at an angle
/// between theirs: whether both are flat, the union of their windows, and the flat or
/// background values (R, T, D) of row `i` with the step to row `i + 1`.
#[derive(Clone, Copy, Debug, PartialEq)]
struct RowPair {
    flat: bool,
    lo: usize,
    hi: usize,
    level: [f32; 3],
    step: [f32; 3],
}

impl RowPair {
    /// The flat or background value of table `which` (0 = R, 1 = T, 2 = D) at weight `w`.
    #[inline(always)]
    fn at(&self, which: usize, w: f32) -> f32 {
        self.level[which] + w * self.step[which]
    }
}

/// The optics tables plus, per pair of neighbouring rows, where they are flat.
#[derive(Debug)]
pub struct ClusterOptics<'a> {
    tables: &'a OpticsTables,
    pairs: Vec<RowPair>,
}

impl<'a> ClusterOptics<'a> {
    /// Summarise `tables`.
    pub fn new(tables: &'a OpticsTables) -> Self {
        let flat: Vec<Option<(f32, f32, f32)>> = (0..tables.angles)
            .map(|i| {
                let (r, t, d) = tables.row(i);
                let spread = |v: &[f32]| {
                    let (lo, hi) = v
                        .iter()
                        .fold((f32::INFINITY, f32::NEG_INFINITY), |(lo, hi), &x| {
                            (lo.min(x), hi.max(x))
                        });
                    hi - lo
                };
                (spread(r) <= FLAT_TOLERANCE
                    && spread(t) <= FLAT_TOLERANCE
                    && spread(d) <= FLAT_TOLERANCE)
                    .then(|| (mean(r), mean(t), mean(d)))
            })
            .collect();
        // Rows that are not flat: the median of each table is the level away from the Bragg
        // line, and the window spans every bin that differs from it by more than the tolerance.
        let windows: Vec<RowWindow> = (0..tables.angles)
            .map(|i| {
                let (r, t, d) = tables.row(i);
                let background = (median(r), median(t), median(d));
                let off = |b: usize| {
                    (r[b] - background.0).abs() > FLAT_TOLERANCE
                        || (t[b] - background.1).abs() > FLAT_TOLERANCE
                        || (d[b] - background.2).abs() > FLAT_TOLERANCE
                };
                let lo = (0..r.len()).find(|&b| off(b)).unwrap_or(0);
                let hi = (0..r.len()).rev().find(|&b| off(b)).map_or(0, |b| b + 1);
                RowWindow { lo, hi, background }
            })
            .collect();
        // A flat row's window is empty and its background its mean.
        let window_of = |k: usize| match flat[k] {
            Some(mean) => RowWindow {
                lo: usize::MAX,
                hi: 0,
                background: mean,
            },
            None => windows[k],
        };
        let pairs = (0..tables.angles - 1)
            .map(|i| {
                let (a, b) = (window_of(i), window_of(i + 1));
                let flat = flat[i].is_some() && flat[i + 1].is_some();
                let (lo, hi) = if flat {
                    (0, 0)
                } else {
                    (a.lo.min(b.lo), a.hi.max(b.hi))
                };
                let (x, y) = (a.background, b.background);
                RowPair {
                    flat,
                    lo,
                    hi,
                    level: [x.0, x.1, x.2],
                    step: [y.0 - x.0, y.1 - x.1, y.2 - x.2],
                }
            })
            .collect();
        ClusterOptics { tables, pairs }
    }

    /// The tables.
    pub fn tables(&self) -> &OpticsTables {
        self.tables
    }

    /// The split at `cos_theta` (|cos| of the angle between ray and plane normal, inside the
    /// stone). Fills `r`, `t`, `d` in the window's bins only when the answer is
    /// [`Split::Window`].
    #[inline(always)]
    pub fn split(&self, cos_theta: f32, r: &mut [f32], t: &mut [f32], d: &mut [f32]) -> Split {
        let (i, w) = self.row_at(cos_theta);
        let pair = &self.pairs[i];
        if pair.flat {
            return Split::Flat {
                r: pair.at(0, w),
                t: pair.at(1, w),
                d: pair.at(2, w),
            };
        }
        // The union of both rows' windows, interpolated densely inside.
        let (lo, hi) = (pair.lo, pair.hi);
        let (ra, ta, da) = self.tables.row(i);
        let (rb, tb, db) = self.tables.row(i + 1);
        if lo < hi {
            lerp(&mut r[lo..hi], &ra[lo..hi], &rb[lo..hi], w);
            lerp(&mut t[lo..hi], &ta[lo..hi], &tb[lo..hi], w);
            lerp(&mut d[lo..hi], &da[lo..hi], &db[lo..hi], w);
        }
        Split::Window {
            lo,
            hi,
            r: pair.at(0, w),
            t: pair.at(1, w),
            d: pair.at(2, w),
        }
    }

    /// The table row below `cos_theta` (|cos| of the angle to the planes) and the weight of
    /// the row after it: rows are uniform in cos θ, row 0 at normal incidence.
    #[inline(always)]
    fn row_at(&self, cos_theta: f32) -> (usize, f32) {
        let last = self.tables.angles - 1;
        let f = (1.0 - cos_theta.clamp(0.0, 1.0)) * last as f32;
        // `f` lies in [0, last] (a NaN cosine clamps to NaN and converts to row 0): through
        // i32, the conversion is one instruction where a float → usize cast is a dozen.
        let i = (f as i32 as usize).min(last - 1);
        (i, f - i as f32)
    }

    /// Specular reflectance only, at `cos_theta`: `Some(r)` where flat, else `None` with the
    /// spectral reflectance written into `r`.
    #[inline(always)]
    pub fn reflectance(&self, cos_theta: f32, r: &mut [f32]) -> Option<f32> {
        self.one_table(cos_theta, r, 0)
    }

    /// Diffuse part only, at `cos_theta`: `Some(d)` where flat, else `None` with the spectral
    /// diffuse part written into `d`.
    #[inline(always)]
    pub fn diffuse(&self, cos_theta: f32, d: &mut [f32]) -> Option<f32> {
        self.one_table(cos_theta, d, 2)
    }

    /// Table `which` (0 = R, 1 = T, 2 = D) at `cos_theta`.
    #[inline(always)]
    fn one_table(&self, cos_theta: f32, out: &mut [f32], which: usize) -> Option<f32> {
        let pick = |row: (&'a [f32], &'a [f32], &'a [f32])| [row.0, row.1, row.2][which];
        let (i, w) = self.row_at(cos_theta);
        let pair = &self.pairs[i];
        if pair.flat {
            return Some(pair.at(which, w));
        }
        let a = pick(self.tables.row(i));
        let b = pick(self.tables.row(i + 1));
        for ((o, a), b) in out.iter_mut().zip(a).zip(b) {
            *o = a + w * (b - a);
        }
        None
    }
}

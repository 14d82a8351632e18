//! What a cluster does to light crossing it, read from the optics tables with a fast path for
//! angles where the tables are flat in wavelength (no Bragg line in the visible).

use crate::optics::OpticsTables;

/// Largest spread over wavelength for a table row to count as flat.
const FLAT_TOLERANCE: f32 = 1e-6;

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
    /// Fractions vary with wavelength; they were written into the caller's buffers.
    Spectral,
}

/// The optics tables plus, per row, whether the row is flat.
#[derive(Debug)]
pub struct ClusterOptics<'a> {
    tables: &'a OpticsTables,
    flat: Vec<Option<(f32, f32, f32)>>,
}

impl<'a> ClusterOptics<'a> {
    /// Summarise `tables`.
    pub fn new(tables: &'a OpticsTables) -> Self {
        let flat = (0..tables.angles)
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
                    .then(|| (r[0], t[0], d[0]))
            })
            .collect();
        ClusterOptics { tables, flat }
    }

    /// The tables.
    pub fn tables(&self) -> &OpticsTables {
        self.tables
    }

    /// The split at `cos_theta` (|cos| of the angle between ray and plane normal, inside the
    /// stone). Fills `r`, `t`, `d` only when the answer is [`Split::Spectral`].
    #[inline]
    pub fn split(&self, cos_theta: f32, r: &mut [f32], t: &mut [f32], d: &mut [f32]) -> Split {
        let last = self.tables.angles - 1;
        let f = (1.0 - cos_theta.clamp(0.0, 1.0)) * last as f32;
        let i = (f as usize).min(last - 1);
        let w = f - i as f32;
        if let (Some(a), Some(b)) = (self.flat[i], self.flat[i + 1]) {
            return Split::Flat {
                r: a.0 + w * (b.0 - a.0),
                t: a.1 + w * (b.1 - a.1),
                d: a.2 + w * (b.2 - a.2),
            };
        }
        self.tables.lookup(cos_theta, r, t, d);
        Split::Spectral
    }

    /// Transmittance only, at `cos_theta`: `Some(t)` where flat, else `None` with the
    /// spectral transmittance written into `t`.
    #[inline]
    pub fn transmittance(&self, cos_theta: f32, t: &mut [f32]) -> Option<f32> {
        let last = self.tables.angles - 1;
        let f = (1.0 - cos_theta.clamp(0.0, 1.0)) * last as f32;
        let i = (f as usize).min(last - 1);
        let w = f - i as f32;
        if let (Some(a), Some(b)) = (self.flat[i], self.flat[i + 1]) {
            return Some(a.1 + w * (b.1 - a.1));
        }
        let (_, t0, _) = self.tables.row(i);
        let (_, t1, _) = self.tables.row(i + 1);
        for ((out, a), b) in t.iter_mut().zip(t0).zip(t1) {
            *out = a + w * (b - a);
        }
        None
    }
}

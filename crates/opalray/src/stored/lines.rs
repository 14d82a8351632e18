//! The stored method's view of a path's wavelengths: the list of the Bragg lines it met
//! ([`Lines`]), each reflected by or passed through, its product evaluated at the end by
//! quadrature ([`SpectralSampler::integrate`]); the path tracer's carrier is
//! [`PathSpectrum`](crate::path::spectral::PathSpectrum) (the module notes in
//! [`crate::path::spectral`]).

use crate::optics::BraggLine;
use crate::stone::ironstone_reflectance;

use crate::film::sensor::{SpectralSampler, MAX_TINTS};

/// Most lines one contribution carries.
pub const MAX_LINES: usize = 24;
/// Room kept for reflections: transmission notches past `MAX_LINES − RESERVED` are dropped.
const RESERVED: usize = 8;
/// Largest step of [`SpectralSampler::integrate`]'s quadrature, nm.
pub const QUADRATURE_STEP_NM: f64 = 0.25;

/// The Bragg lines of one path, each reflected by or passed through.
#[derive(Clone, Copy, Debug)]
pub struct Lines {
    lines: [(BraggLine, bool); MAX_LINES],
    /// Each line's window (`BraggLine::window_nm`), outside which its R is taken as 0.
    windows: [(f64, f64); MAX_LINES],
    len: usize,
    first_reflection: Option<usize>,
    /// A reflection found no room: the path's spectrum is unknown and it adds nothing.
    lost: bool,
    /// Diffuse reflections by ironstone (factor [`ironstone_reflectance`] each).
    tints: u8,
}

impl Default for Lines {
    fn default() -> Self {
        Lines {
            lines: [(BraggLine::new(0.0, 1.0, 1.0, 1.0), false); MAX_LINES],
            windows: [(0.0, 0.0); MAX_LINES],
            len: 0,
            first_reflection: None,
            lost: false,
            tints: 0,
        }
    }
}

impl Lines {
    /// A reflection by `line` (factor R).
    pub fn reflect(&mut self, line: BraggLine) {
        self.lost |= self.len == MAX_LINES;
        if self.len < MAX_LINES {
            self.first_reflection.get_or_insert(self.len);
            self.lines[self.len] = (line, true);
            self.windows[self.len] = line.window_nm();
            self.len += 1;
        }
    }

    /// A pass through `line`'s planes (factor 1 − R), kept only on paths that reflect (see
    /// the module's notes).
    pub fn transmit(&mut self, line: BraggLine) {
        if self.len < MAX_LINES - RESERVED {
            self.lines[self.len] = (line, false);
            self.windows[self.len] = line.window_nm();
            self.len += 1;
        }
    }

    /// A diffuse reflection by ironstone. Past [`MAX_TINTS`] the path is dropped (it then
    /// carries under 0.22⁴ = 0.2 % of the light).
    pub fn tint(&mut self) {
        self.lost |= usize::from(self.tints) == MAX_TINTS;
        self.tints = self.tints.saturating_add(1);
    }

    /// Whether the path was reflected by any line.
    pub fn reflects(&self) -> bool {
        self.first_reflection.is_some()
    }

    /// The spectral factor `Π f_k(λ)`.
    #[inline]
    pub fn factor(&self, wavelength_nm: f64) -> f64 {
        let mut f = 1.0;
        if self.tints > 0 {
            f = ironstone_reflectance(wavelength_nm).powi(i32::from(self.tints));
        }
        for ((line, reflect), (lo, hi)) in self.lines[..self.len].iter().zip(&self.windows) {
            let inside = (*lo..=*hi).contains(&wavelength_nm);
            if *reflect {
                if !inside {
                    return 0.0;
                }
                f *= line.reflectance(wavelength_nm);
            } else if inside {
                f *= 1.0 - line.reflectance(wavelength_nm);
            }
        }
        f
    }
}

impl SpectralSampler {
    /// Add `weight · ∫ Π f(λ) S(λ) c̄(λ) dλ` of `lines` to `xyz` and the binned spectrum to
    /// `bins`, by the midpoint rule over the first reflection's window (within the range), at
    /// steps of at most [`QUADRATURE_STEP_NM`] (a line's core, ~2 nm, takes about ten; its
    /// side lobes, λ/N ≈ 1.5 nm apart, six each). A path without reflection adds the light's
    /// white. Deterministic: the same lines give the same bits.
    pub fn integrate(&self, lines: &Lines, weight: f64, xyz: &mut [f64; 3], bins: &mut [f32]) {
        if weight == 0.0 || lines.lost {
            return;
        }
        let Some(first) = lines.first_reflection else {
            self.add_white(lines.tints, weight, xyz, bins);
            return;
        };
        let (a, z) = lines.windows[first];
        let (a, z) = (a.max(self.lo_nm), z.min(self.hi_nm));
        if z <= a {
            return;
        }
        let steps = ((z - a) / QUADRATURE_STEP_NM).ceil().max(1.0);
        let step = (z - a) / steps;
        let bin_width = self.grid.bin_width_nm();
        let mut sum = [0.0f64; 3];
        for j in 0..steps as usize {
            let w = a + (j as f64 + 0.5) * step;
            let f = lines.factor(w) * step;
            if f == 0.0 {
                continue;
            }
            let s = self.at(w);
            for (v, c) in sum.iter_mut().zip(&s) {
                *v += f * f64::from(*c);
            }
            if let Some(b) = self.grid.bin_of(w) {
                bins[b] += (weight * f * f64::from(s[3]) / bin_width) as f32;
            }
        }
        for (v, s) in xyz.iter_mut().zip(sum) {
            *v += weight * s;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Illuminant;
    use crate::spectrum::WavelengthGrid;

    #[test]
    fn the_quadrature_of_a_line_and_its_notches_matches_a_fine_sum() {
        // Independent: the same product summed at 0.002 nm (R of the reflecting line times
        // 1 − R of a notch half a line-width off its centre, and of a thin stack's broad one).
        let s = SpectralSampler::new(Illuminant::D65, &WavelengthGrid::default(), 4);
        let line = BraggLine::new(0.0037, 589.0, 1.0, 400.0);
        let notch = BraggLine::new(0.0037, 590.0, 1.0, 300.0);
        let broad = BraggLine::new(0.0037, 585.0, 1.0, 20.0);
        let mut lines = Lines::default();
        lines.reflect(line);
        lines.transmit(notch);
        lines.transmit(broad);
        let mut brute = [0.0; 4];
        let step = 0.002;
        let mut w = 380.0 + 0.5 * step;
        while w < 780.0 {
            let f = lines.factor(w) * step;
            for (b, c) in brute.iter_mut().zip(s.at(w)) {
                *b += f * f64::from(c);
            }
            w += step;
        }
        let (mut xyz, mut bins) = ([0.0; 3], vec![0.0; 40]);
        s.integrate(&lines, 2.0, &mut xyz, &mut bins);
        for c in 0..3 {
            assert!(
                (xyz[c] / (2.0 * brute[c]) - 1.0).abs() < 0.01,
                "{c}: {xyz:?} vs 2 × {brute:?}"
            );
        }
        // The bins hold the same light: their sum × width is the integral of the spectrum.
        let binned: f64 = bins.iter().map(|&b| f64::from(b) * 10.0).sum();
        assert!(
            (binned / (2.0 * brute[3]) - 1.0).abs() < 0.01,
            "{binned} vs 2 × {}",
            brute[3]
        );
    }
}

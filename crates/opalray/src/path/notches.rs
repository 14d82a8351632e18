//! The light of a path not yet reflected by any line: the light's white times the notches of
//! every line it passed, `T(λ) = Π_k (1 − R_k(λ))`, held on the light × colour-matching
//! table of the [`SpectralSampler`] (every 0.25 nm: a line's core, ~2 nm, spans about ten
//! points, its side lobes, λ/N ≈ 1.5 nm apart, six each). Past its first side lobes a notch
//! is its lobes' average ([`wing_reflectance`]): the same light taken, at a fifth of the cost.
//!
//! What the notches take from the white, `∫ (1 − T) S c̄ dλ` (the table's trapezoid rule, the
//! rule the white itself is integrated by), and its share of each bin of the spectral image
//! are kept as the notches are passed: a pass costs the points of the line's window, adding
//! the path's light costs nothing more. A line's reflection branch carries `T R_k` at the
//! wavelengths it draws, the light going on `T (1 − R_k)` here: together the light before the
//! crossing, whatever the number of lines passed and however they overlap (alike plates).

use std::f64::consts::PI;

use crate::optics::BraggLine;
use crate::stone::ironstone_reflectance;

use super::spectral::{reflectance_sp_within, SpectralSampler, TABLE_STEP_NM};
use crate::film::NO_BIN;

/// Side lobes each side of a line's stop band whose reflectance is evaluated as it is; past
/// them, as its average over the lobes ([`wing_reflectance`]).
const CORE_LOBES: f64 = 4.0;
/// Least number of table points a side lobe of a line is evaluated at.
const LOBE_POINTS: f64 = 6.0;
/// Most table points between two evaluations of a line.
const MAX_STRIDE: usize = 64;

/// The notches a path not yet reflected has passed.
#[derive(Clone, Debug)]
pub(super) struct Notches {
    /// `T` at each point of the sampler's table.
    t: Vec<f32>,
    /// `∫ (1 − T) S c̄ dλ`: the XYZ the notches took from the light's white (Y = 1).
    taken_xyz: [f64; 3],
    /// Per bin of the spectral image, `∫_bin (1 − T) S dλ` over the bin's width.
    taken_bins: Vec<f32>,
    /// The table points below `touched.0` and from `touched.1` up hold `T = 1`.
    touched: (usize, usize),
}

impl Notches {
    /// No notch yet, on `sampler`'s table.
    pub(super) fn new(sampler: &SpectralSampler) -> Self {
        let n = sampler.table.len();
        Notches {
            t: vec![1.0; n],
            taken_xyz: [0.0; 3],
            taken_bins: vec![0.0; sampler.grid.bins],
            touched: (n, 0),
        }
    }

    /// A pass through `line` (factor `1 − R` within its window) of light whose s share in
    /// the line's plane is `s_share` (`R = q R_s + (1 − q) R_p`; `None`: unpolarised, the
    /// mean).
    pub(super) fn pass(
        &mut self,
        line: &BraggLine,
        sampler: &SpectralSampler,
        s_share: Option<f64>,
    ) {
        let window = line.window_nm();
        let n = self.t.len();
        let index = |w: f64| (w - sampler.lo_nm) / TABLE_STEP_NM;
        let first = index(window.0).ceil().max(0.0) as usize;
        let last = (index(window.1).floor().max(-1.0) + 1.0).min(n as f64) as usize;
        if first >= last {
            return;
        }
        self.touched = (self.touched.0.min(first), self.touched.1.max(last));
        let bin_width = sampler.grid.bin_width_nm();
        let at = |i: usize| sampler.lo_nm + i as f64 * TABLE_STEP_NM;
        // R at every `stride`-th point, linear between: at least LOBE_POINTS points a side
        // lobe (λ/N apart), so that the broad lines of thin stacks cost what a sharp one does.
        let lobe_steps = line.center_nm / line.layers.max(1.0) / TABLE_STEP_NM;
        let stride = ((lobe_steps / LOBE_POINTS) as usize).clamp(1, MAX_STRIDE);
        let weigh = |(rs, rp): (f64, f64)| match s_share {
            Some(q) => q * rs + (1.0 - q) * rp,
            None => 0.5 * (rs + rp),
        };
        let reflectance = |w: f64| weigh(reflectance_sp_within(line, window, w));
        let (mut a, mut r_a) = (first, reflectance(at(first)));
        let (mut b, mut r_b) = (a, r_a);
        // The bin being added to, held here until the points move on to the next (the same
        // f32 sums, in the same order, as adding to the vector point by point).
        let (mut bin, mut bin_taken) = (NO_BIN, 0.0f32);
        for i in first..last {
            let w = at(i);
            let r = match wing_reflectance(line, w) {
                Some(r) => weigh(r),
                None if stride == 1 => reflectance(w),
                None => {
                    if i > b || b == a {
                        (a, r_a) = (b, r_b);
                        b = (a + stride).min(last - 1);
                        r_b = reflectance(at(b));
                    }
                    if b > a {
                        r_a + (r_b - r_a) * (i - a) as f64 / (b - a) as f64
                    } else {
                        r_a
                    }
                }
            };
            let taken = f64::from(self.t[i]) * r;
            if taken <= 0.0 {
                continue;
            }
            self.t[i] = (f64::from(self.t[i]) - taken) as f32;
            let weight = taken * trapezoid_weight(i, n);
            let s = sampler.table[i];
            for (v, c) in self.taken_xyz.iter_mut().zip(&s) {
                *v += weight * f64::from(*c);
            }
            let here = sampler.table_bins[i];
            if here != NO_BIN {
                if here != bin {
                    if bin != NO_BIN {
                        self.taken_bins[usize::from(bin)] = bin_taken;
                    }
                    bin = here;
                    bin_taken = self.taken_bins[usize::from(bin)];
                }
                bin_taken += (weight * f64::from(s[3]) / bin_width) as f32;
            }
        }
        if bin != NO_BIN {
            self.taken_bins[usize::from(bin)] = bin_taken;
        }
    }

    /// `T` at `wavelength_nm` (linear between the table's points).
    pub(super) fn at(&self, sampler: &SpectralSampler, wavelength_nm: f64) -> f64 {
        let x = ((wavelength_nm - sampler.lo_nm) / TABLE_STEP_NM).max(0.0);
        let i = (x as usize).min(self.t.len() - 2);
        let f = (x - i as f64).min(1.0);
        let (a, b) = (f64::from(self.t[i]), f64::from(self.t[i + 1]));
        a + (b - a) * f
    }

    /// Subtract `weight` × what the notches took from the light's white after `tints`
    /// ironstone reflections from `xyz` and `bins`.
    pub(super) fn take_from(
        &self,
        sampler: &SpectralSampler,
        tints: u8,
        weight: f64,
        xyz: &mut [f64; 3],
        bins: &mut [f32],
    ) {
        if tints == 0 {
            for (v, t) in xyz.iter_mut().zip(&self.taken_xyz) {
                *v -= weight * t;
            }
            for (b, t) in bins.iter_mut().zip(&self.taken_bins) {
                *b -= (weight * f64::from(*t)) as f32;
            }
            return;
        }
        // Ironstone tints what the notches took too (rare: boulder opal before a reflection).
        let n = self.t.len();
        let bin_width = sampler.grid.bin_width_nm();
        for i in self.touched.0..self.touched.1 {
            let taken = 1.0 - f64::from(self.t[i]);
            if taken <= 0.0 {
                continue;
            }
            let w = sampler.lo_nm + i as f64 * TABLE_STEP_NM;
            let tint = ironstone_reflectance(w).powi(i32::from(tints));
            let v = weight * taken * tint * trapezoid_weight(i, n);
            let s = sampler.table[i];
            for (x, c) in xyz.iter_mut().zip(&s) {
                *x -= v * f64::from(*c);
            }
            if let Some(b) = sampler.grid.bin_of(w) {
                bins[b] -= (v * f64::from(s[3]) / bin_width) as f32;
            }
        }
    }
}

/// `line`'s reflectance at `wavelength_nm` past its core (the stop band and
/// [`CORE_LOBES`] side lobes each side), averaged over its side lobes: with `s² = σ² − ν²`,
/// `R = ν² sin² s / (s² + ν² sin² s)` (`optics::line`) averages over the phase of `sin² s`
/// to `1 − s/|σ|` (`⟨a sin²/(1 + a sin²)⟩ = 1 − 1/√(1 + a)`, `a = ν²/s²`): what the lobes
/// take from white light, at a fraction of their cost: `(R_s, R_p)`. `None` within the core.
#[inline]
fn wing_reflectance(line: &BraggLine, wavelength_nm: f64) -> Option<(f64, f64)> {
    let ratio = line.center_nm / wavelength_nm;
    let sigma = PI * line.layers * (ratio - 1.0);
    let (nu_s, nu_p) = (line.nu_s * ratio, line.nu_p * ratio);
    if sigma.abs() < nu_s.max(nu_p) + CORE_LOBES * PI {
        return None;
    }
    let average = |nu: f64| 1.0 - (sigma * sigma - nu * nu).sqrt() / sigma.abs();
    Some((average(nu_s), average(nu_p)))
}

/// The trapezoid rule's weight of point `i` of `n` on the table, nm.
fn trapezoid_weight(i: usize, n: usize) -> f64 {
    if i == 0 || i + 1 == n {
        0.5 * TABLE_STEP_NM
    } else {
        TABLE_STEP_NM
    }
}

#[cfg(test)]
mod tests {
    use super::super::spectral::reflectance_within;
    use super::*;
    use crate::scene::Illuminant;
    use crate::spectrum::WavelengthGrid;

    /// `∫ f(λ) S(λ) ȳ(λ) dλ` by the midpoint rule at 0.002 nm (independent of the table's
    /// trapezoid rule).
    fn brute_y(s: &SpectralSampler, f: impl Fn(f64) -> f64) -> f64 {
        let step = 0.002;
        (0..200_000)
            .map(|i| {
                let w = 380.0 + (i as f64 + 0.5) * step;
                let x = ((w - s.lo_nm) / TABLE_STEP_NM).max(0.0);
                let k = (x as usize).min(s.table.len() - 2);
                let g = x - k as f64;
                let y = f64::from(s.table[k][1]) * (1.0 - g) + f64::from(s.table[k + 1][1]) * g;
                f(w) * y * step
            })
            .sum()
    }

    #[test]
    fn the_notches_take_what_their_lines_reflect_even_where_they_overlap() {
        // Sixty alike plates and a line beside them: the light taken is ∫ (1 − Π(1 − R)) S ȳ,
        // by brute force; sixty times one plate's share would be far more.
        let s = SpectralSampler::new(Illuminant::D65, &WavelengthGrid::default(), 4);
        let plate = BraggLine::new(0.0037, 589.3, 1.0, 200.0);
        let other = BraggLine::new(0.0037, 500.0, 1.0, 400.0);
        let mut notches = Notches::new(&s);
        for _ in 0..60 {
            notches.pass(&plate, &s, None);
        }
        notches.pass(&other, &s, None);
        let pass = |l: &BraggLine, w: f64| 1.0 - reflectance_within(l, l.window_nm(), w);
        let brute = brute_y(&s, |w| 1.0 - pass(&plate, w).powi(60) * pass(&other, w));
        let one = brute_y(&s, |w| 1.0 - pass(&plate, w));
        assert!(brute < 0.5 * 60.0 * one, "{brute} vs {}", 60.0 * one);
        let taken = notches.taken_xyz[1];
        assert!((taken / brute - 1.0).abs() < 0.01, "{taken} vs {brute}");
        let (mut xyz, mut bins) = ([1.0; 3], vec![0.0; 40]);
        notches.take_from(&s, 0, 1.0, &mut xyz, &mut bins);
        assert!((xyz[1] - (1.0 - taken)).abs() < 1e-12);
        // The bins lose the same light: their sum × width is the spectrum's integral taken.
        let binned: f64 = bins.iter().map(|&b| f64::from(b) * 10.0).sum();
        let table_s: f64 = (0..s.table.len())
            .map(|i| (1.0 - f64::from(notches.t[i])) * f64::from(s.table[i][3]))
            .sum::<f64>()
            * TABLE_STEP_NM;
        assert!(
            (binned / -table_s - 1.0).abs() < 0.01,
            "{binned} vs {table_s}"
        );
    }
}

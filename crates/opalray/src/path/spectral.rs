//! Wavelengths for the path integrator, and for the stored method's view: a path's spectrum
//! is white until its first reflection by a Bragg line, and from there lies within that line.
//!
//! A path's geometry does not depend on wavelength (no dispersion; choices are made with
//! wavelength-independent probabilities), so its contribution is
//! `w · ∫ Π_k f_k(λ) S(λ) c̄(λ) dλ`, `f_k` = R or 1 − R of line k, S the light's spectrum
//! (luminance 1), c̄ the CIE 1931 colour-matching functions. Without a reflection the product
//! is 1 but for the lines' notches, each under 2.2 nm of the 400 nm range (at most 0.6 % of
//! white light a line, but a path passes hundreds): the path tracer carries them exactly
//! ([`super::notches`]), so that the light going on through a domain loses what its lines
//! reflect; the stored method's view ([`Lines`]) still neglects them. With one, the
//! integrand lives within the line (~2 nm): λ is drawn from a truncated Cauchy law over the
//! first reflection line (90 %) mixed with a uniform law over the range (10 %, so that every
//! wavelength can be drawn and the estimate is unbiased), the draws stratified over the
//! mixture ([`SpectralSampler::draw`]). Narrow lines are thus sampled where they are, and
//! never binned before colour.
//!
//! Two carriers of the product:
//! - [`PathSpectrum`] (the path tracer): until its first reflection, the light's white and
//!   the notches passed on a fine table; the wavelengths are drawn once, at the path's first
//!   reflection, and each carries the product of the path's factors at it from there (hero
//!   wavelengths). Every later line multiplies them at once, so a path can pass any number
//!   of lines, and the share of its light a line reflects is known exactly where the path
//!   must choose ([`PathSpectrum::reflectances`]).
//! - [`Lines`] (the stored method's view): the list of lines itself, its product evaluated
//!   at the end by quadrature ([`SpectralSampler::integrate`]).
//!
//! The light × colour-matching table they are deposited through, and the wavelength draws,
//! are the film's ([`crate::film::sensor`]); the deposits of these two carriers stay here,
//! beside the fields they read.

use crate::optics::BraggLine;
use crate::stone::ironstone_reflectance;

pub(super) use crate::film::sensor::TABLE_STEP_NM;
pub use crate::film::sensor::{SpectralSampler, MAX_TINTS};

use super::notches::Notches;
use super::orders::History;

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

/// Most wavelengths a path carries (`integrator.wavelengths` is at most this).
pub const MAX_DRAWS: usize = 64;

/// `line`'s reflectance at `wavelength_nm` within `window` (its [`BraggLine::window_nm`]), 0
/// outside.
#[inline]
pub(super) fn reflectance_within(
    line: &BraggLine,
    (lo, hi): (f64, f64),
    wavelength_nm: f64,
) -> f64 {
    if (lo..=hi).contains(&wavelength_nm) {
        line.reflectance(wavelength_nm)
    } else {
        0.0
    }
}

/// A path's spectrum in the path tracer: the light's white (with its ironstone tints) times
/// the notches of the lines passed ([`Notches`]) until its first reflection; from there the
/// wavelengths drawn from that line's law ([`SpectralSampler::draw`]), each carrying
/// `Π f_k(λ) / (draws · p(λ))` of the path's lines so far, the notches passed before the
/// reflection among them. Every line is zero outside its window
/// ([`BraggLine::window_nm`]), where it reflects and where it notches alike, so that what a
/// line reflects is exactly what the light going on through it loses.
#[derive(Clone, Debug)]
pub struct PathSpectrum {
    /// The notches passed before the first reflection (`None`: none yet).
    notches: Option<Box<Notches>>,
    /// Diffuse reflections by ironstone before the first reflection.
    tints: u8,
    /// Wavelengths carried (0 before the first reflection).
    draws: u8,
    /// The path adds nothing: its product is 0 at every wavelength it carries, or it met more
    /// ironstone than is tabulated before a reflection.
    dark: bool,
    waves: [f32; MAX_DRAWS],
    weights: [f32; MAX_DRAWS],
    /// What the path has met: its class in the tally by Bragg order ([`super::orders`]).
    pub(super) history: History,
}

impl Default for PathSpectrum {
    fn default() -> Self {
        PathSpectrum {
            notches: None,
            tints: 0,
            draws: 0,
            dark: false,
            waves: [0.0; MAX_DRAWS],
            weights: [0.0; MAX_DRAWS],
            history: History::default(),
        }
    }
}

impl PathSpectrum {
    /// A reflection by `line` (factor R). The first draws the path's wavelengths from the
    /// line's law with `sampler`, stratified with offset `u` in [0, 1).
    pub fn reflect(&mut self, line: BraggLine, sampler: &SpectralSampler, u: f64) {
        let notches = self.notches.take();
        self.reflect_through(line, sampler, u, notches.as_deref());
    }

    /// This path reflected by `line` ([`PathSpectrum::reflect`]), without copying its notches.
    pub fn reflected(&self, line: BraggLine, sampler: &SpectralSampler, u: f64) -> Self {
        let mut out = PathSpectrum {
            notches: None,
            tints: self.tints,
            draws: self.draws,
            dark: self.dark,
            waves: self.waves,
            weights: self.weights,
            history: self.history,
        };
        out.reflect_through(line, sampler, u, self.notches.as_deref());
        out
    }

    /// [`PathSpectrum::reflect`] of a path whose notches so far are `notches`.
    fn reflect_through(
        &mut self,
        line: BraggLine,
        sampler: &SpectralSampler,
        u: f64,
        notches: Option<&Notches>,
    ) {
        self.history.bragg();
        if self.dark {
            return;
        }
        let window = line.window_nm();
        if self.draws == 0 {
            let n = sampler.draws.clamp(1, MAX_DRAWS);
            for j in 0..n {
                let (w, pdf) = sampler.draw(&line, j, u);
                let mut f = reflectance_within(&line, window, w) / (n as f64 * pdf);
                if f > 0.0 {
                    if let Some(notches) = notches {
                        f *= notches.at(sampler, w);
                    }
                    if self.tints > 0 {
                        f *= ironstone_reflectance(w).powi(i32::from(self.tints));
                    }
                }
                self.waves[j] = w as f32;
                self.weights[j] = f as f32;
            }
            self.draws = n as u8;
            self.tints = 0;
        } else {
            for (f, w) in self.carried_mut() {
                if *f != 0.0 {
                    *f *= reflectance_within(&line, window, w) as f32;
                }
            }
        }
        let dark = self.carried().all(|(f, _)| f == 0.0);
        self.dark = dark;
    }

    /// A pass through `line`'s planes (factor 1 − R); `sampler` holds the table a path not
    /// yet reflected carries its notches on.
    pub fn transmit(&mut self, line: BraggLine, sampler: &SpectralSampler) {
        if self.dark {
            return;
        }
        if self.draws == 0 {
            self.notches
                .get_or_insert_with(|| Box::new(Notches::new(sampler)))
                .pass(&line, sampler);
            return;
        }
        let window = line.window_nm();
        for (f, w) in self.carried_mut() {
            if *f != 0.0 {
                *f *= (1.0 - reflectance_within(&line, window, w)) as f32;
            }
        }
    }
    /// A diffuse reflection by ironstone.
    pub fn tint(&mut self) {
        if self.draws == 0 {
            // Past MAX_TINTS white tables the path is dropped (it carries under 0.22⁴ = 0.2 %
            // of the light).
            self.dark |= usize::from(self.tints) == MAX_TINTS;
            self.tints = self.tints.saturating_add(1);
            return;
        }
        for (f, w) in self.carried_mut() {
            *f *= ironstone_reflectance(w) as f32;
        }
    }

    /// Whether the path was reflected by any line.
    pub fn reflects(&self) -> bool {
        self.draws > 0
    }

    /// Whether the path can add nothing; it need not be followed.
    pub fn is_dark(&self) -> bool {
        self.dark
    }

    /// The share of the path's light that `line` reflects, `Σ f_j R(λ_j) / Σ f_j` over the
    /// wavelengths carried (0 for a path not yet reflected or dark), keeping `line`'s
    /// reflectance at each wavelength carried in `r` (0 where the path carries nothing) for
    /// [`PathSpectrum::pass`]: a crossing weighs its lines and then passes them at the same
    /// wavelengths.
    pub fn reflectances(&self, line: &BraggLine, r: &mut [f32; MAX_DRAWS]) -> f64 {
        let window = line.window_nm();
        let (mut total, mut reflected) = (0.0f64, 0.0f64);
        for ((f, w), r) in self.carried().zip(r.iter_mut()) {
            *r = 0.0;
            if f != 0.0 {
                let here = reflectance_within(line, window, w);
                *r = here as f32;
                total += f64::from(f);
                reflected += f64::from(f) * here;
            }
        }
        if total > 0.0 {
            reflected / total
        } else {
            0.0
        }
    }

    /// A pass through a line whose reflectances at the wavelengths carried are `r`, from
    /// [`PathSpectrum::reflectances`] on this path: [`PathSpectrum::transmit`] of a reflected
    /// path without evaluating the line again.
    pub fn pass(&mut self, r: &[f32; MAX_DRAWS]) {
        debug_assert!(self.reflects());
        for ((f, _), r) in self.carried_mut().zip(r) {
            *f *= 1.0 - r;
        }
    }

    /// The carried weights and their wavelengths.
    fn carried(&self) -> impl Iterator<Item = (f32, f64)> + '_ {
        let n = usize::from(self.draws);
        self.weights[..n]
            .iter()
            .zip(&self.waves[..n])
            .map(|(f, w)| (*f, f64::from(*w)))
    }

    fn carried_mut(&mut self) -> impl Iterator<Item = (&mut f32, f64)> + '_ {
        let n = usize::from(self.draws);
        self.weights[..n]
            .iter_mut()
            .zip(&self.waves[..n])
            .map(|(f, w)| (f, f64::from(*w)))
    }
}

impl SpectralSampler {
    /// Add `weight` × the light's white after `tints` ironstone reflections, less what
    /// `notches` took from it.
    fn add_notched(
        &self,
        tints: u8,
        notches: Option<&Notches>,
        weight: f64,
        xyz: &mut [f64; 3],
        bins: &mut [f32],
    ) {
        self.add_white(tints, weight, xyz, bins);
        if let Some(notches) = notches {
            notches.take_from(self, tints, weight, xyz, bins);
        }
    }

    /// Add `weight · ∫ Π f(λ) S(λ) c̄(λ) dλ` of a path's spectrum to `xyz` and the binned
    /// spectrum to `bins`: the light's white before a reflection, else the sum over the
    /// wavelengths it carries.
    pub fn add_path(&self, path: &PathSpectrum, weight: f64, xyz: &mut [f64; 3], bins: &mut [f32]) {
        if weight == 0.0 || path.dark {
            return;
        }
        if !path.reflects() {
            self.add_notched(path.tints, path.notches.as_deref(), weight, xyz, bins);
            return;
        }
        for (f, w) in path.carried() {
            if f != 0.0 {
                self.add_at(w, weight * f64::from(f), xyz, bins);
            }
        }
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
    fn a_white_path_adds_the_lights_white() {
        let s = SpectralSampler::new(Illuminant::D65, &WavelengthGrid::default(), 4);
        let (mut xyz, mut bins) = ([0.0; 3], vec![0.0; 40]);
        s.add_path(&PathSpectrum::default(), 2.0, &mut xyz, &mut bins);
        assert!((xyz[1] - 2.0).abs() < 1e-9);
    }

    #[test]
    fn a_white_path_loses_the_notches_it_passed() {
        // Independent: 1 − ∫ R S ȳ by brute force, for a path that passed a line and has not
        // been reflected: the light its line reflects is not in the light going on.
        let s = SpectralSampler::new(Illuminant::D65, &WavelengthGrid::default(), 4);
        let line = BraggLine::new(0.0037, 589.0, 1.0, 400.0);
        let mut passed = PathSpectrum::default();
        passed.transmit(line, &s);
        let (mut xyz, mut bins) = ([0.0; 3], vec![0.0; 40]);
        s.add_path(&passed, 2.0, &mut xyz, &mut bins);
        let expected =
            2.0 * (1.0 - brute_y(&s, |w| reflectance_within(&line, line.window_nm(), w)));
        assert!(xyz[1] < 1.999, "the notch takes light: {}", xyz[1]);
        assert!((xyz[1] - expected).abs() < 1e-4, "{} vs {expected}", xyz[1]);
    }

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

    /// The mean over `n` stratification offsets of `add_path`'s Y for the path `build` makes
    /// with the offset it is given.
    fn mean_y(s: &SpectralSampler, n: usize, build: impl Fn(f64) -> PathSpectrum) -> f64 {
        (0..n)
            .map(|k| {
                let path = build((k as f64 + 0.5) / n as f64);
                let (mut xyz, mut bins) = ([0.0; 3], vec![0.0; 40]);
                s.add_path(&path, 1.0, &mut xyz, &mut bins);
                xyz[1] / n as f64
            })
            .sum()
    }

    /// `∫ f(λ) S(λ) ȳ(λ) dλ` by the midpoint rule at 0.002 nm.
    fn brute_y(s: &SpectralSampler, f: impl Fn(f64) -> f64) -> f64 {
        let step = 0.002;
        (0..200_000)
            .map(|i| {
                let w = 380.0 + (i as f64 + 0.5) * step;
                f(w) * f64::from(s.at(w)[1]) * step
            })
            .sum()
    }

    #[test]
    fn a_reflected_line_is_integrated_without_bias() {
        // Independent: brute-force quadrature of R(λ)·S·ȳ.
        let s = SpectralSampler::new(Illuminant::E, &WavelengthGrid::default(), 8);
        let line = BraggLine::new(0.0037, 589.0, 1.0, 400.0);
        let brute = brute_y(&s, |w| reflectance_within(&line, line.window_nm(), w));
        let mean = mean_y(&s, 4000, |u| {
            let mut path = PathSpectrum::default();
            path.reflect(line, &s, u);
            path
        });
        assert!((mean / brute - 1.0).abs() < 0.01, "{mean} vs {brute}");
    }

    #[test]
    fn the_lines_around_a_reflection_multiply_it_at_every_wavelength() {
        // Independent: the product R · Π (1 − R) summed at 0.002 nm, for a path that passes a
        // notch and a thin stack's broad line before its reflection and a notch half a
        // line-width off after it.
        let s = SpectralSampler::new(Illuminant::D65, &WavelengthGrid::default(), 4);
        let line = BraggLine::new(0.0037, 589.0, 1.0, 400.0);
        let notch = BraggLine::new(0.0037, 590.0, 1.0, 300.0);
        let before = BraggLine::new(0.0037, 588.0, 1.0, 300.0);
        let broad = BraggLine::new(0.0037, 585.0, 1.0, 20.0);
        // A notch is 1 − R within its window, 1 outside ([`BraggLine::window_nm`]).
        let pass = |l: &BraggLine, w: f64| 1.0 - reflectance_within(l, l.window_nm(), w);
        let brute = brute_y(&s, |w| {
            reflectance_within(&line, line.window_nm(), w)
                * pass(&before, w)
                * pass(&broad, w)
                * pass(&notch, w)
        });
        let mean = mean_y(&s, 4000, |u| {
            let mut path = PathSpectrum::default();
            path.transmit(before, &s);
            path.transmit(broad, &s);
            path.reflect(line, &s, u);
            path.transmit(notch, &s);
            path
        });
        assert!((mean / brute - 1.0).abs() < 0.01, "{mean} vs {brute}");
    }

    #[test]
    fn a_path_keeps_every_line_it_passes_after_its_reflection() {
        // A reflected path passing 60 alike plates (a settled bar seen edge-on) carries
        // (1 − R)⁶⁰ of them: its light falls to the line's wings. Independent: brute force.
        // A list of the lines met, held to a fixed length, would drop the later notches.
        let s = SpectralSampler::new(Illuminant::E, &WavelengthGrid::default(), 8);
        let line = BraggLine::new(0.0037, 589.0, 1.0, 400.0);
        let plate = BraggLine::new(0.0037, 589.3, 1.0, 200.0);
        let plates = 60;
        let window = plate.window_nm();
        let within = |w: f64| reflectance_within(&line, line.window_nm(), w);
        let brute = brute_y(&s, |w| {
            within(w) * (1.0 - reflectance_within(&plate, window, w)).powi(plates)
        });
        let alone = brute_y(&s, within);
        assert!(brute < 0.5 * alone, "the plates matter: {brute} vs {alone}");
        let mean = mean_y(&s, 4000, |u| {
            let mut path = PathSpectrum::default();
            path.reflect(line, &s, u);
            for _ in 0..plates {
                path.transmit(plate, &s);
            }
            path
        });
        assert!((mean / brute - 1.0).abs() < 0.02, "{mean} vs {brute}");
    }

    #[test]
    fn a_lines_share_of_a_reflected_paths_light_is_what_it_reflects_there() {
        // Independent: ∫ R² S / ∫ R S by brute force (E: S flat), for the line itself and for
        // one 30 half-widths away, whose share is about nothing.
        let s = SpectralSampler::new(Illuminant::E, &WavelengthGrid::default(), 64);
        let line = BraggLine::new(0.0037, 589.0, 1.0, 400.0);
        let far = BraggLine::new(0.0037, 589.0 + 30.0 * line.half_width_nm(), 1.0, 400.0);
        let step = 0.002;
        let (mut r1, mut r2) = (0.0, 0.0);
        for i in 0..200_000 {
            let r = line.reflectance(380.0 + (f64::from(i) + 0.5) * step);
            r1 += r;
            r2 += r * r;
        }
        let share_of =
            |path: &PathSpectrum, l: &BraggLine| path.reflectances(l, &mut [0.0; MAX_DRAWS]);
        let mut path = PathSpectrum::default();
        path.reflect(line, &s, 0.5);
        let share = share_of(&path, &line);
        assert!(
            (share / (r2 / r1) - 1.0).abs() < 0.05,
            "{share} vs {}",
            r2 / r1
        );
        assert!(share_of(&path, &far) < 0.01 * share);
        assert_eq!(share_of(&PathSpectrum::default(), &line), 0.0);
    }
}

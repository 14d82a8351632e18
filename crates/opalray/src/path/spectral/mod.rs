//! Wavelengths for the path integrator, and for the stored method's view: a path's spectrum
//! is white until its first reflection by a Bragg line, and from there lies within that line.
//!
//! A path's geometry does not depend on wavelength (no dispersion; choices are made with
//! wavelength-independent probabilities), so its contribution is `w · ∫ Π_k f_k(λ) S(λ) c̄(λ) dλ`,
//! `f_k` = R or 1 − R of line k (of the path's s and p light apart, [`super::polar`]), S the
//! light's spectrum (luminance 1), c̄ the CIE 1931 colour-matching functions. Without a reflection
//! the product is 1 but for the lines' notches, each under 2.2 nm of the 400 nm range (at most 0.6
//! % of white light a line, but a path passes hundreds): the path tracer carries them exactly
//! ([`super::notches`]), so that the light going on through a domain loses what its lines reflect;
//! the stored method's view ([`Lines`](crate::stored::Lines)) still neglects them. With one, the
//! integrand lives within the line (~2 nm): λ is drawn from a truncated Cauchy law over the first
//! reflection line (90 %) mixed with a uniform law over the range (10 %, so that every wavelength
//! can be drawn and the estimate is unbiased), the draws stratified over the mixture
//! ([`SpectralSampler::draw`]). Narrow lines are thus sampled where they are, and never binned
//! before colour.
//!
//! Two carriers of the product:
//! - [`PathSpectrum`] (the path tracer): until its first reflection, the light's white and
//!   the notches passed on a fine table; the wavelengths are drawn once, at the path's first
//!   reflection, and each carries the product of the path's factors at it from there (hero
//!   wavelengths). Every later line multiplies them at once, so a path can pass any number
//!   of lines, and the share of its light a line reflects is known exactly where the path
//!   must choose ([`PathSpectrum::reflectances`]).
//! - [`Lines`](crate::stored::Lines) (the stored method's view, `stored/lines.rs`): the list
//!   of lines itself, its product evaluated at the end by quadrature ([`SpectralSampler::integrate`]).
//!
//! The light × colour-matching table they are deposited through, and the wavelength draws,
//! are the film's ([`crate::film::sensor`]); the deposits of these carriers stay beside the
//! fields they read (a [`PathSpectrum`]'s: `deposit.rs`).

use std::borrow::Cow;

use crate::optics::BraggLine;
use crate::stone::ironstone_reflectance;

pub(super) use crate::film::sensor::TABLE_STEP_NM;
pub use crate::film::sensor::{SpectralSampler, MAX_TINTS};
use glam::Vec3;

use super::notches::Notches;
use super::orders::History;
use super::polar::{apply, Polarisation};

mod deposit;

/// Most wavelengths a path carries (`integrator.wavelengths` is at most this).
pub const MAX_DRAWS: usize = 64;

/// `line`'s reflectance at `wavelength_nm` within `window` (its [`BraggLine::window_nm`]), 0
/// outside (the tests' reference).
#[cfg(test)]
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

/// `line`'s reflectances `(R_s, R_p)` at `wavelength_nm` within `window`, 0 outside.
#[inline]
pub(super) fn reflectance_sp_within(
    line: &BraggLine,
    (lo, hi): (f64, f64),
    wavelength_nm: f64,
) -> (f64, f64) {
    if (lo..=hi).contains(&wavelength_nm) {
        line.reflectance_sp(wavelength_nm)
    } else {
        (0.0, 0.0)
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
    /// Its polarisation: the s share of its white, or of its light at each wavelength
    /// carried ([`super::polar`]); the weights hold the intensities.
    polar: Polarisation,
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
            polar: Polarisation::default(),
            history: History::default(),
        }
    }
}

impl PathSpectrum {
    /// A reflection by `line` (factor R, unpolarised: its plane unknown). The first draws
    /// the path's wavelengths from the line's law with `sampler`, stratified with offset `u`
    /// in [0, 1).
    pub fn reflect(&mut self, line: BraggLine, sampler: &SpectralSampler, u: f64) {
        let notches = self.notches.take();
        self.reflect_through(line, sampler, (u, Vec3::ZERO), notches.as_deref());
    }

    /// This path reflected by `line` ([`PathSpectrum::reflect`]) in the plane of s axis
    /// `axis` ([`super::polar::SpState::s_axis`]; zero: unpolarised), the s and p parts of
    /// its light by `R_s` and `R_p`, without copying its notches.
    pub fn reflected(
        &self,
        line: BraggLine,
        sampler: &SpectralSampler,
        u: f64,
        axis: Vec3,
    ) -> Self {
        let mut out = self.shallow();
        out.reflect_through(line, sampler, (u, axis), self.notches.as_deref());
        out
    }

    /// This path without its notches (a copy of everything else).
    fn shallow(&self) -> Self {
        PathSpectrum {
            notches: None,
            tints: self.tints,
            draws: self.draws,
            dark: self.dark,
            waves: self.waves,
            weights: self.weights,
            polar: self.polar,
            history: self.history,
        }
    }

    /// [`PathSpectrum::reflected`] of a path whose notches so far are `notches`, with offset
    /// `u` in the plane of s axis `axis`.
    fn reflect_through(
        &mut self,
        line: BraggLine,
        sampler: &SpectralSampler,
        (u, axis): (f64, Vec3),
        notches: Option<&Notches>,
    ) {
        self.history.bragg();
        if self.dark {
            return;
        }
        let window = line.window_nm();
        let plane = axis != Vec3::ZERO;
        if self.draws == 0 {
            let n = sampler.draws.clamp(1, MAX_DRAWS);
            let q = self.polar.white_in(axis);
            self.polar.turn(axis, 0);
            let shares = self.polar.shares_mut();
            for (j, share) in shares.iter_mut().enumerate().take(n) {
                let (w, pdf) = sampler.draw(&line, j, u);
                let (rs, rp) = reflectance_sp_within(&line, window, w);
                let (r, q_j) = apply(q, rs, rp, plane);
                *share = q_j;
                let mut f = r / (n as f64 * pdf);
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
            self.each_event(axis, |w| reflectance_sp_within(&line, window, w));
        }
        let dark = self.carried().all(|(f, _)| f == 0.0);
        self.dark = dark;
    }

    /// A pass through `line`'s planes (factor 1 − R, unpolarised: their plane unknown);
    /// `sampler` holds the table a path not yet reflected carries its notches on.
    pub fn transmit(&mut self, line: BraggLine, sampler: &SpectralSampler) {
        self.transmit_in(line, sampler, Vec3::ZERO);
    }

    /// [`PathSpectrum::transmit`] in the plane of s axis `axis` (zero: unpolarised): the s
    /// and p parts by `1 − R_s` and `1 − R_p`. Before the first reflection the notch takes
    /// the white's s share turned to the plane, and leaves the share as it was (a notch
    /// polarises only the ~2 nm it takes).
    pub fn transmit_in(&mut self, line: BraggLine, sampler: &SpectralSampler, axis: Vec3) {
        if self.dark {
            return;
        }
        if self.draws == 0 {
            let q = (axis != Vec3::ZERO).then(|| f64::from(self.polar.white_in(axis)));
            self.notches
                .get_or_insert_with(|| Box::new(Notches::new(sampler)))
                .pass(&line, sampler, q);
            return;
        }
        let window = line.window_nm();
        self.each_event(axis, |w| {
            let (rs, rp) = reflectance_sp_within(&line, window, w);
            (1.0 - rs, 1.0 - rp)
        });
    }

    /// An event at every wavelength carried, in the plane of s axis `axis` (zero:
    /// unpolarised), keeping `kept(λ)` = `(s, p)` of the s and p parts there.
    #[inline]
    fn each_event(&mut self, axis: Vec3, kept: impl Fn(f64) -> (f64, f64)) {
        let n = usize::from(self.draws);
        self.polar.turn(axis, n);
        let plane = axis != Vec3::ZERO;
        let shares = self.polar.shares_mut();
        for ((f, w), q) in self.weights[..n]
            .iter_mut()
            .zip(&self.waves[..n])
            .zip(shares)
        {
            if *f != 0.0 {
                let (ks, kp) = kept(f64::from(*w));
                let (k, share) = apply(*q, ks, kp, plane);
                *f *= k as f32;
                *q = share;
            }
        }
    }

    /// An event that keeps `rs` of the s part and `rp` of the p part of the light at every
    /// wavelength (the surface's Fresnel factors), in the plane of s axis `axis` (zero:
    /// unpolarised): returns the factor on the path's weight, which before the first
    /// reflection is the event's on the white (its share updated), and after it the mean
    /// `(rs + rp)/2`, the wavelengths carried taking their own factor over it (so that the
    /// weight, which the roulette reads, falls as the averaged event's does).
    pub fn event(&mut self, axis: Vec3, rs: f32, rp: f32) -> f32 {
        let (rs, rp) = (f64::from(rs), f64::from(rp));
        if self.draws > 0 {
            let mean = 0.5 * (rs + rp);
            if mean > 0.0 {
                self.each_event(axis, |_| (rs / mean, rp / mean));
            }
            return mean as f32;
        }
        let q = self.polar.white_in(axis);
        self.polar.turn(axis, 0);
        let (k, share) = apply(q, rs, rp, axis != Vec3::ZERO);
        self.polar.set_white(share);
        k as f32
    }

    /// What of this path an event keeping `rs` and `rp` lets through ([`PathSpectrum::event`]
    /// on a copy, the path itself unchanged): the copy and the factor on its weight. Before
    /// the first reflection the copy is the path itself (only the factor differs), so its
    /// notches are not copied.
    pub fn through(&self, axis: Vec3, rs: f32, rp: f32) -> (Cow<'_, PathSpectrum>, f32) {
        if self.draws == 0 {
            let q = self.polar.white_in(axis);
            let (k, _) = apply(q, f64::from(rs), f64::from(rp), axis != Vec3::ZERO);
            return (Cow::Borrowed(self), k as f32);
        }
        let mut copy = self.shallow();
        let k = copy.event(axis, rs, rp);
        (Cow::Owned(copy), k)
    }

    /// Its light unpolarised (a diffuse scattering or a backing).
    pub fn depolarise(&mut self) {
        self.polar.depolarise();
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

    /// The share of the path's light that `line` reflects unpolarised, `Σ f_j R(λ_j) / Σ f_j`
    /// over the wavelengths carried (0 for a path not yet reflected or dark), keeping
    /// `line`'s `(R_s, R_p)` at each wavelength carried in `r` (0 where the path carries
    /// nothing) for [`PathSpectrum::pass`]: a crossing weighs its lines and then passes them
    /// at the same wavelengths.
    pub fn reflectances(&self, line: &BraggLine, r: &mut [[f32; 2]; MAX_DRAWS]) -> f64 {
        let window = line.window_nm();
        let (mut total, mut reflected) = (0.0f64, 0.0f64);
        for ((f, w), r) in self.carried().zip(r.iter_mut()) {
            *r = [0.0; 2];
            if f != 0.0 {
                let (rs, rp) = reflectance_sp_within(line, window, w);
                *r = [rs as f32, rp as f32];
                total += f64::from(f);
                reflected += f64::from(f) * 0.5 * (rs + rp);
            }
        }
        if total > 0.0 {
            reflected / total
        } else {
            0.0
        }
    }

    /// A pass in the plane of s axis `axis` through a line whose `(R_s, R_p)` at the
    /// wavelengths carried are `r`, from [`PathSpectrum::reflectances`] on this path:
    /// [`PathSpectrum::transmit_in`] of a reflected path without evaluating the line again.
    pub fn pass(&mut self, r: &[[f32; 2]; MAX_DRAWS], axis: Vec3) {
        debug_assert!(self.reflects());
        let n = usize::from(self.draws);
        self.polar.turn(axis, n);
        let plane = axis != Vec3::ZERO;
        let shares = self.polar.shares_mut();
        for ((f, r), q) in self.weights[..n].iter_mut().zip(r).zip(shares) {
            let (k, share) = apply(*q, f64::from(1.0 - r[0]), f64::from(1.0 - r[1]), plane);
            *f *= k as f32;
            *q = share;
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

#[cfg(test)]
mod tests;

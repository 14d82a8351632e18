//! Polarisation carried as two incoherent intensities, s and p, relative to the plane of
//! incidence of a path's last event (a 2-component reduction of the Stokes vector).
//!
//! Input: the state after the previous event and the next event's plane (its s axis, the unit
//! normal of the plane holding the incoming direction and the surface's or the planes'
//! normal) and reflectances `(R_s, R_p)` (or transmittances) → output: the state after it.
//!
//! Model (`docs/model.md`, "Polarisation"): between events the light is described by its
//! intensities along the old s and p axes; projected on the new plane's axes, at angle φ
//! between the planes, `s' = cos²φ s + sin²φ p`, `p' = sin²φ s + cos²φ p` (the coherence term,
//! Stokes U, is dropped), then `s' R_s`, `p' R_p`. The rotation and the diagonal event
//! matrices are symmetric, so the state can be carried from the camera as well as from the
//! light; unpolarised light starts at (½, ½) and the detector reads `s + p`. This is exact
//! for up to two polarising events from unpolarised light (U made by the rotation before
//! the second event does not reach the intensity); from the third on, U and the phase
//! between `r_s` and `r_p` (which the line model does not carry) would be needed.

use glam::Vec3;

use super::spectral::MAX_DRAWS;
use super::Tracer;
use crate::geometry::fresnel_dielectric_sp;

/// A beam's polarisation state: its intensities along the s and p axes of the plane of its
/// last event.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpState {
    /// Intensity polarised perpendicular to the last plane of incidence (≥ 0).
    pub s: f32,
    /// Intensity polarised in the last plane of incidence (≥ 0).
    pub p: f32,
    /// Unit s axis of the last plane of incidence; zero where no event has set one (the
    /// state is then unpolarised, `s = p`).
    pub axis: Vec3,
}

impl SpState {
    /// Unpolarised light of `intensity`: `(intensity/2, intensity/2)`, no plane.
    pub fn unpolarised(intensity: f32) -> Self {
        SpState {
            s: 0.5 * intensity,
            p: 0.5 * intensity,
            axis: Vec3::ZERO,
        }
    }

    /// The total intensity `s + p` (what an unpolarised detector or a white,
    /// unpolarised environment reads).
    pub fn intensity(&self) -> f32 {
        self.s + self.p
    }

    /// The s axis of the plane of incidence of a beam along `dir` (unit) meeting a surface
    /// or a family of planes of unit normal `normal`: `dir × normal`, normalised; zero at
    /// normal incidence, where the plane is undefined and `R_s = R_p`.
    pub fn s_axis(dir: Vec3, normal: Vec3) -> Vec3 {
        let a = dir.cross(normal);
        if a.length_squared() < 1e-12 {
            Vec3::ZERO
        } else {
            a.normalize()
        }
    }

    /// The state projected on the plane whose s axis is `axis` (`cos²φ`, `sin²φ` split,
    /// module notes); unchanged where either axis is zero.
    pub fn rotated_to(&self, axis: Vec3) -> Self {
        if axis == Vec3::ZERO {
            return *self;
        }
        if self.axis == Vec3::ZERO {
            return SpState { axis, ..*self };
        }
        let c2 = self.axis.dot(axis).powi(2).clamp(0.0, 1.0);
        let s2 = 1.0 - c2;
        SpState {
            s: c2 * self.s + s2 * self.p,
            p: s2 * self.s + c2 * self.p,
            axis,
        }
    }

    /// The state after an event of plane `axis` (see [`SpState::s_axis`]) that keeps `rs` of
    /// the s part and `rp` of the p part (reflectances or transmittances, in [0, 1]).
    pub fn event(&self, axis: Vec3, rs: f32, rp: f32) -> Self {
        let r = self.rotated_to(axis);
        SpState {
            s: r.s * rs,
            p: r.p * rp,
            axis: r.axis,
        }
    }

    /// The same intensity unpolarised (a diffuse scattering or a Lambert backing).
    pub fn depolarised(&self) -> Self {
        SpState::unpolarised(self.intensity())
    }
}

/// The polarisation a path carries, as the share of its light that is s-polarised relative
/// to the plane of its last polarising event: one share for its white before its first
/// Bragg reflection, one per wavelength it carries after it ([`super::PathSpectrum`]; its
/// intensities stay in the spectrum's weights). A zero axis means no plane yet: the light is
/// unpolarised (every share ½).
#[derive(Clone, Copy, Debug)]
pub struct Polarisation {
    /// Unit s axis of the last plane ([`SpState::s_axis`]); zero: unpolarised.
    axis: Vec3,
    /// The s share of the white, before the first reflection.
    white: f32,
    /// The s share at each wavelength carried.
    shares: [f32; MAX_DRAWS],
}

impl Default for Polarisation {
    fn default() -> Self {
        Polarisation {
            axis: Vec3::ZERO,
            white: 0.5,
            shares: [0.5; MAX_DRAWS],
        }
    }
}

/// An event that keeps `rs` of the s part and `rp` of the p part of light whose s share is
/// `q`: the factor on its intensity and its s share after. Without a plane (`plane` false:
/// normal incidence, or a plane the path does not know) the mean, the share unchanged.
#[inline]
pub(super) fn apply(q: f32, rs: f64, rp: f64, plane: bool) -> (f64, f32) {
    if !plane {
        return (0.5 * (rs + rp), q);
    }
    let q64 = f64::from(q);
    let kept_s = q64 * rs;
    let factor = kept_s + (1.0 - q64) * rp;
    let share = if factor > 0.0 {
        (kept_s / factor) as f32
    } else {
        q
    };
    (factor, share)
}

impl Polarisation {
    /// The same state, unpolarised (a diffuse scattering or a backing).
    pub fn depolarise(&mut self) {
        *self = Polarisation::default();
    }

    /// The white's s share turned to the plane of s axis `axis` (unchanged where either
    /// axis is zero), without turning the state.
    pub(super) fn white_in(&self, axis: Vec3) -> f32 {
        match self.cos2_to(axis) {
            Some(c2) => turned(self.white, c2),
            None => self.white,
        }
    }

    /// The state turned to the plane of s axis `axis`, its first `carried` shares and the
    /// white's (`s' = cos²φ s + sin²φ p`); nothing where `axis` is zero.
    pub(super) fn turn(&mut self, axis: Vec3, carried: usize) {
        if axis == Vec3::ZERO {
            return;
        }
        if let Some(c2) = self.cos2_to(axis) {
            self.white = turned(self.white, c2);
            for q in &mut self.shares[..carried] {
                *q = turned(*q, c2);
            }
        }
        self.axis = axis;
    }

    /// Set the white's s share (after an event on the white).
    pub(super) fn set_white(&mut self, q: f32) {
        self.white = q;
    }

    /// The s shares at the wavelengths carried.
    pub(super) fn shares_mut(&mut self) -> &mut [f32; MAX_DRAWS] {
        &mut self.shares
    }

    /// `cos²φ` between the last plane's s axis and `axis`; `None` where either is zero or
    /// they are the same plane (no turn).
    fn cos2_to(&self, axis: Vec3) -> Option<f32> {
        if axis == Vec3::ZERO || self.axis == Vec3::ZERO {
            return None;
        }
        let c2 = self.axis.dot(axis).powi(2).clamp(0.0, 1.0);
        (c2 < 1.0).then_some(c2)
    }
}

impl Tracer<'_> {
    /// The s axis of the plane of an event of a path along `dir` at a surface or planes of
    /// unit normal `normal` ([`SpState::s_axis`]); zero (no plane: the mean of s and p) where
    /// the tracer does not polarise.
    pub(super) fn plane(&self, dir: Vec3, normal: Vec3) -> Vec3 {
        if self.polarised {
            SpState::s_axis(dir, normal)
        } else {
            Vec3::ZERO
        }
    }

    /// The light's refraction in at `entry`, seen from a path inside that leaves towards it
    /// along `to_light`, the light outside along `out` (unit, towards the light): the plane's
    /// s axis and `T_s`, `T_p` over their mean (the estimate's irradiance holds the mean).
    pub(super) fn entry_sp(&self, entry: Vec3, to_light: Vec3, out: Vec3) -> (Vec3, f32, f32) {
        let normal = self.stone.shape.normal(entry);
        let (fs, fp) = fresnel_dielectric_sp(out.dot(normal).max(0.0), 1.0, self.n_eff);
        let (ts, tp) = (1.0 - fs, 1.0 - fp);
        let mean = 0.5 * (ts + tp);
        if mean <= 0.0 {
            return (Vec3::ZERO, 1.0, 1.0);
        }
        (self.plane(to_light, normal), ts / mean, tp / mean)
    }
}

/// The s share `q` projected on axes turned by φ from its own (`cos²φ` = `c2`).
#[inline]
fn turned(q: f32, c2: f32) -> f32 {
    c2 * q + (1.0 - c2) * (1.0 - q)
}

#[cfg(test)]
mod tests;

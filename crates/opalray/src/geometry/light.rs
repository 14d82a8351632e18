//! A light as the stone sees it, and the one refracted path by which it reaches a point
//! inside: shared by every renderer (the paper's light pass, the stored method, the path
//! tracer's next-event estimation).
//!
//! A collimated beam refracted at a locally flat surface element carries, perpendicular to
//! its new direction, the irradiance `E · (1 − F) · cos θᵢ / cos θₜ` (the element's power
//! `E cos θᵢ dA`, less the Fresnel part, through the cross-section `cos θₜ dA`). The surface's
//! curvature focuses the beam further; the stone model's `Stone::light_spread` adds it.

use glam::Vec3;

use super::{fresnel_dielectric, refract, Ray, Surface};

/// A light in the opal's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LightSource {
    /// Parallel light travelling along `direction` (unit, light → opal), irradiance 1 on a
    /// plane perpendicular to it (times the spectrum's scale).
    Directional {
        /// Unit direction of travel.
        direction: Vec3,
    },
    /// A point light at `position` (mm) with intensity such that the irradiance at the opal's
    /// centre, facing the light, is 1.
    Point {
        /// Position, mm.
        position: Vec3,
    },
}

impl LightSource {
    /// Unit direction from `p` towards the light.
    pub fn direction_to_light(&self, p: Vec3) -> Vec3 {
        match *self {
            LightSource::Directional { direction } => -direction,
            LightSource::Point { position } => (position - p).normalize(),
        }
    }

    /// Irradiance at `p` on a plane facing the light, relative to the opal's centre.
    pub fn irradiance_at(&self, p: Vec3) -> f32 {
        match *self {
            LightSource::Directional { .. } => 1.0,
            LightSource::Point { position } => {
                position.length_squared() / (position - p).length_squared()
            }
        }
    }
}

/// Most iterations of the entry-point search. It stops once the refracted direction moves by
/// under [`ENTRY_TOLERANCE`], after a few steps on most of the stone; about 1 % of the paper's
/// stone's cells, at the strongly curved rim, use up all of them and keep the last step.
const ENTRY_ITERATIONS: usize = 24;
/// The entry-point search has converged when the refracted direction moves by under this
/// (radians): the path then misses the cell's centre by about 10⁻⁴ × its length, 0.5 µm at
/// 5 mm, a 400th of a cell. Two steps per cell on average with a neighbour's guess (10⁻⁵ took
/// three, for an image 0.04 % RMS away and 10 ms more of light pass).
const ENTRY_TOLERANCE: f32 = 1e-4;
/// Step towards the refracted direction taken per iteration once the search is damped.
const ENTRY_DAMPING: f32 = 0.5;

/// Where the light that reaches `target` straight (refracted once) enters the stone:
/// `(entry point, refracted direction, irradiance across the beam inside)`, or `None`
/// where the surface facing the light does not see `target`. `guess` is a refracted
/// direction to start from (a neighbouring cell's); without one the unrefracted line to
/// the light.
#[inline(always)]
pub fn refracted_entry<S: Surface + ?Sized>(
    shape: &S,
    source: &LightSource,
    n_eff: f32,
    target: Vec3,
    guess: Option<Vec3>,
) -> Option<(Vec3, Vec3, f32)> {
    // Move the entry point until the refracted direction at it points at the target.
    let mut d = guess.unwrap_or_else(|| -source.direction_to_light(target));
    let mut found = None;
    let (mut previous_step, mut damped) = (f32::INFINITY, false);
    for k in 0..ENTRY_ITERATIONS {
        let back = Ray::new(target, -d);
        let (_, t_far) = shape.intersect(&back)?;
        let p = back.at(t_far.max(0.0));
        let normal = shape.normal(p);
        let incoming = -source.direction_to_light(p);
        let cos_i = -incoming.dot(normal);
        if cos_i <= 0.0 {
            return None;
        }
        let refracted = refract(incoming, normal, 1.0, n_eff)?;
        let step = (refracted - d).length_squared();
        let converged = step < ENTRY_TOLERANCE * ENTRY_TOLERANCE;
        // Damped from the third step on once the plain iteration stops halving its step:
        // near the rim, where the surface curves fast, it overshoots and oscillates. Where
        // the surface is gentle it converges in a few plain steps.
        damped |= k >= 2 && step > 0.25 * previous_step;
        previous_step = step;
        d = if damped {
            (d + ENTRY_DAMPING * (refracted - d)).normalize()
        } else {
            refracted
        };
        found = Some((p, normal, cos_i));
        if converged {
            break;
        }
    }
    let (p, normal, cos_i) = found?;
    let cos_t = -d.dot(normal);
    if cos_t <= 0.0 {
        return None;
    }
    let fresnel = fresnel_dielectric(cos_i, 1.0, n_eff);
    let irradiance = source.irradiance_at(p) * (1.0 - fresnel) * cos_i / cos_t;
    Some((p, d, irradiance))
}

//! Next-event estimation through the stone's surface: light from outside found from a point
//! inside along the one refracted path, with the surface's exact lensing; the environment's
//! estimate at potch scatterings and backings (the area lights': `area.rs`).
//!
//! Input: a point `x` in the opal and a direction (or point) outside → output: the refracted
//! path in ([`Inbound`]) and the contributions added to the pixel.
//!
//! A direction `ω_o` outside (of an environment or area light sample) is solved for the one
//! refracted path that reaches `x` (the entry point `e`, the direction `ω_i` inside); the
//! value `v` seen from `e` along `ω_o` reaches `x` as `v (1 − F) n² / J` per steradian inside,
//! `J = dω_o / dω_i` the lensing of the curved surface ([`Stone::spread_out`](crate::stone::Stone::spread_out), finite
//! differences of neighbouring rays). The estimate of `∫ ρ(ω_i) v_i(ω_i) dω_i` from one draw
//! of density `q` (per steradian outside) is `ρ v (1 − F) n² / (J q)`.

use glam::Vec3;

use super::{CameraSample, Estimate, Tracer, EPSILON_MM};
use crate::geometry::fresnel_dielectric;
use crate::geometry::refracted_entry;
use crate::geometry::LightSource;

/// The one refracted path from a direction outside to a point inside.
#[derive(Clone, Copy, Debug)]
pub(super) struct Inbound {
    /// Where it enters the stone.
    pub entry: Vec3,
    /// Unit direction from the point inside towards the entry point.
    pub to_light: Vec3,
    /// Distance from the point inside to the entry point, mm.
    pub distance: f32,
    /// The lensing `J = dω_out / dω_in`.
    pub spread: f32,
    /// `(1 − F) n² / J`: what a value outside per steradian outside gives inside.
    pub gain: f32,
}

impl Tracer<'_> {
    /// The refracted path from direction `out` (unit, outside, towards the light) to `x`:
    /// `None` where the surface facing `out` does not see `x`, the path enters under a
    /// backing, or the neighbouring rays do not all leave.
    pub(super) fn refracted_in(&self, x: Vec3, out: Vec3) -> Option<Inbound> {
        let stone = self.stone;
        let source = LightSource::Directional { direction: -out };
        let (entry, d, _) = refracted_entry(&stone.shape, &source, self.n_eff, x, None)?;
        if stone.back.is_some_and(|b| entry.z <= b.z + EPSILON_MM) {
            return None;
        }
        let to_light = -d;
        // The exact spread of directions through the curved surface (not a flat element's).
        let spread = self.stone.spread_out(x, to_light)?;
        let cos_out = out.dot(stone.shape.normal(entry)).max(0.0);
        let fresnel = fresnel_dielectric(cos_out, 1.0, self.n_eff);
        Some(Inbound {
            entry,
            to_light,
            distance: (entry - x).length(),
            spread,
            gain: (1.0 - fresnel) * self.n_eff * self.n_eff / spread,
        })
    }

    /// Walk from `at`'s point along `to_light` for `distance` mm (the potch's transmittance,
    /// the notches of the domains crossed but `skip`), then add `value(transmittance)` with
    /// the path's lines and those notches.
    pub(super) fn add_towards(
        &mut self,
        at: &Estimate,
        to_light: Vec3,
        distance: f32,
        skip: Option<u32>,
        value: impl Fn(f32) -> f32,
        s: &mut CameraSample,
    ) {
        let Some((transmitted, notches)) = self.towards_light(at.x, to_light, distance, skip)
        else {
            return;
        };
        if notches.is_empty() {
            self.add(at.path, value(transmitted), s);
            return;
        }
        let mut lines = at.path.clone();
        for n in &notches {
            lines.transmit(*n, self.setup.spectral);
        }
        self.add(&lines, value(transmitted), s);
    }

    /// Whether the environment's draw of `out` at `from` finds the refracted path that leaves
    /// the stone at `exit` ([`Tracer::environment_at`]'s solve).
    pub(super) fn entry_found(&self, from: Vec3, out: Vec3, exit: Vec3) -> bool {
        let source = LightSource::Directional { direction: -out };
        refracted_entry(&self.stone.shape, &source, self.n_eff, from, None).is_some_and(
            |(entry, _, _)| {
                (entry - exit).length_squared() < 1e-4
                    && !self.stone.back.is_some_and(|b| entry.z <= b.z + EPSILON_MM)
            },
        )
    }

    /// Next-event estimation of the environment (and an area light in front of it) at a
    /// scattering point (`at`) in the opal whose scattering density towards a direction (per
    /// steradian, inside) is `density`: one direction drawn from the environment's
    /// distribution, refracted in through the surface ([`refracted_entry`]), weighted by the
    /// balance heuristic against the scattering's own draw (see the escape in
    /// [`Tracer::surface`]).
    pub(super) fn environment_at(
        &mut self,
        at: &Estimate,
        density: &dyn Fn(Vec3) -> f32,
        s: &mut CameraSample,
    ) {
        let Estimate { x, weight, .. } = *at;
        let u = [s.draws.uniform_f32(), s.draws.uniform_f32()];
        let sample = self.setup.environment.sample(u);
        if sample.pdf <= 0.0 {
            return;
        }
        let Some(inbound) = self.refracted_in(x, sample.direction) else {
            return;
        };
        let f = density(inbound.to_light);
        if f <= 0.0 {
            return;
        }
        let (value, light) = self.escaped_to(inbound.entry, sample.direction);
        if value <= 0.0 {
            return;
        }
        let p_b = f / inbound.spread;
        // Where it meets the area light, that light's own draw finds the same path.
        let p_area = if light {
            self.area_pdf(x, sample.direction)
        } else {
            0.0
        };
        let mis = sample.pdf / (sample.pdf + p_b + p_area);
        let irradiance = inbound.gain;
        self.add_towards(
            at,
            inbound.to_light,
            inbound.distance,
            None,
            |transmitted| weight * f * value * irradiance * transmitted * mis / sample.pdf,
            s,
        );
    }
}

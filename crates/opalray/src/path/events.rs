//! The events of a path inside the stone, one method each: a scattering in the potch or a
//! milky domain's haze, the surface from inside, a backing, a triplet's cap plane (the domain
//! crossings in [`super::crossing`]; the loop over them in [`super::vertex`]).

use glam::Vec3;

use super::area::Drawn;
use super::sampler::PathSampler;
use super::vertex::{Segment, Step, Vertex, Waiting, WaitingAt};
use super::{scattering_split, CameraSample, Estimate, Tracer, EPSILON_MM, MIN_REACH};
use crate::geometry::{fresnel_dielectric_sp, reflect, refract, Ray};
use crate::scatter::{Lambert, Phase, Scatter};
use crate::scene::Backing;
use crate::stone::{Hint, Region};

/// A scattering at `from`: `remaining` directions to follow as branches, then the path's own.
pub(super) struct Scattering {
    pub from: Vec3,
    pub remaining: u32,
    /// Its direction before the scattering.
    pub incoming: Vec3,
    /// The phase's anisotropy.
    pub g: f32,
    /// Whether the environment and an area light were estimated there.
    pub estimated: bool,
}

impl Scattering {
    /// The phase function it draws from.
    fn phase(&self) -> Phase {
        Phase {
            incoming: self.incoming,
            g: self.g,
        }
    }

    /// How a direction `d` drawn from the phase was drawn, for its escape's balance.
    fn drawn(&self, d: Vec3) -> Option<Drawn> {
        self.estimated.then(|| Drawn {
            density: self.phase().density(d),
            from: self.from,
            environment: true,
        })
    }
}

impl Tracer<'_> {
    /// A scattering at `t` along `ray` keeping `albedo`: the lights estimated there, then
    /// the phase's draws (several directions for the camera path's first).
    pub(super) fn scatter(
        &mut self,
        v: &mut Vertex,
        ray: &Ray,
        t: f32,
        albedo: f32,
        s: &mut CameraSample,
    ) -> Step {
        let stone = self.stone;
        v.pos = ray.at(t);
        v.weight *= albedo;
        v.scatterings += 1;
        v.lines.history.scattered();
        v.lines.depolarise();
        self.nee_hint = v.hint;
        let at = Estimate {
            x: v.pos,
            path: &v.lines,
            weight: v.weight,
        };
        self.light_at_potch(&at, v.dir, s);
        let g = stone.potch.anisotropy;
        let incoming = v.dir;
        // Deep in a milky body no light from outside reaches this point: the estimate is
        // skipped and the scattering's own draw weighs alone.
        let estimated = stone.cap.is_none() && stone.reach_bound(v.pos) >= MIN_REACH;
        if estimated {
            let law = Phase { incoming, g };
            let phase = |to: Vec3| law.eval(to);
            self.environment_at(&at, &phase, s);
            self.area_at(&at, &phase, s);
        }
        // The camera path's first scattering goes on in several directions.
        let k = if v.splits_scattering {
            scattering_split(v.weight)
        } else {
            1
        };
        v.splits_scattering = false;
        v.weight /= k as f32;
        let scattering = Scattering {
            from: v.pos,
            remaining: k - 1,
            incoming,
            g,
            estimated,
        };
        self.scatter_on(v, scattering, s)
    }

    /// A scattered path's next direction: a branch while `remaining`, then its own.
    pub(super) fn scatter_on(
        &mut self,
        v: &mut Vertex,
        mut sc: Scattering,
        s: &mut CameraSample,
    ) -> Step {
        if sc.remaining > 0 {
            sc.remaining -= 1;
            let d = sc.phase().sample(s.draws);
            let child = Vertex {
                pos: v.pos,
                dir: d,
                weight: v.weight,
                lines: v.lines.clone(),
                skip: None,
                region: v.region,
                drawn: sc.drawn(d),
                hint: v.hint,
                split: false,
                splits_scattering: false,
                first_in_cap: v.region == Region::Cap,
                level: v.level + 1,
                scatterings: v.scatterings,
                walking: true,
            };
            return Step::Fork(Box::new(Waiting {
                vertex: std::mem::replace(v, child),
                at: WaitingAt::Scattering(sc),
            }));
        }
        let dir = Phase {
            incoming: v.dir,
            g: sc.g,
        }
        .sample(s.draws);
        v.drawn = sc.drawn(dir);
        v.dir = dir;
        v.walking = true;
        self.go_on(v, s.draws)
    }

    /// The surface from inside: what escapes (its share 1 − F) is added now, the path goes
    /// on reflected with weight × F (both ways at once, no random choice); s and p apart
    /// (`F_s`, `F_p`). The reflection of a segment drawn at a scattering is a step of the
    /// body's walk (which the calibration's walks take without limit), counted with the
    /// scatterings rather than against `max_depth`.
    pub(super) fn surface(
        &mut self,
        v: &mut Vertex,
        segment: &Segment,
        s: &mut CameraSample,
    ) -> Step {
        let n = self.stone.index_of(v.region);
        let exit = segment.ray.at(segment.t_end);
        let normal = self.stone.shape.normal(exit);
        let dir = v.dir;
        let cos = dir.dot(normal).max(0.0);
        let (fs, fp) = fresnel_dielectric_sp(cos, n, 1.0);
        let axis = self.plane(dir, normal);
        if fs.min(fp) < 1.0 {
            if let Some(out) = refract(dir, normal, n, 1.0) {
                let (mut value, light) = self.escaped_to(exit, out);
                if let Some(drawn) = v.drawn.filter(|_| value > 0.0) {
                    // Drawn where light was also sampled: the balance heuristic over external
                    // solid angle, against the draws that would have found this same path.
                    value *= self.escape_weight(&drawn, dir, out, exit, light);
                }
                if value > 0.0 {
                    let (out, t) = v.lines.through(axis, 1.0 - fs, 1.0 - fp);
                    self.add(&out, v.weight * t * n * n * value, s);
                }
            }
        }
        v.weight *= v.lines.event(axis, fs, fp);
        if std::mem::take(&mut v.walking) {
            v.scatterings += 1;
        }
        v.lines.history.reflected_inside();
        v.dir = reflect(dir, normal);
        v.pos = exit - normal * EPSILON_MM;
        v.drawn = None;
        self.go_on(v, s.draws)
    }

    /// A backing: a diffuse reflection (Lambert, cosine-weighted about +z), the lights
    /// estimated there.
    pub(super) fn backing(
        &mut self,
        v: &mut Vertex,
        segment: &Segment,
        s: &mut CameraSample,
    ) -> Step {
        let Some(back) = self.stone.back else {
            return Step::End;
        };
        v.pos = segment.ray.at(segment.t_end) + Vec3::Z * EPSILON_MM;
        v.lines.history.backed();
        v.lines.depolarise();
        v.walking = false;
        v.weight *= match back.kind {
            Backing::Ironstone => {
                v.lines.tint();
                1.0
            }
            _ => back.reflectance(550.0) as f32,
        };
        if v.weight <= 0.0 {
            return Step::End;
        }
        self.nee_hint = v.hint;
        let at = Estimate {
            x: v.pos,
            path: &v.lines,
            weight: v.weight,
        };
        self.light_at_back(&at, s);
        let estimated = self.stone.cap.is_none();
        // The backing's reflectance is in the weight already.
        let law = Lambert { albedo: 1.0 };
        if estimated {
            let lambert = |to: Vec3| law.eval(to);
            self.environment_at(&at, &lambert, s);
            self.area_at(&at, &lambert, s);
        }
        v.dir = law.sample(s.draws);
        v.drawn = estimated.then(|| Drawn {
            density: law.density(v.dir),
            from: v.pos,
            environment: true,
        });
        self.go_on(v, s.draws)
    }

    /// The plane between a triplet's opal slice and its cap: reflected with probability F
    /// (the mean of s and p), else refracted into the other region, s and p apart.
    pub(super) fn cap_plane(
        &mut self,
        v: &mut Vertex,
        segment: &Segment,
        s: &mut CameraSample,
    ) -> Step {
        let other = match v.region {
            Region::Opal => Region::Cap,
            Region::Cap => Region::Opal,
        };
        let (n1, n2) = (self.stone.index_of(v.region), self.stone.index_of(other));
        let dir = v.dir;
        let facing = if dir.z > 0.0 { -Vec3::Z } else { Vec3::Z };
        let (fs, fp) = fresnel_dielectric_sp(-dir.dot(facing), n1, n2);
        let f = 0.5 * (fs + fp);
        let axis = self.plane(dir, facing);
        let at = segment.ray.at(segment.t_end);
        v.walking = false;
        match refract(dir, facing, n1, n2).filter(|_| s.draws.uniform_f32() >= f) {
            Some(d) => {
                v.dir = d;
                let kept = v.lines.event(axis, 1.0 - fs, 1.0 - fp) / (1.0 - f);
                v.weight *= kept * (n1 / n2) * (n1 / n2);
                v.region = other;
                v.pos = at - facing * EPSILON_MM;
            }
            None => {
                // Drawn with probability F (or 1 beyond the critical angle, where F_s = F_p = 1).
                v.weight *= v.lines.event(axis, fs, fp) / f;
                v.dir = reflect(dir, facing);
                v.pos = at + facing * EPSILON_MM;
            }
        }
        v.hint = Hint::default();
        v.drawn = None;
        self.go_on(v, s.draws)
    }

    /// After an event: the camera ray's first segment in the opal splits (after a triplet's
    /// cap, its first there), then Russian roulette and the next level.
    fn go_on(&self, v: &mut Vertex, draws: &mut PathSampler) -> Step {
        if !(v.region == Region::Opal && v.first_in_cap) {
            v.split = false;
        }
        v.first_in_cap = false;
        if !self.roulette(&mut v.weight, draws) {
            return Step::End;
        }
        v.level += 1;
        Step::Go
    }
}

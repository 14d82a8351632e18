//! A reflection at a domain crossing as a path of its own: the lobe's normal drawn about the
//! family's (a Gaussian of the mosaic and the domain's width), the ray mirrored about it and
//! the line met at the half-vector angle; a reflection of the camera ray's first segment
//! followed with the probability its first escape gives it (the crossing itself: [`super`]).

use glam::Vec3;

use super::Reflection;
use crate::geometry::{reflect, refract, Ray};
use crate::optics::BraggLine;
use crate::path::sampler::PathSampler;
use crate::path::spectral::PathSpectrum;
use crate::path::vertex::Vertex;
use crate::path::{Tracer, MIN_FOLLOW};
use crate::scatter::{Mosaic, Scatter};
use crate::stone::{ActiveLine, Boundary, Region};

impl Tracer<'_> {
    /// The reflection `path` by `line` as a path of its own; if `cull`, followed with the
    /// probability [`Tracer::follow_probability`] gives it (its weight over that).
    pub(super) fn branch(
        &mut self,
        path: &Reflection,
        line: &ActiveLine,
        cull: bool,
        lines: &PathSpectrum,
        draws: &mut PathSampler,
    ) -> Option<Vertex> {
        let mut child = self.reflected_path(path, line, lines, draws)?;
        if cull {
            // Russian roulette on what the branch's first escape will see.
            let p = self.follow_probability(path.face, child.dir);
            if p < 1.0 {
                if draws.uniform_f32() >= p {
                    return None;
                }
                child.weight /= p;
            }
        }
        Some(child)
    }

    /// The path that the reflection `path` by `line` of a path of spectrum `lines` starts: the
    /// lobe's normal drawn ([`Tracer::reflection`]); `None` where it faces away or the path's
    /// light is all gone.
    pub(super) fn reflected_path(
        &mut self,
        path: &Reflection,
        line: &ActiveLine,
        lines: &PathSpectrum,
        draws: &mut PathSampler,
    ) -> Option<Vertex> {
        let (d, l, axis) = self.reflection(path.domain, line, path.dir, draws)?;
        let branch = lines.reflected(l, self.setup.spectral, draws.uniform(), axis);
        if branch.is_dark() {
            return None;
        }
        Some(Vertex {
            pos: path.face,
            dir: d,
            weight: path.weight,
            lines: branch,
            skip: Some(path.domain),
            region: Region::Opal,
            drawn: path
                .p_pick
                .and_then(|p| self.drawn_branch(path.x, path.dir, d, line, p)),
            hint: path.cells,
            split: false,
            splits_scattering: false,
            first_in_cap: false,
            level: path.level,
            scatterings: path.scatterings,
            walking: false,
        })
    }

    /// The probability with which a reflection of the camera ray's first segment, leaving
    /// `from` along `dir`, is followed: what the room shows where it first meets the surface
    /// and refracts out, over [`FOLLOW_FROM`](crate::path::FOLLOW_FROM) of the room's brightest, at least
    /// [`MIN_FOLLOW`]; 1 where it meets an area light, is reflected whole (beyond the
    /// critical angle) or meets anything but the surface first. Most reflections look into
    /// the dark room; the bright ones, which hold the picture's colour, are all followed.
    pub(in crate::path) fn follow_probability(&self, from: Vec3, dir: Vec3) -> f32 {
        if self.follow_from <= 0.0 {
            return 1.0;
        }
        let stone = self.stone;
        let ray = Ray {
            origin: from,
            direction: dir,
        };
        let Some((t, Boundary::Surface)) = stone.exit(&ray, Region::Opal) else {
            return 1.0;
        };
        let exit = ray.at(t);
        let Some(out) = refract(dir, stone.shape.normal(exit), stone.n_eff, 1.0) else {
            return 1.0;
        };
        let (value, light) = self.escaped_to(exit, out);
        if light {
            return 1.0;
        }
        (value / self.follow_from).clamp(MIN_FOLLOW, 1.0)
    }

    /// A reflection of the ray along `dir` by `line` of `domain`: the lobe's normal drawn, the
    /// mirrored direction, the line at the half-vector angle and the s axis of the plane of
    /// incidence; `None` if the drawn normal faces away.
    fn reflection(
        &self,
        domain: u32,
        line: &ActiveLine,
        dir: Vec3,
        draws: &mut PathSampler,
    ) -> Option<(Vec3, BraggLine, Vec3)> {
        let sigma = self.stone.lobe_sigma(line.kind, -dir.dot(line.normal));
        let h = Mosaic {
            normal: line.normal,
            sigma,
        }
        .sample(draws);
        let cos_h = -dir.dot(h);
        (cos_h > 0.0).then(|| {
            let l = self.line_at(domain, line, cos_h);
            (reflect(dir, h), l, self.plane(dir, h))
        })
    }
}

//! The direct light inside the stone, as every renderer of the stone model sees it: the one
//! refracted path from the light to a point, what it crosses on the way (potch, haze, the
//! domains' plane families), and a family's line and lobe at a half vector.
//!
//! Input: a [`Stone`], a [`LightSource`] and a point inside → output: the direction towards
//! the light, the irradiance across the beam, the transmittance and the Bragg lines crossed.
//! The path tracer's next-event estimation and the stored method's light pass call the same
//! functions.

use glam::Vec3;

use super::{ActiveLine, Hint, Span, Stone};
use crate::geometry::refracted_entry;
use crate::geometry::LightSource;
use crate::geometry::{fresnel_dielectric, refract, Ray};
use crate::optics::BraggLine;
use crate::scatter::Mosaic;

/// Offset kept between the back plane and an entry point that counts as from above, mm.
const BACK_EPSILON_MM: f32 = 1e-4;
/// The lobe is treated as zero beyond this many standard deviations.
pub const LOBE_SIGMAS: f32 = 4.0;

/// The straight path inside the stone from a point to the light's entry point, as
/// [`Stone::towards_light`] walks it.
#[derive(Clone, Copy, Debug)]
pub struct PathToLight {
    /// The start, mm (inside the opal).
    pub x: Vec3,
    /// The unit direction towards the light, inside.
    pub to_light: Vec3,
    /// The distance from `x` to the entry point, mm ([`Stone::light_entry`]).
    pub distance: f32,
    /// The cells likely to hold `x` ([`Stone::walk`]); the default for none.
    pub hint: Hint,
    /// The domain whose lines are not handed on (the one the path starts in), or `None`.
    pub skip: Option<u32>,
}

impl Stone {
    /// The light of `source` reaching `x` (inside the opal) straight: `(direction towards the
    /// light inside, irradiance across the beam relative to the light's at the stone's centre,
    /// distance to the entry point in mm)`.
    ///
    /// The one refracted path is solved through the outer surface into the opal: under a
    /// triplet's cap (two refractions) there is none, and light from under a backing is
    /// blocked. The irradiance is the surface's exact lensing ([`Stone::light_spread`]).
    pub fn light_entry(&self, source: &LightSource, x: Vec3) -> Option<(Vec3, f32, f32)> {
        if self.cap.is_some() {
            return None;
        }
        let (entry, d, _) = refracted_entry(&self.shape, source, self.n_eff, x, None)?;
        if self.back.is_some_and(|b| entry.z <= b.z + BACK_EPSILON_MM) {
            return None;
        }
        let irradiance = self.light_spread(source, entry, x, -d)?;
        Some((-d, irradiance, (entry - x).length()))
    }

    /// `dω_out / dω_in` of the rays leaving `x` inside along directions about `d` and
    /// refracted out through the surface: the surface's lensing, its curvature included
    /// (finite differences of two neighbouring rays); `None` where they do not all leave.
    pub fn spread_out(&self, x: Vec3, d: Vec3) -> Option<f32> {
        let (rays, inside) = self.fan_out(x, d)?;
        let [(_, o0), (_, o1), (_, o2)] = rays;
        let outside = (o1 - o0).cross(o2 - o0).length();
        (inside > 0.0 && outside > 0.0).then(|| outside / inside)
    }

    /// The rays leaving `x` inside along `d` and two neighbours, refracted out: each one's
    /// exit point and direction outside, and twice the solid angle of their triangle inside
    /// (of the order of the step squared); `None` where they do not all leave.
    fn fan_out(&self, x: Vec3, d: Vec3) -> Option<([(Vec3, Vec3); 3], f32)> {
        const STEP: f32 = 2e-3;
        let shape = &self.shape;
        let n = self.n_eff;
        let out = |dir: Vec3| {
            let ray = Ray {
                origin: x,
                direction: dir,
            };
            let (_, t) = shape.intersect(&ray)?;
            let p = ray.at(t.max(0.0));
            Some((p, refract(dir, -shape.normal(p), n, 1.0)?))
        };
        let (t, b) = d.any_orthonormal_pair();
        let (d1, d2) = ((d + STEP * t).normalize(), (d + STEP * b).normalize());
        let rays = [out(d)?, out(d1)?, out(d2)?];
        Some((rays, (d1 - d).cross(d2 - d).length()))
    }

    /// The irradiance across the beam at `x` (relative to the light's, at the stone's centre
    /// facing it) of `source`'s light entering at `entry` and travelling to `x` against
    /// `to_light`, with the surface's exact lensing: a directional light's `(1 − F) n² / J`;
    /// a point light's `(1 − F) n² I / (dA / dω)`, `I = |P|²` its intensity and `dA / dω` the
    /// area swept on the plane through `P` across the beam per solid angle at `x` (the
    /// rays traced back out; exact for a near light, and the `I J / r²` of a far one).
    pub fn light_spread(
        &self,
        source: &LightSource,
        entry: Vec3,
        x: Vec3,
        to_light: Vec3,
    ) -> Option<f32> {
        let normal = self.shape.normal(entry);
        let cos_i = source.direction_to_light(entry).dot(normal);
        if cos_i <= 0.0 {
            return None;
        }
        let gain = (1.0 - fresnel_dielectric(cos_i, 1.0, self.n_eff)) * self.n_eff * self.n_eff;
        match *source {
            LightSource::Directional { .. } => Some(gain / self.spread_out(x, to_light)?),
            LightSource::Point { position } => {
                let (rays, inside) = self.fan_out(x, to_light)?;
                let axis = rays[0].1;
                let on_plane = rays.map(|(p, o)| p + o * ((position - p).dot(axis) / o.dot(axis)));
                let [q0, q1, q2] = on_plane;
                let area = (q1 - q0).cross(q2 - q0).length();
                (inside > 0.0 && area > 0.0)
                    .then(|| gain * position.length_squared() * inside / area)
            }
        }
    }

    /// What lies along `path` between its start and the light's entry point: the
    /// transmittance of the potch and of the domains' haze (returned), and the line of every
    /// family of every domain crossed (except `path.skip`), handed to `notch` with its domain,
    /// in order from the start. `spans` and `lines` are scratch buffers.
    pub fn towards_light(
        &self,
        path: PathToLight,
        spans: &mut Vec<Span>,
        lines: &mut Vec<ActiveLine>,
        notch: &mut dyn FnMut(u32, BraggLine),
    ) -> f32 {
        let PathToLight {
            x,
            to_light,
            distance,
            hint,
            skip,
        } = path;
        spans.clear();
        self.walk(x, to_light, 0.0, distance, hint, &mut |s| {
            spans.push(s);
            true
        });
        let mut optical_depth = 0.0;
        for span in spans.iter() {
            optical_depth += self.optical_depth(span);
            if let Some(d) = span.domain.filter(|&d| Some(d) != skip) {
                lines.clear();
                self.lines(d, -to_light, span.t1 - span.t0, lines);
                for l in lines.iter() {
                    notch(d, l.line);
                }
            }
        }
        (-optical_depth).exp()
    }

    /// The transmittance of the potch and of the domains' haze between `x` and the point
    /// `distance` mm along `to_light`: [`Stone::towards_light`] without the lines, for paths
    /// whose spectrum the notches do not change (those not reflected by any line).
    pub fn transmittance_towards(
        &self,
        x: Vec3,
        to_light: Vec3,
        distance: f32,
        hint: Hint,
        spans: &mut Vec<Span>,
    ) -> f32 {
        spans.clear();
        self.walk(x, to_light, 0.0, distance, hint, &mut |s| {
            spans.push(s);
            true
        });
        let optical_depth: f32 = spans.iter().map(|s| self.optical_depth(s)).sum();
        (-optical_depth).exp()
    }

    /// Extinction × length of one span of a walk.
    fn optical_depth(&self, span: &Span) -> f32 {
        let sigma = match span.domain {
            None => self.potch.extinction_per_mm,
            Some(_) => self.potch.domain_scattering_per_mm,
        };
        sigma * (span.t1 - span.t0)
    }

    /// The line of `line`'s family in `domain` met at `cos_theta` (the same layers): the
    /// half-vector law `λ = 2 d n̄(λ) cos θ_h`, with the dispersion at its own wavelength.
    pub fn line_at(&self, domain: u32, line: &ActiveLine, cos_theta: f32) -> BraggLine {
        let family = &self.families.kinds[line.kind as usize];
        let d = f64::from(self.domains[domain as usize].sphere_diameter_nm);
        let two_dn = 2.0 * f64::from(self.n_eff) * family.spacing_over_diameter * d;
        let index = &self.families.index;
        // `line`'s layers hold its group ratio (`optics::dispersion`): the periods met.
        let layers = line.line.layers / index.line_group_ratio(line.line.center_nm);
        let c = f64::from(cos_theta);
        let (coupling, normal_center_nm, group) = index.line_args(family.coupling, two_dn, c);
        BraggLine::new(coupling, normal_center_nm, c, layers * group)
    }

    /// The density over normals (per steradian) of `line`'s lobe at the unit normal `h` met at
    /// `cos θ_h = cos_h`: a Gaussian of the angle to the family normal, of standard deviation
    /// [`Stone::lobe_sigma`]; zero beyond [`LOBE_SIGMAS`].
    pub fn lobe_density(&self, line: &ActiveLine, h: Vec3, cos_h: f32) -> f32 {
        self.lobe_density_within(line, h, cos_h, LOBE_SIGMAS)
    }

    /// [`Stone::lobe_density`] zero beyond `sigmas` standard deviations (not renormalised:
    /// the Gaussian holds `1 − e^(−sigmas²/2)` of the lobe within them).
    pub fn lobe_density_within(&self, line: &ActiveLine, h: Vec3, cos_h: f32, sigmas: f32) -> f32 {
        let sigma = self.lobe_sigma(line.kind, cos_h);
        Mosaic {
            normal: line.normal,
            sigma,
        }
        .small_angle_density(h, sigmas)
    }

    /// [`Stone::lobe_density`] for a lamp of angular radius `lamp_radius_rad` (outside): the
    /// lobe convolved with the lamp's disc, the disc taken as the Gaussian of its variance.
    /// A disc of radius `a` inside (`r / n̄`, the surface's lensing left out) has the variance
    /// `a²/4` per axis, and the half vector turns by half the light's turn: `σ_lamp = a / 4`.
    /// A mirror (mosaic 0) then shows the lamp as wide as its disc, not as a point.
    pub fn lamp_density(
        &self,
        line: &ActiveLine,
        h: Vec3,
        cos_h: f32,
        lamp_radius_rad: f32,
    ) -> f32 {
        let lamp = 0.25 * lamp_radius_rad / self.n_eff;
        let sigma = self.lobe_sigma(line.kind, cos_h).hypot(lamp);
        Mosaic {
            normal: line.normal,
            sigma,
        }
        .small_angle_density(h, LOBE_SIGMAS)
    }
}

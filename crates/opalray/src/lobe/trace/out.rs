//! The reflected ray's way out of the stone: through the domains (their notches and second
//! reflections) or through the surface alone, and what it sees at each surface event.

use super::*;
use crate::stone::LineWavelength;

impl Tracer<'_> {
    /// [`Tracer::reflected`] through the domains: each segment in the opal walked, dimmed by
    /// the potch and haze, whose own light it sees on the way (the body's radiance where it
    /// scatters, as the eye ray sees it), and, with `lines`, notched by the lines it crosses
    /// whose windows hold `wavelength` (the line's centre), each read over the reflection's
    /// band (`out.band`, [`Band::taken_by`]); what a line takes from it is reflected again and seen through the
    /// surface along its own mirror direction ([`Tracer::seen_out`]: a second Bragg
    /// reflection, so that no light is lost), where `gain` (the eye ray's weight times the
    /// line's largest tristimulus value) times what it takes times the brightest light
    /// reaches [`CUT`], as the first reflection's cull has it; under that, it is only taken.
    pub(super) fn follow_out(
        &mut self,
        out: &Out,
        wavelength: f64,
        sigma: f32,
        lines: bool,
        gain: f32,
    ) -> f32 {
        let stone = self.stone;
        let (mut pos, mut dir, mut region) = (out.face, out.dir, Region::Opal);
        let mut skip = Some(out.domain);
        let mut hint = out.hint;
        let mut way = Outgoing { w: 1.0, seen: 0.0 };
        let notches = Notches {
            band: out.band,
            at_wavelength: stone.line_wavelength(wavelength),
            sigma,
            lines,
            gain,
        };
        for _ in 0..MAX_SEGMENTS {
            let ray = Ray {
                origin: pos,
                direction: dir,
            };
            let Some((t_end, boundary)) = stone.exit(&ray, region) else {
                break;
            };
            if region == Region::Opal {
                self.walk_out(&ray, t_end, std::mem::take(&mut hint));
                let skipped = skip.take();
                self.spans_out(&ray, t_end, boundary, skipped, &notches, &mut way);
            }
            if way.w < MIN_WEIGHT {
                break;
            }
            let at = ray.at(t_end);
            let before = way.w;
            let event;
            (event, pos, dir, region, way.w) =
                self.boundary_out(at, dir, region, boundary, way.w, sigma);
            way.seen += event;
            if boundary == Boundary::Back {
                break;
            }
            if boundary == Boundary::Surface && way.w < PARTIAL * before {
                // A partial reflection at the surface: the share sent back inside is
                // followed through the surface alone, dimmed by the potch under a bar, while
                // what is left of it could still reach the cut.
                let floor = CUT / (gain * way.w * self.peak);
                let back = Ray {
                    origin: pos,
                    direction: dir,
                };
                let (seen, _) = self.escape(&back, region, sigma, Dim::Bar, Hint::default(), floor);
                way.seen += way.w * seen;
                break;
            }
        }
        way.seen
    }

    /// The spans of the reflected ray's segment in the opal up to `t_end`, into `out_spans`,
    /// the walk starting from the cells `hint` holds.
    fn walk_out(&mut self, ray: &Ray, t_end: f32, hint: Hint) {
        self.out_spans.clear();
        let spans = &mut self.out_spans;
        self.stone
            .walk(ray.origin, ray.direction, 0.0, t_end, hint, &mut |s| {
                spans.push(s);
                true
            });
    }

    /// The reflected ray along the spans of its segment in the opal (`out_spans`, the
    /// segment ending at `t_end` on `boundary`): the potch and haze dim it and send it the
    /// body's light, and each domain but `skipped` (the one it was reflected in) notches it.
    fn spans_out(
        &mut self,
        ray: &Ray,
        t_end: f32,
        boundary: Boundary,
        skipped: Option<u32>,
        notches: &Notches,
        way: &mut Outgoing,
    ) {
        let potch = self.stone.potch;
        let ground = ground_of(self.stone, boundary);
        let light_beyond = self.light_beyond(ray.at(t_end), boundary);
        let mut beyond: f32 = self.out_spans.iter().map(|s| self.km_scattering(s)).sum();
        for k in 0..self.out_spans.len() {
            let span = self.out_spans[k];
            let len = span.t1 - span.t0;
            let layer = beyond;
            beyond -= self.km_scattering(&span);
            let sigma_t = match span.domain {
                None => potch.extinction_per_mm,
                Some(_) => potch.domain_scattering_per_mm,
            };
            let kept = (-sigma_t * len).exp();
            if sigma_t > 0.0 {
                // The body seen along the reflection: its light in the line's colour.
                let lit = self.layer_light(ray.at(span.t0), span, layer, ground, light_beyond, 0.0);
                way.seen += way.w * (1.0 - kept) * self.body_radiance(lit);
            }
            way.w *= kept;
            let Some(domain) = span.domain else {
                continue;
            };
            if notches.lines && Some(domain) != skipped {
                self.notch_out(ray, span, domain, notches, way);
            }
        }
    }

    /// The lines of `domain` that the reflected ray crosses along `span` (of the segment
    /// `ray` in the opal) whose windows hold the notches' wavelength: each takes its share of
    /// the reflection's band from the ray's weight, and what it takes is seen along its own mirror direction where it can reach
    /// [`CUT`].
    fn notch_out(
        &mut self,
        ray: &Ray,
        span: Span,
        domain: u32,
        notches: &Notches,
        way: &mut Outgoing,
    ) {
        let dir = ray.direction;
        let len = span.t1 - span.t0;
        self.out_lines.clear();
        let at_wavelength = notches.at_wavelength;
        self.stone
            .lines_at_wavelength(domain, dir, len, at_wavelength, &mut self.out_lines);
        for l in &self.out_lines {
            let r = notches.band.taken_by(&Band::notch(&l.line)) as f32;
            let bound = notches.gain * way.w * r * self.peak;
            if bound >= CUT {
                let again = reflect(dir, l.normal);
                // Followed while what is left of it could still reach the cut.
                let (at, sigma) = (ray.at(span.t0), notches.sigma);
                let seen = self.seen_out(at, again, Region::Opal, sigma, CUT / bound);
                way.seen += way.w * r * seen;
            }
            way.w *= 1.0 - r;
        }
    }

    /// What a ray from `pos` along `dir` in `region` sees through the surface (up to
    /// [`MAX_SEGMENTS`] surface events, no domains on the way, while its weight is at least
    /// `floor`): the environment through a lobe of width `sigma` over normals, in the
    /// stone's radiance.
    pub(super) fn seen_out(
        &self,
        pos: Vec3,
        dir: Vec3,
        region: Region,
        sigma: f32,
        floor: f32,
    ) -> f32 {
        let ray = Ray {
            origin: pos,
            direction: dir,
        };
        self.escape(&ray, region, sigma, Dim::None, Hint::default(), floor)
            .0
    }

    /// Whether `weight` times what a ray from `pos` along `dir` in the opal sees through the
    /// surface ([`Tracer::seen_out`]) reaches [`CUT`]: the same sum, event by event, stopped
    /// at the first event that takes it there. No event adds less than 0 (`1 − F ≥ 0`, the
    /// light's value ≥ 0), and a float sum of such terms never falls, so the answer is the
    /// full sum's: the cull keeps the same lines without the surface events after the one
    /// that decides (the reflections inside the dome a kept line's light goes on to).
    pub(super) fn reaches_cut(&self, pos: Vec3, dir: Vec3, sigma: f32, weight: f32) -> bool {
        let stone = self.stone;
        let (mut pos, mut dir, mut region) = (pos, dir, Region::Opal);
        let (mut w, mut seen) = (1.0f32, 0.0f32);
        for _ in 0..MAX_SEGMENTS {
            let ray = Ray {
                origin: pos,
                direction: dir,
            };
            let Some((t_end, boundary)) = stone.exit(&ray, region) else {
                break;
            };
            let event;
            (event, pos, dir, region, w) =
                self.boundary_out(ray.at(t_end), dir, region, boundary, w, sigma);
            seen += event;
            if weight * seen >= CUT {
                return true;
            }
            if boundary == Boundary::Back || w < MIN_WEIGHT {
                break;
            }
        }
        false
    }

    /// What a ray from `ray`'s origin along its direction in `region` sees through the
    /// surface ([`Tracer::seen_out`]), dimmed on every segment in the opal as `dim` says,
    /// followed only while its weight is at least `floor` (at least [`MIN_WEIGHT`]; a caller
    /// whose ray weighs `g` at most, relative to the brightest light, passes `CUT / g`, so
    /// that it stops where the light left could no longer reach [`CUT`]); and the share of
    /// its weight that the dimming took on the way (the light of a ray from the body that
    /// the surface sends back into it). `hint` holds the cells of the ray's origin, if known
    /// (the first walk starts from them), each later segment's walk starting from the cells
    /// where the last one ended.
    pub(super) fn escape(
        &self,
        ray: &Ray,
        region: Region,
        sigma: f32,
        dim: Dim,
        mut hint: Hint,
        floor: f32,
    ) -> (f32, f32) {
        let floor = floor.max(MIN_WEIGHT);
        let stone = self.stone;
        let potch = stone.potch;
        let (mut pos, mut dir, mut region) = (ray.origin, ray.direction, region);
        let (mut w, mut seen, mut taken) = (1.0f32, 0.0f32, 0.0f32);
        for segment in 0..MAX_SEGMENTS {
            let ray = Ray {
                origin: pos,
                direction: dir,
            };
            let Some((t_end, boundary)) = stone.exit(&ray, region) else {
                break;
            };
            if matches!(dim, Dim::Bar | Dim::Potch | Dim::Body { .. }) && region == Region::Opal {
                let bar = stone.bar_chord(&ray, t_end);
                let chord = match dim {
                    Dim::Body { share } => bar + (t_end - bar).max(0.0) * share,
                    _ => bar,
                };
                let kept = (-potch.extinction_per_mm * chord).exp();
                taken += w * (1.0 - kept);
                w *= kept;
                if w < floor {
                    break;
                }
            }
            // The potch's light under a bar: the haze scatters what the dome sent back along
            // the bar, near where it left the potch (the first segment up is a flat
            // surface's, whose return `r_i` holds the haze's share already).
            // Under `Dim::Potch` the walk only finds the domains' haze: none, no walk.
            let walked = match dim {
                Dim::PotchAndHaze => true,
                Dim::Potch => segment > 0 && potch.domain_scattering_per_mm > 0.0,
                Dim::None | Dim::Bar | Dim::Body { .. } => false,
            };
            if walked && region == Region::Opal {
                let mut tau = 0.0f32;
                hint = stone.walk(pos, dir, 0.0, t_end, hint, &mut |s| {
                    let sigma = match (s.domain, dim) {
                        (None, Dim::PotchAndHaze) => potch.extinction_per_mm,
                        (None, _) => 0.0,
                        (Some(_), _) => potch.domain_scattering_per_mm,
                    };
                    if sigma <= 0.0 {
                        return true;
                    }
                    tau += sigma * (s.t1 - s.t0);
                    // Once the ray is dimmed under its floor, the rest of the walk (which
                    // can only dim it more) is left: it ends below.
                    w * (-tau).exp() >= floor
                });
                taken += w * (1.0 - (-tau).exp());
                w *= (-tau).exp();
                if w < floor {
                    break;
                }
            }
            let event;
            (event, pos, dir, region, w) =
                self.boundary_out(ray.at(t_end), dir, region, boundary, w, sigma);
            seen += event;
            if boundary == Boundary::Back || w < floor {
                break;
            }
        }
        (seen, taken)
    }

    /// A ray of weight `w` along `dir` in `region` meeting `boundary` at `at`: what it sees
    /// escaping there (the environment through a lobe of width `sigma` over normals, times
    /// `(1 − F) n²`), and the ray going on (reflected inside, or into a triplet's other
    /// region; a backing ends it).
    pub(super) fn boundary_out(
        &self,
        at: Vec3,
        dir: Vec3,
        region: Region,
        boundary: Boundary,
        w: f32,
        sigma: f32,
    ) -> (f32, Vec3, Vec3, Region, f32) {
        let stone = self.stone;
        match boundary {
            Boundary::Surface => {
                let n = stone.index_of(region);
                let normal = stone.shape.normal(at);
                let cos_in = dir.dot(normal);
                let f = fresnel_dielectric(cos_in, n, 1.0);
                let mut seen = 0.0;
                if let Some(out) = refract(dir, normal, n, 1.0) {
                    // The lobe's width over directions, twice its width over normals,
                    // widened by the refraction out (its mean over the two axes).
                    let cos_out = out.dot(normal).max(1e-3);
                    let spread = 2.0 * sigma * stone.n_eff * (cos_in.max(1e-3) / cos_out).sqrt();
                    seen = w * (1.0 - f) * n * n * self.seen_through_lobe(at, out, spread);
                }
                (
                    seen,
                    at - normal * EPSILON_MM,
                    reflect(dir, normal),
                    region,
                    w * f,
                )
            }
            Boundary::Back => (0.0, at, dir, region, 0.0),
            Boundary::CapPlane => {
                let (pos, dir, region, w) = self.cap_plane(at, dir, region, w);
                (0.0, pos, dir, region, w)
            }
        }
    }

    /// A ray along `dir` with weight `w` in `region` meeting the plane between a triplet's
    /// slice and its cap at `at`: refracted into the other region with `(1 − F)` and the
    /// radiance's `(n₁/n₂)²`, or reflected whole beyond the critical angle (the plane's
    /// partial reflection is left out: F is under 10⁻³ between silica and quartz).
    pub(super) fn cap_plane(
        &self,
        at: Vec3,
        dir: Vec3,
        region: Region,
        w: f32,
    ) -> (Vec3, Vec3, Region, f32) {
        let stone = self.stone;
        let other = match region {
            Region::Opal => Region::Cap,
            Region::Cap => Region::Opal,
        };
        let (n1, n2) = (stone.index_of(region), stone.index_of(other));
        let facing = if dir.z > 0.0 { -Vec3::Z } else { Vec3::Z };
        match refract(dir, facing, n1, n2) {
            Some(d) => {
                let f = fresnel_dielectric(-dir.dot(facing), n1, n2);
                (
                    at - facing * EPSILON_MM,
                    d,
                    other,
                    w * (1.0 - f) * (n1 / n2) * (n1 / n2),
                )
            }
            None => (at + facing * EPSILON_MM, reflect(dir, facing), region, w),
        }
    }
}

/// What a reflection carries on its way out ([`Tracer::follow_out`]).
struct Outgoing {
    /// Its weight.
    w: f32,
    /// The light it has seen so far.
    seen: f32,
}

/// The band a reflection is followed in and what the lines it crosses do to it.
struct Notches {
    /// The reflection's band: what each line crossed takes of it ([`Band::taken_by`]).
    band: Band,
    /// The reflected line's centre, as the stone's lines that can take from it are found
    /// (their windows, 40 half-widths wide, hold it).
    at_wavelength: LineWavelength,
    /// The lobe's width over normals, rad.
    sigma: f32,
    /// Whether the lines crossed notch the ray at all.
    lines: bool,
    /// The eye ray's weight times the line's largest tristimulus value.
    gain: f32,
}

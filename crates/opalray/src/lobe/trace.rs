//! One camera ray of the lobe integrator (module notes in [`super`]): a loop over the eye
//! ray's segments, and for every line it meets a loop over the reflected ray's segments out
//! of the stone. Bounded loops, no recursion, no random numbers.

use std::f32::consts::PI;

use glam::Vec3;

use super::potch::PotchLight;
use super::{BackingLight, Irradiance, LineColours, LobeSetup};
use crate::geometry::{fresnel_dielectric, reflect, refract, Ray};
use crate::lights::emitters::seen;
use crate::optics::BraggLine;
use crate::scene::Backing;
use crate::stone::{ActiveLine, Boundary, Hint, PathToLight, Region, Span, Stone};

/// Most segments of a ray inside the stone between surface events (its refraction in or its
/// reflection, then up to seven internal reflections: light caught by total reflection in a
/// clear dome after three carries about 1 % of the `crystal` preset's light).
pub const MAX_SEGMENTS: usize = 8;
/// Offset of a new ray's origin along its way, mm (0.1 µm).
const EPSILON_MM: f32 = 1e-4;
/// An eye ray whose weight falls below this adds nothing more.
const MIN_WEIGHT: f32 = 1e-4;
/// A line's reflection adding less luminance than this (relative to a white diffuser under
/// the light) is left out: 1/30 of the darkest step of an 8-bit sRGB image.
const CUT: f32 = 1e-5;
/// A reflection whose light through the surface is under [`CUT`] is followed for the body's
/// light alone (walked without its lines) only where that could add more than this: a dark
/// body's light seen in reflections is a few tenths of a per cent of the black opal's, and
/// following every reflection for it took half as long again.
const BODY_CUT: f32 = 1e-3;
/// A reflection's walk out that loses more than this share of its weight at the surface was
/// partly reflected there (total internal reflection keeps all of it).
const PARTIAL: f32 = 0.99;
/// Most lines of the eye ray kept for the notches of later reflections.
const MAX_EYE_LINES: usize = 96;
/// Directions of the quadrature of the light reaching a point of the backing.
const BACK_DIRECTIONS: usize = 24;

/// What one pixel's camera rays add up to.
pub(super) struct Sums<'b> {
    /// Radiance of the light's white (its spectrum, luminance 1) added.
    pub white: f64,
    /// XYZ of the rest.
    pub xyz: [f64; 3],
    /// Bins of the rest.
    pub bins: &'b mut [f32],
}

/// One thread's camera rays.
pub(super) struct Tracer<'a> {
    stone: &'a Stone,
    setup: &'a LobeSetup<'a>,
    colours: &'a LineColours,
    irradiance: &'a Irradiance,
    /// The light reaching the backing and the potch under a bar (none while they are made).
    lit: Lit<'a>,
    spans: Vec<Span>,
    lines: Vec<ActiveLine>,
    out_spans: Vec<Span>,
    out_lines: Vec<ActiveLine>,
    /// The colours `(XYZ, S)` of the lines of the crossing at hand, and what the eye ray's
    /// earlier lines leave of each line's centre.
    line_colours: Vec<([f64; 3], f64, f64)>,
    /// The lines the eye ray has crossed.
    eye_lines: Vec<BraggLine>,
    /// Their windows (`BraggLine::window_nm`), apart: what every wavelength is checked against.
    eye_windows: Vec<(f64, f64)>,
    /// XYZ the eye ray's notches take from a white of luminance 1.
    notch_xyz: [f64; 3],
    /// The same per bin.
    notch_bins: Vec<f32>,
    bin_width_nm: f64,
    /// The most radiance any reflection can see: the environment's peak or an area light's
    /// value, through the surface.
    peak: f32,
    /// The scene's light as the body sees it: the direction towards it from the stone's
    /// centre and its irradiance there on a plane facing it.
    body_light: Option<(Vec3, f32)>,
    /// Where the camera ray at hand entered the stone.
    entry: Entry,
    /// The most radiance the body can send (in the stone), 0 without a scattering body:
    /// what a reflection can see besides the light through the surface.
    body_peak: f32,
}

impl<'a> Tracer<'a> {
    pub(super) fn new(
        stone: &'a Stone,
        setup: &'a LobeSetup<'a>,
        colours: &'a LineColours,
        irradiance: &'a Irradiance,
        lit: Lit<'a>,
    ) -> Self {
        let body_light = setup
            .light
            .map(|l| (l.source.direction_to_light(Vec3::ZERO), l.intensity))
            .or(setup
                .area_light
                .map(|a| (a.center().normalize(), setup.light_intensity)));
        let mut tracer = Tracer {
            stone,
            setup,
            colours,
            irradiance,
            lit,
            spans: Vec::with_capacity(64),
            lines: Vec::with_capacity(16),
            out_spans: Vec::with_capacity(64),
            out_lines: Vec::with_capacity(16),
            line_colours: Vec::with_capacity(16),
            eye_lines: Vec::with_capacity(MAX_EYE_LINES),
            eye_windows: Vec::with_capacity(MAX_EYE_LINES),
            notch_xyz: [0.0; 3],
            notch_bins: vec![0.0; setup.spectral.grid.bins],
            bin_width_nm: setup.spectral.grid.bin_width_nm(),
            peak: setup
                .environment
                .peak()
                .max(setup.area_light.map_or(0.0, |a| a.value()))
                * stone.n_eff
                * stone.n_eff,
            body_light,
            entry: Entry {
                normal: Vec3::Z,
                fresnel_normal: fresnel_dielectric(1.0, 1.0, stone.n_eff),
            },
            body_peak: 0.0,
        };
        tracer.body_peak = tracer.body_peak(irradiance);
        tracer
    }

    /// The most radiance the body can send into the stone ([`Tracer::body_radiance`] at its
    /// brightest light), 0 where nothing scatters.
    fn body_peak(&self, irradiance: &Irradiance) -> f32 {
        let potch = &self.stone.potch;
        if potch.extinction_per_mm <= 0.0 && potch.domain_scattering_per_mm <= 0.0 {
            return 0.0;
        }
        let lamp = self.body_light.map_or(0.0, |(_, e)| e);
        let lit = irradiance
            .peak()
            .max(self.lit.potch.map_or(0.0, |p| p.peak()))
            + lamp;
        self.body_radiance(self.setup.body_reflectance, lit)
    }

    /// One camera ray.
    pub(super) fn sample(&mut self, ray: Ray, sums: &mut Sums) {
        let stone = self.stone;
        let Some((t0, _)) = stone.shape.intersect(&ray).filter(|&(t0, _)| t0 > 0.0) else {
            sums.white += f64::from(self.seen_sharp(ray.origin, ray.direction));
            return;
        };
        self.eye_lines.clear();
        self.eye_windows.clear();
        self.notch_xyz = [0.0; 3];
        self.notch_bins.iter_mut().for_each(|b| *b = 0.0);
        // The surface: the gloss, and the refracted part goes in.
        let p = ray.at(t0);
        let normal = stone.shape.normal(p);
        let region = stone.region_at(p - normal * EPSILON_MM);
        let n = stone.index_of(region);
        let fresnel = fresnel_dielectric(-ray.direction.dot(normal), 1.0, n);
        let mirror = reflect(ray.direction, normal);
        sums.white += f64::from(
            fresnel * self.setup.gloss * (self.seen_sharp(p, mirror) + self.disc(mirror)),
        );
        let Some(dir) = refract(ray.direction, normal, 1.0, n) else {
            return;
        };
        let entry = Entry {
            normal,
            fresnel_normal: fresnel_dielectric(1.0, 1.0, n),
        };
        self.entry = entry;
        self.inside(p, dir, region, (1.0 - fresnel) / (n * n), sums);
    }

    /// The eye ray inside the stone from `pos` along `dir` in `region`, with weight `w`.
    fn inside(
        &mut self,
        mut pos: Vec3,
        mut dir: Vec3,
        mut region: Region,
        mut w: f32,
        sums: &mut Sums,
    ) {
        let stone = self.stone;
        let potch = stone.potch;
        for _ in 0..MAX_SEGMENTS {
            let ray = Ray {
                origin: pos,
                direction: dir,
            };
            let Some((t_end, boundary)) = stone.exit(&ray, region) else {
                return;
            };
            if region == Region::Opal {
                self.spans.clear();
                let spans = &mut self.spans;
                stone.walk(pos, dir, 0.0, t_end, Hint::default(), &mut |s| {
                    spans.push(s);
                    true
                });
                // The body's scattering thickness from each span to the segment's end, and
                // what lies beyond it: the body there is a layer of that thickness.
                let ground = ground_of(stone, boundary);
                let mut beyond: f32 = self.spans.iter().map(|s| self.km_scattering(s)).sum();
                for k in 0..self.spans.len() {
                    let span = self.spans[k];
                    let layer = beyond;
                    beyond -= self.km_scattering(&span);
                    let sigma = match span.domain {
                        None => potch.extinction_per_mm,
                        Some(domain) => {
                            self.cross(&ray, span, domain, w, sums);
                            potch.domain_scattering_per_mm
                        }
                    };
                    if sigma > 0.0 {
                        let tau = sigma * (span.t1 - span.t0);
                        let kept = (-tau).exp();
                        let r = layer_reflectance(self.setup.body_reflectance, layer, ground);
                        let lit = self.light_on_body(ray.at(span.t0), span);
                        self.body(w * (1.0 - kept), r, lit, sums);
                        w *= kept;
                    }
                    if w < MIN_WEIGHT {
                        return;
                    }
                }
            }
            let at = ray.at(t_end);
            match boundary {
                Boundary::Surface => {
                    let n = stone.index_of(region);
                    let normal = stone.shape.normal(at);
                    let f = fresnel_dielectric(dir.dot(normal), n, 1.0);
                    if let Some(out) = refract(dir, normal, n, 1.0) {
                        let v = w * (1.0 - f) * n * n * self.seen_sharp(at, out);
                        self.add_notched_white(f64::from(v), sums);
                    }
                    w *= f;
                    dir = reflect(dir, normal);
                    pos = at - normal * EPSILON_MM;
                }
                Boundary::Back => {
                    self.backing(w, at, sums);
                    return;
                }
                Boundary::CapPlane => {
                    (pos, dir, region, w) = self.cap_plane(at, dir, region, w);
                }
            }
            if w < MIN_WEIGHT {
                return;
            }
        }
    }

    /// The eye ray along `ray` crossing `domain` over `span`, with weight `w`: every line's
    /// reflection of the lights, then its notch on the way on.
    fn cross(&mut self, ray: &Ray, span: Span, domain: u32, w: f32, sums: &mut Sums) {
        let stone = self.stone;
        let dir = ray.direction;
        let mut lines = std::mem::take(&mut self.lines);
        lines.clear();
        stone.lines(domain, dir, span.t1 - span.t0, &mut lines);
        let face = ray.at(span.t0);
        let mut colours = std::mem::take(&mut self.line_colours);
        colours.clear();
        for l in &lines {
            let (xyz, s) = self.colours.of(&l.line);
            let t_in = self.eye_transmittance(l.line.center_nm);
            colours.push((xyz, s, t_in));
            let weight = w * t_in as f32;
            if weight * xyz[1] as f32 * (self.peak + self.body_peak) > CUT {
                let cos_theta = -dir.dot(l.normal);
                let sigma = stone.lobe_sigma(l.kind, cos_theta);
                // The line as the lobe's normals spread it.
                let (xyz, s, center) =
                    self.colours
                        .in_lobe(&l.line, (xyz, s), cos_theta.into(), sigma.into());
                let mirror = reflect(dir, l.normal);
                let out = Out {
                    face,
                    dir: mirror,
                    domain,
                    hint: span.hint,
                };
                let seen = self.reflected(&out, &l.line, sigma, weight * xyz[1] as f32);
                self.add_line(f64::from(weight * seen), xyz, s, center, sums);
            }
            if self.setup.light.is_some() {
                self.light_at(ray.at(span.t0 + EPSILON_MM), dir, domain, l, weight, sums);
            }
        }
        // The ray goes on through, carrying each line's notch: what the earlier lines, this
        // crossing's before it among them, leave of its centre.
        for (k, (l, &(xyz, s, t_in))) in lines.iter().zip(&colours).enumerate() {
            if self.eye_lines.len() >= MAX_EYE_LINES {
                break;
            }
            let centre = l.line.center_nm;
            let mut t_prev = t_in;
            for before in &lines[..k] {
                let (lo, hi) = before.line.window_nm();
                if centre > lo && centre < hi {
                    t_prev *= 1.0 - before.line.reflectance(centre);
                }
            }
            for (n, v) in self.notch_xyz.iter_mut().zip(xyz) {
                *n += t_prev * v;
            }
            if let Some(b) = self.setup.spectral.grid.bin_of(l.line.center_nm) {
                self.notch_bins[b] += (t_prev * s / self.bin_width_nm) as f32;
            }
            self.eye_windows.push(l.line.window_nm());
            self.eye_lines.push(l.line);
        }
        self.line_colours = colours;
        self.lines = lines;
    }

    /// `Π (1 − R)` at `wavelength_nm` of the lines the eye ray has crossed.
    fn eye_transmittance(&self, wavelength_nm: f64) -> f64 {
        let mut t = 1.0;
        for (k, (lo, hi)) in self.eye_windows.iter().enumerate() {
            if wavelength_nm > *lo && wavelength_nm < *hi {
                t *= 1.0 - self.eye_lines[k].reflectance(wavelength_nm);
            }
        }
        t
    }

    /// The radiance (in the stone, relative to the light's) that reaches the domain's face
    /// `face` against `dir`, the mirror direction of `line` whose lobe has width `sigma`
    /// (over normals, radians): the environment through the lobe, carried in through every
    /// surface event up to [`MAX_SEGMENTS`], notched at the line's centre by the lines on
    /// the way and dimmed by the potch and haze. Where `weight` times the line's luminance
    /// times what the surface alone lets through is under [`CUT`], 0: the walks through the
    /// domains, which only dim it, are then left out.
    fn reflected(&mut self, out: &Out, line: &BraggLine, sigma: f32, weight: f32) -> f32 {
        let bound = self.seen_out(out.face, out.dir, Region::Opal, sigma);
        if weight * bound >= CUT {
            self.follow_out(out, line.center_nm, sigma, true)
        } else if weight * self.body_peak >= BODY_CUT {
            // Only the body can add enough: its light along the way, the lines not read.
            self.follow_out(out, line.center_nm, sigma, false)
        } else {
            0.0
        }
    }

    /// [`Tracer::reflected`] through the domains: each segment in the opal walked, dimmed by
    /// the potch and haze, whose own light it sees on the way (the body's radiance where it
    /// scatters, as the eye ray sees it), and, with `lines`, notched at `wavelength` by the
    /// lines it crosses; what a line takes from it is reflected again and seen through the
    /// surface along its own mirror direction ([`Tracer::seen_out`]: a second Bragg
    /// reflection, so that no light is lost).
    fn follow_out(&mut self, out: &Out, wavelength: f64, sigma: f32, lines: bool) -> f32 {
        let stone = self.stone;
        let potch = stone.potch;
        let (mut pos, mut dir, mut region) = (out.face, out.dir, Region::Opal);
        let mut skip = Some(out.domain);
        let mut hint = out.hint;
        let (mut w, mut seen) = (1.0f32, 0.0f32);
        for _ in 0..MAX_SEGMENTS {
            let ray = Ray {
                origin: pos,
                direction: dir,
            };
            let Some((t_end, boundary)) = stone.exit(&ray, region) else {
                break;
            };
            if region == Region::Opal {
                self.out_spans.clear();
                let spans = &mut self.out_spans;
                stone.walk(pos, dir, 0.0, t_end, std::mem::take(&mut hint), &mut |s| {
                    spans.push(s);
                    true
                });
                let skipped = skip.take();
                let ground = ground_of(stone, boundary);
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
                        let r = layer_reflectance(self.setup.body_reflectance, layer, ground);
                        let lit = self.light_on_body(ray.at(span.t0), span);
                        seen += w * (1.0 - kept) * self.body_radiance(r, lit);
                    }
                    w *= kept;
                    let Some(domain) = span.domain else {
                        continue;
                    };
                    if !lines || Some(domain) == skipped {
                        continue;
                    }
                    self.out_lines.clear();
                    stone.lines_at(domain, dir, len, wavelength, &mut self.out_lines);
                    for l in &self.out_lines {
                        let r = l.line.reflectance(wavelength) as f32;
                        let again = reflect(dir, l.normal);
                        seen += w * r * self.seen_out(ray.at(span.t0), again, region, sigma);
                        w *= 1.0 - r;
                    }
                }
            }
            if w < MIN_WEIGHT {
                break;
            }
            let at = ray.at(t_end);
            let before = w;
            let event;
            (event, pos, dir, region, w) = self.boundary_out(at, dir, region, boundary, w, sigma);
            seen += event;
            if boundary == Boundary::Back {
                break;
            }
            if boundary == Boundary::Surface && w < PARTIAL * before {
                // A partial reflection at the surface: the share sent back inside is
                // followed through the surface alone, dimmed by the potch under a bar.
                seen += w * self.escape(pos, dir, region, sigma, Dim::Bar, Hint::default());
                break;
            }
        }
        seen
    }

    /// What a ray from `pos` along `dir` in `region` sees through the surface (up to
    /// [`MAX_SEGMENTS`] surface events, no domains on the way): the environment through a
    /// lobe of width `sigma` over normals, in the stone's radiance.
    fn seen_out(&self, pos: Vec3, dir: Vec3, region: Region, sigma: f32) -> f32 {
        self.escape(pos, dir, region, sigma, Dim::None, Hint::default())
    }

    /// [`Tracer::seen_out`], dimmed on every segment in the opal as `dim` says; `hint` holds
    /// the cells of `pos`, if known (the first walk starts from them), each later segment's
    /// walk starting from the cells where the last one ended.
    fn escape(
        &self,
        pos: Vec3,
        dir: Vec3,
        region: Region,
        sigma: f32,
        dim: Dim,
        mut hint: Hint,
    ) -> f32 {
        let stone = self.stone;
        let potch = stone.potch;
        let (mut pos, mut dir, mut region) = (pos, dir, region);
        let (mut w, mut seen) = (1.0f32, 0.0f32);
        for _ in 0..MAX_SEGMENTS {
            let ray = Ray {
                origin: pos,
                direction: dir,
            };
            let Some((t_end, boundary)) = stone.exit(&ray, region) else {
                break;
            };
            if dim == Dim::Bar && region == Region::Opal {
                w *= (-potch.extinction_per_mm * stone.bar_chord(&ray, t_end)).exp();
                if w < MIN_WEIGHT {
                    break;
                }
            } else if dim != Dim::None && region == Region::Opal {
                let mut tau = 0.0f32;
                hint = stone.walk(pos, dir, 0.0, t_end, hint, &mut |s| {
                    let sigma = match (s.domain, dim) {
                        (None, _) => potch.extinction_per_mm,
                        (Some(_), Dim::PotchAndHaze) => potch.domain_scattering_per_mm,
                        (Some(_), _) => 0.0,
                    };
                    if sigma <= 0.0 {
                        return true;
                    }
                    tau += sigma * (s.t1 - s.t0);
                    // Once the ray is dimmed under MIN_WEIGHT, the rest of the walk (which
                    // can only dim it more) is left: it ends below.
                    w * (-tau).exp() >= MIN_WEIGHT
                });
                w *= (-tau).exp();
                if w < MIN_WEIGHT {
                    break;
                }
            }
            let event;
            (event, pos, dir, region, w) =
                self.boundary_out(ray.at(t_end), dir, region, boundary, w, sigma);
            seen += event;
            if boundary == Boundary::Back || w < MIN_WEIGHT {
                break;
            }
        }
        seen
    }

    /// A ray of weight `w` along `dir` in `region` meeting `boundary` at `at`: what it sees
    /// escaping there (the environment through a lobe of width `sigma` over normals, times
    /// `(1 − F) n²`), and the ray going on (reflected inside, or into a triplet's other
    /// region; a backing ends it).
    fn boundary_out(
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
    fn cap_plane(&self, at: Vec3, dir: Vec3, region: Region, w: f32) -> (Vec3, Vec3, Region, f32) {
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

    /// The scene's point or directional light reflected by `line` of `domain` at `x` towards
    /// the eye ray along `dir`, with weight `w`: `π E R(λ, θ_h) D(h) / (4 cos θ_h)`.
    fn light_at(
        &mut self,
        x: Vec3,
        dir: Vec3,
        domain: u32,
        line: &ActiveLine,
        w: f32,
        sums: &mut Sums,
    ) {
        let stone = self.stone;
        let Some(light) = self.setup.light else {
            return;
        };
        let Some((to_light, irradiance, distance)) = stone.light_entry(&light.source, x) else {
            return;
        };
        let h = (to_light - dir).normalize_or_zero();
        let cos_h = h.dot(to_light);
        if cos_h <= 0.0 {
            return;
        }
        let density = stone.lobe_density(line, h, cos_h);
        if density <= 0.0 {
            return;
        }
        let at_h = stone.line_at(domain, line, cos_h);
        let wavelength = at_h.center_nm;
        let mut notches = 1.0f64;
        let path = PathToLight {
            x,
            to_light,
            distance,
            hint: Hint::default(),
            skip: Some(domain),
        };
        let kept = stone.towards_light(
            path,
            &mut self.out_spans,
            &mut self.out_lines,
            &mut |_, l| {
                let (lo, hi) = l.window_nm();
                if wavelength > lo && wavelength < hi {
                    notches *= 1.0 - l.reflectance(wavelength);
                }
            },
        );
        let (xyz, s) = self.colours.of(&at_h);
        let value = w
            * PI
            * irradiance
            * light.intensity
            * kept
            * notches as f32
            * self.eye_transmittance(wavelength) as f32
            * density
            / (4.0 * cos_h);
        self.add_line(f64::from(value), xyz, s, wavelength, sums);
    }

    /// The body seen by the share `w` of the eye ray scattered in it: `reflectance` (its
    /// Munsell value, or less for a thin layer, [`layer_reflectance`]) under the
    /// environment's irradiance at the surface the eye ray entered (the chip's reflectance
    /// includes the surface's `1 − F₀` on the way in, which the eye ray's weight holds
    /// already).
    fn body(&mut self, w: f32, reflectance: f32, e: f32, sums: &mut Sums) {
        let v = w * self.body_radiance(reflectance, e);
        self.add_notched_white(f64::from(v), sums);
    }

    /// The irradiance (outside, `Ē`) that lights the body where the eye ray meets it at `at`
    /// over `span`: under a colour bar the light reaching the potch's top through the bar
    /// ([`PotchLight`]), elsewhere the room's and the lamp's at the surface the eye ray
    /// entered.
    fn light_on_body(&self, at: Vec3, span: Span) -> f32 {
        match self.lit.potch {
            Some(potch) if span.domain.is_none() && potch.holds(at) => potch.at(at),
            _ => self.irradiance_on(self.entry.normal),
        }
    }

    /// The radiance in the stone of a body of reflectance `reflectance` lit by the outside
    /// irradiance `e` (a chip at the surface the eye ray entered: its reflectance includes
    /// the surface's `1 − F₀` on the way in).
    fn body_radiance(&self, reflectance: f32, e: f32) -> f32 {
        let n = self.stone.n_eff;
        n * n * reflectance * e / (1.0 - self.entry.fresnel_normal)
    }

    /// The backing seen at `at` by the eye ray with weight `w`: its reflectance under the
    /// light that reaches it through the stone ([`BackingLight`]).
    fn backing(&mut self, w: f32, at: Vec3, sums: &mut Sums) {
        let stone = self.stone;
        let Some(back) = stone.back else {
            return;
        };
        let light = self.lit.backing.map_or(0.0, |b| b.at(at));
        let v = w * light;
        match back.kind {
            Backing::None => {}
            Backing::Black => {
                self.add_notched_white(f64::from(v * back.reflectance(550.0) as f32), sums)
            }
            Backing::Ironstone => {
                let (xyz, bins) = self.setup.spectral.tinted_white(1);
                for (sum, x) in sums.xyz.iter_mut().zip(xyz) {
                    *sum += f64::from(v) * x;
                }
                for (b, t) in sums.bins.iter_mut().zip(bins) {
                    *b += v * t;
                }
            }
        }
    }

    /// The light reaching the backing at `at` (on the back plane), as the radiance a white
    /// Lambertian backing there sends back into the stone: the mean, over
    /// [`BACK_DIRECTIONS`] cosine-distributed directions up into the stone (a Fibonacci
    /// spiral on the disc, lifted to the hemisphere), of what each sees through the stone —
    /// dimmed by the potch and haze, refracted out with `(1 − F) n²` (the rest reflected
    /// inside and followed), the environment read through a lobe of the quadrature's spacing
    /// and the area light — and the point or directional light along its refracted path.
    /// The lines' notches on the way are left out, and so is the light the backing sends
    /// up that the dome reflects back to it.
    pub(super) fn light_on_backing(&mut self, at: Vec3) -> f32 {
        self.light_on(
            at + Vec3::Z * EPSILON_MM,
            Vec3::Z,
            BACK_DIRECTIONS,
            Dim::PotchAndHaze,
        )
    }

    /// [`Tracer::light_on_backing`] at `at`, inside the stone, on a surface of unit normal
    /// `normal` (`directions` of them, cosine-distributed about it), dimmed as `dim` says.
    pub(super) fn light_on(&mut self, at: Vec3, normal: Vec3, directions: usize, dim: Dim) -> f32 {
        let count = directions as f32;
        // Half the spacing of the directions, over normals (`boundary_out` doubles it).
        let sigma = 0.25 * (PI / count).sqrt();
        let golden = PI * (3.0 - 5f32.sqrt());
        let (t, b) = normal.any_orthonormal_pair();
        // The cells holding `at`, where every direction's walk starts.
        let mut start = Hint::default();
        if dim != Dim::None && self.stone.region_at(at) == Region::Opal {
            self.stone
                .walk(at, normal, 0.0, EPSILON_MM, start, &mut |s| {
                    start = s.hint;
                    false
                });
        }
        let mut sum = 0.0;
        for k in 0..directions {
            let r = ((k as f32 + 0.5) / count).sqrt();
            let phi = golden * k as f32;
            let dir = (t * (r * phi.cos()) + b * (r * phi.sin()))
                + normal * (1.0 - r * r).max(0.0).sqrt();
            sum += self.escape(at, dir, self.stone.region_at(at), sigma, dim, start);
        }
        sum / count + self.point_light_on(at, normal)
    }

    /// The point or directional light's irradiance at `x` inside the stone along its
    /// refracted path, dimmed by the potch and haze on the way (its lines' notches left
    /// out), as the radiance a white Lambertian surface of unit normal `normal` sends back.
    fn point_light_on(&mut self, x: Vec3, normal: Vec3) -> f32 {
        let Some(light) = self.setup.light else {
            return 0.0;
        };
        let stone = self.stone;
        let Some((to_light, irradiance, distance)) = stone.light_entry(&light.source, x) else {
            return 0.0;
        };
        let path = PathToLight {
            x,
            to_light,
            distance,
            hint: Hint::default(),
            skip: None,
        };
        let kept = stone.towards_light(
            path,
            &mut self.out_spans,
            &mut self.out_lines,
            &mut |_, _| {},
        );
        light.intensity * irradiance * kept * to_light.dot(normal).max(0.0)
    }

    /// Add `v` of the light's white less the eye ray's notches.
    fn add_notched_white(&self, v: f64, sums: &mut Sums) {
        if v == 0.0 {
            return;
        }
        sums.white += v;
        for c in 0..3 {
            sums.xyz[c] -= v * self.notch_xyz[c];
        }
        for (b, n) in sums.bins.iter_mut().zip(&self.notch_bins) {
            *b -= (v * f64::from(*n)) as f32;
        }
    }

    /// Add `v` times a line's colour `xyz` (and `s`, its `∫ R S dλ`) at `center_nm`.
    fn add_line(&self, v: f64, xyz: [f64; 3], s: f64, center_nm: f64, sums: &mut Sums) {
        if v == 0.0 {
            return;
        }
        for (sum, x) in sums.xyz.iter_mut().zip(xyz) {
            *sum += v * x;
        }
        if let Some(b) = self.setup.spectral.grid.bin_of(center_nm) {
            sums.bins[b] += (v * s / self.bin_width_nm) as f32;
        }
    }

    /// What a ray leaving the stone at `at` along `dir` sees: the area light where it meets
    /// it, else the environment.
    fn seen_sharp(&self, at: Vec3, dir: Vec3) -> f32 {
        seen(
            self.setup.environment,
            self.setup.area_light.as_ref(),
            at,
            dir,
        )
        .0
    }

    /// What a lobe of directions of width `spread` (radians, per axis) about `dir` sees
    /// leaving the stone at `at`: the area light over the share of the lobe it fills
    /// ([`crate::lights::AreaLight::lobe_share`]), the environment through the rest.
    fn seen_through_lobe(&self, at: Vec3, dir: Vec3, spread: f32) -> f32 {
        let env = self.setup.environment.filtered(dir, spread);
        match self.setup.area_light {
            Some(light) => {
                let share = light.lobe_share(at, dir, spread);
                env * (1.0 - share) + light.value() * share
            }
            None => env,
        }
    }

    /// The irradiance on a plane of unit normal `n` outside the stone: the environment's
    /// ([`Irradiance`]) and the light's, `E max(0, n·ℓ)` (its horizon's clipping of a large
    /// area light left out).
    fn irradiance_on(&self, n: Vec3) -> f32 {
        let light = self
            .body_light
            .map_or(0.0, |(to, e)| e * n.dot(to).max(0.0));
        self.irradiance.at(n) + light
    }

    /// The light's disc seen along `dir` from outside, in image units.
    fn disc(&self, dir: Vec3) -> f32 {
        self.setup.light.map_or(0.0, |light| light.disc(dir))
    }
}

impl Tracer<'_> {
    /// Kubelka–Munk scattering thickness `S X` of `span`: `S = ¾ σ_s (1 − g)` of the potch
    /// (σ_s its extinction times its albedo) or of a milky domain's haze.
    fn km_scattering(&self, span: &Span) -> f32 {
        let potch = &self.stone.potch;
        let sigma_s = match span.domain {
            None => potch.extinction_per_mm * potch.albedo,
            Some(_) => potch.domain_scattering_per_mm,
        };
        0.75 * sigma_s * (1.0 - potch.anisotropy) * (span.t1 - span.t0)
    }
}

/// The reflectance of a layer of body of scattering thickness `sx` (Kubelka–Munk `S X`)
/// over a ground of reflectance `ground`, the body's own reflectance when thick being
/// `thick` (Kubelka & Munk 1931; Judd & Wyszecki, *Color in Business, Science and
/// Industry*, §3.8): `R = (1 − R_g (a − b coth bSX)) / (a − R_g + b coth bSX)`,
/// `a = (1 + R∞²)/(2 R∞)`, `b = √(a² − 1)`. A thick layer shows `R∞`, a thin one its ground.
fn layer_reflectance(thick: f32, sx: f32, ground: f32) -> f32 {
    let r_inf = f64::from(thick).clamp(1e-4, 0.9999);
    let a = (1.0 + r_inf * r_inf) / (2.0 * r_inf);
    let b = (a * a - 1.0).sqrt();
    let x = (b * f64::from(sx.max(0.0))).max(1e-9);
    if x > 20.0 {
        return thick;
    }
    let coth = 1.0 / x.tanh();
    let g = f64::from(ground);
    ((1.0 - g * (a - b * coth)) / (a - g + b * coth)) as f32
}

/// What dims a ray on its way out ([`Tracer::escape`]).
#[derive(Clone, Copy, PartialEq, Eq)]
pub(super) enum Dim {
    /// Nothing: the surface alone.
    None,
    /// The potch, whose light is the body's own (a milky domain's haze sends on most of
    /// what it scatters, down to the potch under a colour bar).
    Potch,
    /// The potch and the domains' haze.
    PotchAndHaze,
    /// The potch under a colour bar alone (its chord, without a walk).
    Bar,
}

/// The tables of light inside the stone a tracer reads (none while they are being made).
#[derive(Clone, Copy, Default)]
pub(super) struct Lit<'a> {
    /// The light reaching the backing.
    pub backing: Option<&'a BackingLight>,
    /// The light reaching the potch under a colour bar.
    pub potch: Option<&'a PotchLight>,
}

/// The reflectance of what lies beyond a segment in the opal that ends at `boundary`: the
/// backing's (at 550 nm) or nothing.
fn ground_of(stone: &Stone, boundary: Boundary) -> f32 {
    match (boundary, stone.back) {
        (Boundary::Back, Some(back)) => back.reflectance(550.0) as f32,
        _ => 0.0,
    }
}

/// A reflection leaving a domain: its face, its direction, the domain (the reflected ray
/// leaves it through that face) and the cells likely to hold the face.
struct Out {
    face: Vec3,
    dir: Vec3,
    domain: u32,
    hint: Hint,
}

/// Where the eye ray entered the stone.
#[derive(Clone, Copy)]
struct Entry {
    /// The surface's outward normal there.
    normal: Vec3,
    /// The surface's Fresnel reflectance at normal incidence.
    fresnel_normal: f32,
}

#[cfg(test)]
mod tests {
    use super::layer_reflectance;

    #[test]
    fn a_layer_shows_its_ground_when_thin_and_its_own_reflectance_when_thick() {
        assert!((layer_reflectance(0.3, 1e-6, 0.03) - 0.03).abs() < 1e-4);
        assert!((layer_reflectance(0.3, 50.0, 0.03) - 0.3).abs() < 1e-6);
        // Over a ground of its own reflectance a layer of any thickness shows that.
        for sx in [0.1, 1.0, 3.0] {
            assert!((layer_reflectance(0.3, sx, 0.3) - 0.3).abs() < 1e-5, "{sx}");
        }
        // Kubelka–Munk over black: R = 1 / (a + b coth bSX); R∞ = 0.5, SX = 1 gives
        // a = 1.25, b = 0.75, R = 1 / (1.25 + 0.75 coth 0.75) = 0.4114 (hand computed).
        assert!((layer_reflectance(0.5, 1.0, 0.0) - 0.4114).abs() < 1e-3);
    }
}

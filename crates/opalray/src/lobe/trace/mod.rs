//! One camera ray of the lobe integrator (module notes in [`super`]): a loop over the eye
//! ray's segments, and for every line it meets a loop over the reflected ray's segments out
//! of the stone. Bounded loops, no recursion, no random numbers.

use std::f32::consts::PI;

use glam::Vec3;

use super::band::Band;
use super::colour::LineProfile;
use super::layer::BodyLayer;
use super::potch::PotchLight;
use super::{BackingLight, Irradiance, LineColours, LobeSetup};
use crate::geometry::{fresnel_dielectric, reflect, refract, Ray};
use crate::lights::emitters::seen;
use crate::optics::BraggLine;
use crate::scene::Backing;
use crate::stone::{ActiveLine, Boundary, Hint, PathToLight, Region, Span, Stone};

mod cross;
mod lit;
mod out;
mod reuse;
mod seen;
mod single;
#[cfg(test)]
mod tests;
mod trapped;

use lit::{ground_of, Beam};
use reuse::Meeting;
pub(super) use reuse::{Followed, Mode, Reuse, Scattered};

/// Most segments of a ray inside the stone between surface events (its refraction in or its
/// reflection, then up to seven internal reflections: light caught by total reflection in a
/// clear dome after three carries about 1 % of the `crystal` preset's light).
pub const MAX_SEGMENTS: usize = 8;
/// Offset of a new ray's origin along its way, mm (0.1 µm).
const EPSILON_MM: f32 = 1e-4;
/// An eye ray whose weight falls below this adds nothing more.
const MIN_WEIGHT: f32 = 1e-4;
/// An eye ray left with less than this weight by a partial reflection at the surface inside
/// the opal is followed out through the surface alone ([`Tracer::faint`]): its domains'
/// reflections, its body's light and its notches on the way are left out. It came in with
/// `(1 − F)/n²` ≈ 46 %, and each partial reflection keeps 3–10 % of that: in a clear stone
/// it goes faint after its second. In the clear `crystal` the faint rays took 45 % of the
/// frame's time, and what their domains and body added was 0.01 % of its light
/// (`BENCHMARKS.md`); what they see through the surface, the internal images of the lights
/// along the rim, is kept.
const FAINT_WEIGHT: f32 = 0.01;
/// The lobe (over normals, radians) through which a faint eye ray reads the light out of
/// the stone: a near-sharp one, about 0.17° wide outside (six pixels of the default frame).
const FAINT_SIGMA: f32 = 1e-3;
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
    /// The lines of the crossing at hand: their colours `(XYZ, S)` and notches.
    line_colours: Vec<CrossedLine>,
    /// The lines the eye ray has crossed.
    eye_lines: Vec<BraggLine>,
    /// Their windows (`BraggLine::window_nm`), apart: what a point or directional light's
    /// wavelength is checked against ([`Tracer::eye_transmittance`]).
    eye_windows: Vec<(f64, f64)>,
    /// Their notches ([`Band::notch`]): what a reflection's band, or a notch's, is read
    /// against.
    eye_bands: Vec<Band>,
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
    /// The body as a layer of the stone's thickness.
    layer: BodyLayer,
    /// The point or directional light's beam into the body where the camera ray entered.
    beam: Option<Beam>,
    /// The eye ray's segment at hand (surface events before it).
    segment: u8,
    /// The reflections the pixel's rays have followed out.
    pub(super) reuse: Reuse,
    /// The domains the eye ray at hand crossed, each with its segment, in order.
    crossed: Vec<(u8, u32)>,
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
            eye_bands: Vec::with_capacity(MAX_EYE_LINES),
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
            layer: BodyLayer::new(&stone.potch, stone.n_eff, setup.body_reflectance),
            beam: None,
            segment: 0,
            reuse: Reuse::default(),
            crossed: Vec::with_capacity(32),
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
        // The tone's value: a thin layer lit from beyond sends more (`BodyLayer::of`), but
        // bounding by what a scattering sees of it on average made black-opal's view pass
        // 31 % longer (BENCHMARKS.md); a reflection walked for the body alone misses it.
        self.body_radiance(self.setup.body_reflectance * lit)
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
        self.eye_bands.clear();
        self.crossed.clear();
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
        self.beam = self.beam_at_entry();
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
        // The last segment in the opal, whose potch dims a faint ray.
        let mut last = None;
        for segment in 0..MAX_SEGMENTS {
            self.segment = segment as u8;
            let ray = Ray {
                origin: pos,
                direction: dir,
            };
            let Some((t_end, boundary)) = stone.exit(&ray, region) else {
                return;
            };
            if region == Region::Opal {
                self.walk_eye(&ray, t_end);
                last = Some((ray, t_end));
                let Some(kept) = self.spans_eye(&ray, t_end, boundary, w, sums) else {
                    return;
                };
                w = kept;
            }
            let at = ray.at(t_end);
            let before = w;
            let Some(next) = self.boundary_eye(at, dir, region, boundary, w, sums) else {
                return;
            };
            (pos, dir, region, w) = next;
            if w < MIN_WEIGHT {
                return;
            }
            let partial = boundary == Boundary::Surface && w < PARTIAL * before;
            if partial && w < FAINT_WEIGHT && region == Region::Opal {
                // The segment just walked, in the opal, was the ray's last: a body that
                // scattered a share of it could show more than `BODY_CUT` on the segments
                // left, and is not left out.
                let scattered = 1.0 - (-self.scattering_depth()).exp();
                if w * self.body_peak * scattered < BODY_CUT {
                    let share =
                        last.map_or(1.0, |(ray, t_end)| self.potch_on_segment(&ray, t_end).1);
                    self.faint(pos, dir, w, share, sums);
                    return;
                }
            }
        }
    }

    /// The potch on the eye ray's segment `ray` in the opal (its spans in `spans`, ending at
    /// `t_end`): its length, and its share of the segment beyond the chord under a colour
    /// bar (what [`Dim::Body`] dims by besides that chord).
    fn potch_on_segment(&self, ray: &Ray, t_end: f32) -> (f32, f32) {
        let chord: f32 = self
            .spans
            .iter()
            .filter(|s| s.domain.is_none())
            .map(|s| s.t1 - s.t0)
            .sum();
        let bar = self.stone.bar_chord(ray, t_end);
        let rest = t_end - bar;
        let share = if rest > 1e-6 {
            ((chord - bar) / rest).clamp(0.0, 1.0)
        } else {
            0.0
        };
        (chord, share)
    }

    /// The optical depth of the potch and haze on the eye ray's last segment (its spans in
    /// `spans`).
    fn scattering_depth(&self) -> f32 {
        let potch = self.stone.potch;
        self.spans
            .iter()
            .map(|s| {
                let sigma = match s.domain {
                    None => potch.extinction_per_mm,
                    Some(_) => potch.domain_scattering_per_mm,
                };
                sigma * (s.t1 - s.t0)
            })
            .sum()
    }

    /// A faint eye ray of weight `w` from `pos` along `dir` in the opal ([`FAINT_WEIGHT`]):
    /// what it sees out through the surface ([`Tracer::escape`]: its internal reflections
    /// with their Fresnel weights, dimmed by the potch as its last segment found it,
    /// `share`), notched by the lines it crossed before. A backing it reaches shows it
    /// nothing.
    fn faint(&mut self, pos: Vec3, dir: Vec3, w: f32, share: f32, sums: &mut Sums) {
        let ray = Ray {
            origin: pos,
            direction: dir,
        };
        let dim = Dim::Body { share };
        // Followed while its weight stays over [`MIN_WEIGHT`], as the eye ray was.
        let floor = MIN_WEIGHT / w;
        let (seen, _) = self.escape(&ray, Region::Opal, FAINT_SIGMA, dim, Hint::default(), floor);
        self.add_notched_white(f64::from(w * seen), sums);
    }

    /// The spans of the eye ray's segment in the opal up to `t_end`, into `spans`.
    fn walk_eye(&mut self, ray: &Ray, t_end: f32) {
        self.spans.clear();
        let spans = &mut self.spans;
        self.stone.walk(
            ray.origin,
            ray.direction,
            0.0,
            t_end,
            Hint::default(),
            &mut |s| {
                spans.push(s);
                true
            },
        );
    }

    /// The eye ray of weight `w` along the spans of its segment in the opal (`spans`, the
    /// segment ending at `t_end` on `boundary`): each domain's lines crossed, the body's light
    /// seen where the potch or haze scatters, which dims the ray. Its weight after them, or
    /// `None` once that falls under [`MIN_WEIGHT`].
    fn spans_eye(
        &mut self,
        ray: &Ray,
        t_end: f32,
        boundary: Boundary,
        mut w: f32,
        sums: &mut Sums,
    ) -> Option<f32> {
        let potch = self.stone.potch;
        // The body's scattering thickness from each span to the segment's end, and
        // what lies beyond it: the body there is a layer of that thickness.
        let ground = ground_of(self.stone, boundary);
        let light_beyond = self.light_beyond(ray.at(t_end), boundary);
        let mut beyond: f32 = self.spans.iter().map(|s| self.km_scattering(s)).sum();
        // The body's single scattering of the light reaching it unscattered, beside the
        // layer's diffuse light; `tau` the optical depth of the potch passed so far.
        let single = self.single(ray, t_end, w);
        let mut tau = 0.0f32;
        for k in 0..self.spans.len() {
            let span = self.spans[k];
            let layer = beyond;
            beyond -= self.km_scattering(&span);
            let sigma = match span.domain {
                None => potch.extinction_per_mm,
                Some(domain) => {
                    self.cross(ray, span, domain, w, sums);
                    potch.domain_scattering_per_mm
                }
            };
            if sigma > 0.0 {
                let depth = sigma * (span.t1 - span.t0);
                let kept = (-depth).exp();
                // What the single scattering below shows of a lamp's once scattered light
                // in this span: `sech(d/2)` of it (nothing to take without a lamp's beam).
                let once = match (self.beam, single, span.domain) {
                    (Some(_), Some(_), None) => 1.0 / (0.5 * depth).cosh(),
                    _ => 0.0,
                };
                let light =
                    self.layer_light(ray.at(span.t0), span, layer, ground, light_beyond, once);
                self.body(w * (1.0 - kept), light, sums);
                if let (Some(single), None) = (single, span.domain) {
                    // Read at the span's optical middle: `sech(d/2)` times the integral of
                    // the dimmed light over the span, which fades the term in a thick span,
                    // where the layer (calibrated to the tone) holds the body's scattering
                    // of the light already (`single.rs`).
                    let scattered = w * (1.0 - kept) * potch.albedo;
                    let v = scattered * single.at(tau + 0.5 * depth);
                    self.add_notched_white(f64::from(v), sums);
                    tau += depth;
                }
                w *= kept;
            }
            if w < MIN_WEIGHT {
                return None;
            }
        }
        Some(w)
    }

    /// The eye ray of weight `w` along `dir` in `region` meeting `boundary` at `at`: at the
    /// surface it sees the light through it (notched by the lines it crossed) and goes on
    /// reflected; at a triplet's cap plane it goes on refracted or reflected; a backing ends it
    /// with the backing's light (`None`). Where it goes on: `(pos, dir, region, w)`.
    fn boundary_eye(
        &mut self,
        at: Vec3,
        dir: Vec3,
        region: Region,
        boundary: Boundary,
        w: f32,
        sums: &mut Sums,
    ) -> Option<(Vec3, Vec3, Region, f32)> {
        let stone = self.stone;
        match boundary {
            Boundary::Surface => {
                let n = stone.index_of(region);
                let normal = stone.shape.normal(at);
                let f = fresnel_dielectric(dir.dot(normal), n, 1.0);
                if let Some(out) = refract(dir, normal, n, 1.0) {
                    let v = w * (1.0 - f) * n * n * self.seen_sharp(at, out);
                    self.add_notched_white(f64::from(v), sums);
                }
                Some((
                    at - normal * EPSILON_MM,
                    reflect(dir, normal),
                    region,
                    w * f,
                ))
            }
            Boundary::Back => {
                self.backing(w, at, sums);
                None
            }
            Boundary::CapPlane => Some(self.cap_plane(at, dir, region, w)),
        }
    }
}

/// What dims a ray on its way out ([`Tracer::escape`]).
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Dim {
    /// Nothing: the surface alone.
    None,
    /// The light from the potch under a colour bar: the potch under the bar (its chord,
    /// whose light is the body's own; the potch of the bar's voids, a white grain, passes
    /// it on), and after the first surface event the domains' haze (it scatters what the
    /// dome sent back along the bar near where it left; on the first way up a milky domain
    /// sends on most of what it scatters).
    Potch,
    /// The potch and the domains' haze.
    PotchAndHaze,
    /// The potch under a colour bar alone (its chord, without a walk).
    Bar,
    /// The potch without a walk: its chord under a colour bar, and `share` of the rest of
    /// each segment in the opal (the share of potch the eye ray found where it looked).
    Body { share: f32 },
}

/// The tables of light inside the stone a tracer reads (none while they are being made).
#[derive(Clone, Copy, Default)]
pub(super) struct Lit<'a> {
    /// The light reaching the backing.
    pub backing: Option<&'a BackingLight>,
    /// The light reaching the potch under a colour bar.
    pub potch: Option<&'a PotchLight>,
}

/// A line of the crossing at hand, as [`Tracer::cross`] found it: its colour `(XYZ, S)`
/// and its notch on the light going on.
#[derive(Clone, Copy)]
struct CrossedLine {
    xyz: [f64; 3],
    s: f64,
    notch: Band,
}

/// A reflection leaving a domain: its face, its direction, the domain (the reflected ray
/// leaves it through that face), the cells likely to hold the face and the reflected line's
/// band (what the lines on the way are read against).
struct Out {
    face: Vec3,
    dir: Vec3,
    domain: u32,
    hint: Hint,
    band: Band,
}

/// Where the eye ray entered the stone.
#[derive(Clone, Copy)]
struct Entry {
    /// The surface's outward normal there.
    normal: Vec3,
    /// The surface's Fresnel reflectance at normal incidence.
    fresnel_normal: f32,
}

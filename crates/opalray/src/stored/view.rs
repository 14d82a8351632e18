//! The stored method's view pass (the paper's second pass, eq. (2), on the stone model): each
//! camera ray refracted into the stone and walked through it, gathering the stored light's
//! single reflection by every domain it crosses and its single scattering by the potch.
//!
//! Input: a [`Stone`], its [`StoredLight`] and a [`StoredSetup`] → output: XYZ and the binned
//! spectrum per pixel. Per camera ray:
//!
//! - **Surface**: the gloss (Fresnel F) shows the backdrop and the light's disc; `(1 − F)/n²`
//!   of the radiance refracts in.
//! - **Domain crossing**, for every line the ray meets ([`Stone::lines`]): the half vector h
//!   between the way back to the eye and the stored light's direction, the line at cos θ_h
//!   ([`Stone::line_at`]), the lobe's density D(h) ([`Stone::lobe_density`]):
//!   `L = w · π E R(λ, θ_h) D(h) / (4 cos θ_h)`, w the eye path's weight (Fresnel, potch and
//!   haze so far), E the stored irradiance; its spectrum is R times the `1 − R` notches of
//!   the lines crossed before on the eye path and on the light's way in (the reflecting
//!   domain's own excepted), integrated by a fixed quadrature
//!   ([`SpectralSampler::integrate`]). The ray goes on through the planes.
//! - **Potch** (and a milky domain's haze): `∫ σ_s e^{−τ} π E p(cos) dt` with the
//!   Henyey–Greenstein phase p, by sub-segments of a cell's length, the stored light at each
//!   one's middle; white (the notches are left out, as the path tracer leaves them out of
//!   paths without a reflection).
//! - **Exit**: through the far surface the backdrop, `(1 − F) n²`; on a backing, the stored
//!   light's Lambertian reflection.
//!
//! Left out: every path with two or more scattering events (reflections of reflections,
//! internal reflections at the surface, multiple scattering in the potch).

use std::f32::consts::PI;

use glam::Vec3;

use super::light::{Scratch, StoredLight};
use super::lines::Lines;
use super::StoredSetup;
use crate::geometry::{fresnel_dielectric, reflect, refract, Ray};
use crate::optics::BraggLine;
use crate::scatter::{Phase, Scatter};
use crate::scene::Backing;
use crate::stone::{ActiveLine, Boundary, Hint, Region, Span, Stone};

/// Offset of a point past a domain's face, mm (0.1 µm).
const EPSILON_MM: f32 = 1e-4;
/// The lobe is cut at this many standard deviations (past it lie 1.1 % of its light and 44 %
/// of the half vectors that meet it) and renormalised to hold all its light.
const LOBE_SIGMAS: f32 = 3.0;
/// Optical depth along the eye path past which nothing more is gathered (e⁻¹² ≈ 6·10⁻⁶).
const MAX_OPTICAL_DEPTH: f32 = 12.0;

/// What one pixel's samples add up to.
pub(super) struct Sums<'b> {
    /// Radiance of the light's white (its spectrum, luminance 1) added.
    pub white: f64,
    /// XYZ of the rest.
    pub xyz: [f64; 3],
    /// Bins of the rest.
    pub bins: &'b mut [f32],
}

/// One thread's eye paths.
pub(super) struct Gather<'a> {
    stone: &'a Stone,
    light: &'a StoredLight,
    setup: &'a StoredSetup<'a>,
    spans: Vec<Span>,
    lines: Vec<ActiveLine>,
    /// The lines crossed so far on the eye path, with their windows.
    eye_notches: Vec<(BraggLine, (f64, f64))>,
    light_notches: Vec<BraggLine>,
    scratch: Scratch,
    /// The pixel's reflections so far, one per line of a domain.
    pending: Vec<Pending>,
    /// Their notches.
    pending_notches: Vec<BraggLine>,
}

/// The reflections of one family's line of one domain met by a pixel's camera rays: one
/// quadrature at the weighted mean of their half-vector angles (within a pixel they differ by
/// under 10⁻³, the line's centre by well under its width).
struct Pending {
    domain: u32,
    line: ActiveLine,
    /// Σ value.
    value: f64,
    /// Σ value · cos θ_h.
    value_cos: f64,
    /// The first one's notches in `pending_notches`.
    notches: std::ops::Range<usize>,
}

/// What scatters the stored light towards the eye along a span: the potch, or the haze
/// within a domain.
#[derive(Clone, Copy, Debug)]
struct Medium {
    /// Scattering density, per mm (the extinction too).
    scattering_per_mm: f32,
    /// Share of what is scattered that survives.
    albedo: f32,
}

impl<'a> Gather<'a> {
    pub(super) fn new(stone: &'a Stone, light: &'a StoredLight, setup: &'a StoredSetup) -> Self {
        Gather {
            stone,
            light,
            setup,
            spans: Vec::with_capacity(64),
            lines: Vec::with_capacity(16),
            eye_notches: Vec::with_capacity(64),
            light_notches: Vec::with_capacity(32),
            scratch: Scratch::default(),
            pending: Vec::with_capacity(16),
            pending_notches: Vec::with_capacity(64),
        }
    }

    /// One camera ray.
    pub(super) fn sample(&mut self, ray: Ray, sums: &mut Sums) {
        let stone = self.stone;
        let env = self.setup.environment;
        let Some((t0, _)) = stone.shape.intersect(&ray).filter(|&(t0, _)| t0 > 0.0) else {
            sums.white += f64::from(env.value(ray.direction));
            return;
        };
        // The surface: gloss, and the refracted part goes in.
        let p = ray.at(t0);
        let normal = stone.shape.normal(p);
        let n = stone.n_eff;
        let fresnel = fresnel_dielectric(-ray.direction.dot(normal), 1.0, n);
        let mirror = reflect(ray.direction, normal);
        let gloss = fresnel * self.setup.gloss * (env.value(mirror) + self.disc(mirror));
        sums.white += f64::from(gloss);
        let Some(dir) = refract(ray.direction, normal, 1.0, n) else {
            return;
        };
        self.inside(p, dir, (1.0 - fresnel) / (n * n), sums);
    }

    /// The light's disc seen along `dir` from outside, in image units.
    fn disc(&self, dir: Vec3) -> f32 {
        self.setup.light.disc(dir)
    }

    /// The refracted camera ray from `p` along `dir` with weight `weight`, to where it leaves.
    fn inside(&mut self, p: Vec3, dir: Vec3, weight: f32, sums: &mut Sums) {
        let stone = self.stone;
        let potch = stone.potch;
        let ray = Ray {
            origin: p,
            direction: dir,
        };
        let Some((t_end, boundary)) = stone.exit(&ray, Region::Opal) else {
            return;
        };
        let mut spans = std::mem::take(&mut self.spans);
        spans.clear();
        stone.walk(p, dir, 0.0, t_end, Hint::default(), &mut |s| {
            spans.push(s);
            true
        });
        self.eye_notches.clear();
        let mut tau = 0.0f32;
        for span in &spans {
            if tau > MAX_OPTICAL_DEPTH {
                break;
            }
            let chord = span.t1 - span.t0;
            match span.domain {
                None => {
                    let sigma = potch.extinction_per_mm;
                    let medium = Medium {
                        scattering_per_mm: sigma,
                        albedo: potch.albedo,
                    };
                    self.scatter(&ray, span, medium, tau, weight, sums);
                    tau += sigma * chord;
                }
                Some(domain) => {
                    let haze = potch.domain_scattering_per_mm;
                    if haze > 0.0 {
                        let medium = Medium {
                            scattering_per_mm: haze,
                            albedo: 1.0,
                        };
                        self.scatter(&ray, span, medium, tau, weight, sums);
                    }
                    self.cross(&ray, span.t0, chord, domain, weight * (-tau).exp());
                    tau += haze * chord;
                }
            }
        }
        self.spans = spans;
        if tau > MAX_OPTICAL_DEPTH {
            return;
        }
        let weight = weight * (-tau).exp();
        let exit = ray.at(t_end);
        match boundary {
            Boundary::Surface => {
                // Through the far surface: the backdrop.
                let n = stone.n_eff;
                let normal = stone.shape.normal(exit);
                let f = fresnel_dielectric(dir.dot(normal).max(0.0), n, 1.0);
                if let Some(out) = refract(dir, normal, n, 1.0) {
                    let v = self.setup.environment.value(out);
                    sums.white += f64::from(weight * (1.0 - f) * n * n * v);
                }
            }
            Boundary::Back => self.backing(exit + Vec3::Z * EPSILON_MM, weight, sums),
            // A triplet's cap: refused by the scene's validation.
            Boundary::CapPlane => {}
        }
    }

    /// Single scattering of the stored light over `span` of `ray` by `medium`, the eye
    /// path's optical depth `tau` at its start.
    fn scatter(
        &mut self,
        ray: &Ray,
        span: &Span,
        medium: Medium,
        mut tau: f32,
        weight: f32,
        sums: &mut Sums,
    ) {
        let Medium {
            scattering_per_mm: sigma,
            albedo,
        } = medium;
        let cell = self.setup.cell_mm as f32;
        let steps = ((span.t1 - span.t0) / cell).ceil().max(1.0);
        let step = (span.t1 - span.t0) / steps;
        let g = self.stone.potch.anisotropy;
        for k in 0..steps as usize {
            if tau > MAX_OPTICAL_DEPTH {
                return;
            }
            let x = ray.at(span.t0 + (k as f32 + 0.5) * step);
            let depth = sigma * step;
            if let Some(a) = self.light.at(self.stone, x, &mut self.scratch, None) {
                // The share scattered in this piece, e^−τ (1 − e^−σΔ), of which `albedo`
                // survives; π E p: light along −to_light turned into −dir.
                let share = (-tau).exp() * (1.0 - (-depth).exp()) * albedo;
                let law = Phase {
                    incoming: ray.direction,
                    g,
                };
                let phase = law.eval(a.to_light);
                sums.white += f64::from(weight * share * PI * a.irradiance * phase);
            }
            tau += depth;
        }
    }

    /// The stored light's single reflection at the crossing of `domain` at `t0` (over
    /// `chord`) by `ray`, with the eye path's weight `weight`; the ray's lines join the eye
    /// path's notches.
    fn cross(&mut self, ray: &Ray, t0: f32, chord: f32, domain: u32, weight: f32) {
        let stone = self.stone;
        let dir = ray.direction;
        self.lines.clear();
        stone.lines(domain, dir, chord, &mut self.lines);
        if self.lines.is_empty() {
            return;
        }
        let x = ray.at(t0 + EPSILON_MM);
        if let Some(a) = self.light.at(stone, x, &mut self.scratch, None) {
            let to_eye = -dir;
            let h = (a.to_light + to_eye).normalize_or_zero();
            let cos_h = h.dot(to_eye);
            if cos_h > 0.0 {
                self.reflect_light(x, domain, h, cos_h, weight * a.irradiance);
            }
        }
        for l in &self.lines {
            self.eye_notches.push((l.line, l.line.window_nm()));
        }
    }

    /// Every line of `self.lines` whose lobe holds `h`: `weight_e · π R D(h) / (4 cos θ_h)`,
    /// `weight_e` the eye path's weight times the stored irradiance at `x`, joins the pixel's
    /// pending reflection of its line ([`Gather::finish_pixel`] integrates it).
    fn reflect_light(&mut self, x: Vec3, domain: u32, h: Vec3, cos_h: f32, weight_e: f32) {
        let stone = self.stone;
        let mut fetched = false;
        let renormalise = 1.0 / (1.0 - (-0.5 * LOBE_SIGMAS * LOBE_SIGMAS).exp());
        for line in &self.lines {
            let density = stone.lobe_density_within(line, h, cos_h, LOBE_SIGMAS) * renormalise;
            if density <= 0.0 {
                continue;
            }
            if !fetched {
                // The notches on the light's way in, but the reflecting domain's own.
                fetched = true;
                let notches = &mut self.light_notches;
                notches.clear();
                self.light.at(
                    stone,
                    x,
                    &mut self.scratch,
                    Some(&mut |n| {
                        if n.domain != domain {
                            notches.push(n.line());
                        }
                    }),
                );
            }
            let value = f64::from(weight_e * PI * density / (4.0 * cos_h));
            if let Some(p) = self.pending.iter_mut().find(|p| {
                p.domain == domain && p.line.kind == line.kind && p.line.normal == line.normal
            }) {
                p.value += value;
                p.value_cos += value * f64::from(cos_h);
                continue;
            }
            // The notches that reach into the reflected line's window.
            let (lo, hi) = stone.line_at(domain, line, cos_h).window_nm();
            let first = self.pending_notches.len();
            for &(notch, (a, z)) in &self.eye_notches {
                if z > lo && a < hi {
                    self.pending_notches.push(notch);
                }
            }
            for notch in &self.light_notches {
                let (a, z) = notch.window_nm();
                if z > lo && a < hi {
                    self.pending_notches.push(*notch);
                }
            }
            self.pending.push(Pending {
                domain,
                line: *line,
                value,
                value_cos: value * f64::from(cos_h),
                notches: first..self.pending_notches.len(),
            });
        }
    }

    /// Integrate the pixel's reflections into `sums` and start the next pixel.
    pub(super) fn finish_pixel(&mut self, sums: &mut Sums) {
        for p in &self.pending {
            let cos_h = (p.value_cos / p.value) as f32;
            let reflected = self.stone.line_at(p.domain, &p.line, cos_h);
            let mut lines = Lines::default();
            lines.reflect(reflected);
            for notch in &self.pending_notches[p.notches.clone()] {
                lines.transmit(*notch);
            }
            self.setup
                .spectral
                .integrate(&lines, p.value, &mut sums.xyz, sums.bins);
        }
        self.pending.clear();
        self.pending_notches.clear();
    }

    /// The stored light's Lambertian reflection by the backing at `x` (facing +z).
    fn backing(&mut self, x: Vec3, weight: f32, sums: &mut Sums) {
        let Some(back) = self.stone.back else {
            return;
        };
        let Some(a) = self.light.at(self.stone, x, &mut self.scratch, None) else {
            return;
        };
        let cos = a.to_light.z;
        if cos <= 0.0 {
            return;
        }
        // π × ρ E cos / π.
        let value = weight * a.irradiance * cos;
        match back.kind {
            Backing::Ironstone => {
                let mut lines = Lines::default();
                lines.tint();
                self.setup
                    .spectral
                    .integrate(&lines, f64::from(value), &mut sums.xyz, sums.bins);
            }
            _ => sums.white += f64::from(value) * back.reflectance(550.0),
        }
    }
}

//! What lights the body and a backing as the eye ray sees them: the body as a lit layer, the
//! backing under the light that reaches it through the stone, and a point light's share.

use super::*;

impl Tracer<'_> {
    /// The body seen by the share `w` of the eye ray scattered in it, sending back `light`:
    /// its layer's reflectance ([`BodyLayer::of`], the tone's Munsell value when thick)
    /// times the irradiance that lights it, plus its transmittance times the irradiance
    /// beyond (the chip's reflectance includes the surface's `1 − F₀` on the way in, which
    /// the eye ray's weight holds already).
    pub(super) fn body(&mut self, w: f32, light: f32, sums: &mut Sums) {
        let v = w * self.body_radiance(light);
        self.add_notched_white(f64::from(v), sums);
    }

    /// The irradiance (outside, `Ē`) that lights the body where the eye ray meets it at `at`
    /// over `span`, and the share of the body's own diffuse light that comes back to it
    /// from above: under a colour bar — the potch there, or a milky domain's haze over it,
    /// whose light is the potch's glow below — the light reaching the potch's top through
    /// the bar and the bar's and dome's return ([`PotchLight`]); elsewhere the room's and the
    /// lamp's at the surface the eye ray entered, and a polished surface's `r_i`.
    ///
    /// Where a point or directional light's beam lights the body as a layer
    /// ([`Tracer::beam`]), its part is left out here (`true` beside): not under a bar.
    fn light_on_body(&self, at: Vec3, span: Span) -> (f32, f32, bool) {
        if let Some(potch) = self.lit.potch {
            let under = match span.domain {
                None => potch.holds(at),
                Some(_) => true,
            };
            if let Some(top) = potch.returned_at(at).filter(|_| under) {
                return (potch.at(at), top, false);
            }
        }
        let top = self.layer.r_inside();
        match self.beam {
            Some(_) => (self.irradiance.at(self.entry.normal), top, true),
            None => (self.irradiance_on(self.entry.normal), top, false),
        }
    }

    /// The light the body sends back where a ray meets it at `at` over `span`, as a layer
    /// of scattering thickness `layer` down to `ground` (`light_beyond` lighting it from
    /// there), in the units of [`Tracer::body`]: the diffuse layer under the room's light
    /// ([`BodyLayer::of`]) and a lamp's beam through the same layer
    /// ([`BodyLayer::collimated`]), less `once` of the beam's once scattered light.
    pub(super) fn layer_light(
        &self,
        at: Vec3,
        span: Span,
        layer: f32,
        ground: Option<f32>,
        light_beyond: f32,
        once: f32,
    ) -> f32 {
        let (lit, top, apart) = self.light_on_body(at, span);
        let (r, t) = self.layer.of(layer, ground, top);
        let mut light = r * lit + t * light_beyond;
        if let Some(beam) = self.beam.filter(|_| apart) {
            let depth = self.layer.potch_depth(layer);
            let back = ground.unwrap_or(beam.back);
            light += beam.irradiance
                * self
                    .layer
                    .collimated(depth, beam.mu, ground, back, top, once);
        }
        light
    }

    /// The point or directional light's beam into the body where the camera ray entered
    /// (`None` without such a light, or where it is below that surface's horizon).
    pub(super) fn beam_at_entry(&self) -> Option<Beam> {
        self.setup.light?;
        let (to_light, e) = self.body_light?;
        let normal = self.entry.normal;
        let cos = normal.dot(to_light);
        if cos <= 0.0 || e <= 0.0 {
            return None;
        }
        let n = self.stone.n_eff;
        let sin = (1.0 - cos * cos).max(0.0).sqrt() / n;
        let mu = (1.0 - sin * sin).max(0.0).sqrt();
        Some(Beam {
            irradiance: e * cos * (1.0 - fresnel_dielectric(cos, 1.0, n)),
            mu,
            back: fresnel_dielectric(mu, n, 1.0),
        })
    }

    /// The radiance in the stone of a body sending back `light` (its reflectance times the
    /// outside irradiance, as a chip at the surface the eye ray entered: its reflectance
    /// includes the surface's `1 − F₀` on the way in).
    pub(super) fn body_radiance(&self, light: f32) -> f32 {
        let n = self.stone.n_eff;
        n * n * light / (1.0 - self.entry.fresnel_normal)
    }

    /// The irradiance outside the surface where a segment inside ends at `at` on
    /// `boundary`: what comes into the body from beyond it (0 at a backing or the cap).
    pub(super) fn light_beyond(&self, at: Vec3, boundary: Boundary) -> f32 {
        match boundary {
            Boundary::Surface => self.irradiance_on(self.stone.shape.normal(at)),
            Boundary::Back | Boundary::CapPlane => 0.0,
        }
    }

    /// The backing seen at `at` by the eye ray with weight `w`: its reflectance under the
    /// light that reaches it through the stone ([`BackingLight`]).
    pub(super) fn backing(&mut self, w: f32, at: Vec3, sums: &mut Sums) {
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
    pub(in crate::lobe) fn light_on_backing(&mut self, at: Vec3) -> f32 {
        self.light_on(
            at + Vec3::Z * EPSILON_MM,
            Vec3::Z,
            BACK_DIRECTIONS,
            Dim::PotchAndHaze,
        )
    }

    /// [`Tracer::light_on_backing`] at `at`, inside the stone, on a surface of unit normal
    /// `normal` (`directions` of them, cosine-distributed about it), dimmed as `dim` says.
    pub(in crate::lobe) fn light_on(
        &mut self,
        at: Vec3,
        normal: Vec3,
        directions: usize,
        dim: Dim,
    ) -> f32 {
        self.light_and_return_on(at, normal, directions, dim).0
    }

    /// [`Tracer::light_on`], and the share of a diffuse light leaving the surface at `at`
    /// (cosine-distributed about `normal`) that the dimming takes on its way out: for the
    /// potch under a colour bar ([`Dim::Potch`]), the share of its own light that the bar and
    /// the dome send back into it, `1 − (1 − F̄)/n²` under a flat surface.
    pub(in crate::lobe) fn light_and_return_on(
        &mut self,
        at: Vec3,
        normal: Vec3,
        directions: usize,
        dim: Dim,
    ) -> (f32, f32) {
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
        let (mut sum, mut returned) = (0.0, 0.0);
        for k in 0..directions {
            let r = ((k as f32 + 0.5) / count).sqrt();
            let phi = golden * k as f32;
            let dir = (t * (r * phi.cos()) + b * (r * phi.sin()))
                + normal * (1.0 - r * r).max(0.0).sqrt();
            let ray = Ray {
                origin: at,
                direction: dir,
            };
            let region = self.stone.region_at(at);
            let (seen, taken) = self.escape(&ray, region, sigma, dim, start, MIN_WEIGHT);
            sum += seen;
            returned += taken;
        }
        (
            sum / count + self.point_light_on(at, normal),
            returned / count,
        )
    }

    /// The point or directional light's irradiance at `x` inside the stone along its
    /// refracted path, dimmed by the potch and haze on the way (its lines' notches left
    /// out), as the radiance a white Lambertian surface of unit normal `normal` sends back.
    pub(super) fn point_light_on(&mut self, x: Vec3, normal: Vec3) -> f32 {
        self.point_light_reaching(x)
            .map_or(0.0, |(to_light, e)| e * to_light.dot(normal).max(0.0))
    }

    /// The point or directional light at `x` inside the stone: the direction towards it
    /// along its refracted path, and its irradiance there on a plane facing it (its
    /// intensity applied), dimmed by the potch and haze on the way (its lines' notches left
    /// out). `None` without such a light or where it does not reach `x`.
    pub(super) fn point_light_reaching(&mut self, x: Vec3) -> Option<(Vec3, f32)> {
        let light = self.setup.light?;
        let stone = self.stone;
        let (to_light, irradiance, distance) = stone.light_entry(&light.source, x)?;
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
        Some((to_light, light.intensity * irradiance * kept))
    }

    /// The scene's point or directional light reflected by `line` of `domain` at `x` towards
    /// the eye ray along `dir`, with weight `w`: `π E R(λ, θ_h) D(h) / (4 cos θ_h)`.
    pub(super) fn light_at(
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
}

impl Tracer<'_> {
    /// Kubelka–Munk scattering thickness `S X` of `span`: `S = ¾ σ_s (1 − g)` of the potch
    /// (σ_s its extinction times its albedo) or of a milky domain's haze.
    pub(super) fn km_scattering(&self, span: &Span) -> f32 {
        let potch = &self.stone.potch;
        let sigma_s = match span.domain {
            None => potch.extinction_per_mm * potch.albedo,
            Some(_) => potch.domain_scattering_per_mm,
        };
        0.75 * sigma_s * (1.0 - potch.anisotropy) * (span.t1 - span.t0)
    }
}

/// What lies beyond a segment in the opal that ends at `boundary`: a backing in contact
/// (its reflectance at 550 nm), or `None`, a polished surface ([`BodyLayer::of`]).
pub(super) fn ground_of(stone: &Stone, boundary: Boundary) -> Option<f32> {
    match (boundary, stone.back) {
        (Boundary::Back, Some(back)) => Some(back.reflectance(550.0) as f32),
        _ => None,
    }
}

/// A point or directional light's beam into the body ([`Tracer::beam_at_entry`]): the
/// irradiance that went in through the surface (on the surface's plane), the cosine of its
/// refracted direction to the surface's normal, and what a polished back parallel to the
/// surface reflects of it.
#[derive(Clone, Copy)]
pub(super) struct Beam {
    pub irradiance: f32,
    pub mu: f32,
    pub back: f32,
}

//! The body's single scattering of the light that reaches it unscattered ([`Single`]): the
//! softbox seen through the dome, the light through a clear stone from beyond. The body's
//! layer ([`BodyLayer`]) answers a diffuse irradiance with a Lambertian chip's light; a thin
//! span of potch (a void in a colour bar, a clear body) sends the eye what it scatters of
//! the light arriving from every direction, weighted by its phase function.

use super::*;
use crate::scatter::{hg_cos, hg_phase};

/// Directions of the quadrature of the light a point of the body scatters towards the eye:
/// drawn from the potch's Henyey–Greenstein phase function about the eye ray (stratified in
/// its cosine, a golden-angle spiral about the ray). With 20 or 32, the ΔE₀₀ medians of
/// five gem presets against the path tracer at 160 × 120 move by up to 0.04 and 0.07
/// (docs/model.md, "The body's single scattering").
const SINGLE_DIRECTIONS: usize = 24;

/// The light a segment of the eye ray's body scatters towards the eye, once per segment:
/// `light` at the median depth of its first scattering, `tau` (its optical depth from the
/// segment's first span of potch), in the stone's radiance per unit of the scattered share.
#[derive(Clone, Copy)]
pub(super) struct Single {
    light: f32,
    tau: f32,
}

impl Single {
    /// The light at optical depth `tau` into the segment's potch: the light at the median
    /// depth, dimmed (or, above it, brightened) as the eye ray is between the two (the
    /// light a point scatters to the eye mostly came down the way the eye looks up).
    pub(super) fn at(&self, tau: f32) -> f32 {
        self.light * (self.tau - tau).exp()
    }
}

impl Tracer<'_> {
    /// The single scattering of the eye ray's segment along `ray` (its spans in `spans`, the
    /// segment ending at `t_end`), `None` where it has no potch or the eye ray's weight `w`
    /// could not make it show ([`CUT`]). The point is the median depth of the eye ray's
    /// first scattering in the segment's potch, `τ_m = −ln((1 + e^{−τ})/2)` (at most ln 2);
    /// each quadrature direction is followed out of the stone ([`Tracer::escape`], internal
    /// reflections with their Fresnel weights), dimmed by the potch on its way
    /// ([`Dim::Body`]: the chord under a colour bar, elsewhere the share of potch the eye
    /// ray found on this segment), and reads the environment through a lobe of the
    /// quadrature's spacing; a point or directional light adds its phase-weighted
    /// irradiance along its refracted path.
    pub(super) fn single(&mut self, ray: &Ray, t_end: f32, w: f32) -> Option<Single> {
        let potch = self.stone.potch;
        let extinction = potch.extinction_per_mm;
        if potch.albedo <= 0.0 || extinction <= 0.0 {
            return None;
        }
        let (chord, share) = self.potch_on_segment(ray, t_end);
        let tau = extinction * chord;
        // A bound on what the segment's spans add: the light above the median depth is
        // brightened by up to e^{τ_m} ≤ 2 ([`Single::at`]); a lamp's phase is at most
        // HG's forward peak for |g|.
        let g = potch.anisotropy;
        let lamp = self.body_light.map_or(0.0, |(_, e)| e) * PI * hg_phase(g.abs(), 1.0);
        // Past this the light is followed only while it could still reach the cut for a
        // ray of any weight and depth (`w (1 − e^{−τ})` at most 1): the light found is then
        // the same for every ray of a pixel, which its further rays read back.
        let most = 2.0 * potch.albedo * (self.peak + lamp);
        if tau <= 0.0 || w * (1.0 - (-tau).exp()) * most < CUT {
            return None;
        }
        let tau_m = -((1.0 + (-tau).exp()) * 0.5).ln();
        // A pixel's rays on the same segment: what the first found there (`reuse.rs`).
        let reusable = self.reuse.on();
        if let Some(light) = reusable
            .then(|| self.reuse.find_single(self.segment, ray.direction))
            .flatten()
        {
            return Some(Single { light, tau: tau_m });
        }
        let at = self.at_depth(ray, tau_m / extinction);
        let dim = Dim::Body { share };
        let count = SINGLE_DIRECTIONS as f32;
        let sigma = 0.5 * (PI / count).sqrt();
        let golden = PI * (3.0 - 5f32.sqrt());
        let d = ray.direction;
        let (t, b) = d.any_orthonormal_pair();
        let mut sum = 0.0;
        for k in 0..SINGLE_DIRECTIONS {
            let cos = hg_cos(f64::from(g), (k as f64 + 0.5) / f64::from(count)) as f32;
            let sin = (1.0 - cos * cos).max(0.0).sqrt();
            let phi = golden * k as f32;
            let u = d * cos + (t * phi.cos() + b * phi.sin()) * sin;
            // Followed while what is left of it could still reach the cut.
            let ray = Ray {
                origin: at,
                direction: u,
            };
            let hint = Hint::default();
            sum += self
                .escape(&ray, Region::Opal, sigma, dim, hint, CUT / most)
                .0;
        }
        let light = sum / count + self.point_light_scattered(at, d);
        if reusable {
            self.reuse.keep_single(self.segment, ray.direction, light);
        }
        Some(Single { light, tau: tau_m })
    }

    /// The point on the eye ray's segment `depth` mm into its potch (its spans' order).
    fn at_depth(&self, ray: &Ray, depth: f32) -> Vec3 {
        let mut left = depth;
        let mut t = 0.0;
        for s in self.spans.iter().filter(|s| s.domain.is_none()) {
            t = s.t0 + left;
            if left <= s.t1 - s.t0 {
                break;
            }
            left -= s.t1 - s.t0;
            t = s.t1;
        }
        ray.at(t)
    }

    /// The point or directional light scattered at `x` towards the eye ray along `dir`, in
    /// the stone's radiance per unit scattered: `π p(cos) E`, `E` its irradiance there on a
    /// plane facing it, dimmed by the potch and haze on its refracted path.
    fn point_light_scattered(&mut self, x: Vec3, dir: Vec3) -> f32 {
        let g = self.stone.potch.anisotropy;
        self.point_light_reaching(x)
            .map_or(0.0, |(to_light, e)| PI * hg_phase(g, to_light.dot(dir)) * e)
    }
}

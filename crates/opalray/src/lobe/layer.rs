//! The body as a layer of the stone's own thickness ([`BodyLayer`]): what a span of potch (or
//! a milky domain's haze) shows of the light above it and of the light that comes in from
//! beyond the segment's end, by the Kubelka–Munk two-flux model of the potch's *physical*
//! absorption and scattering, with the polished surfaces' internal reflection (Saunderson
//! 1942), scaled so that a thick layer shows the tone's Munsell value.
//!
//! Why the physical coefficients: a chip of the tone's value `R∞` read as a Kubelka–Munk
//! medium of scattering `S = ¾ σ_s (1 − g)` has `K = S (1 − R∞)²/(2 R∞)`; for the white
//! preset's N9 potch that is `K` = 0.16 mm⁻¹, where the potch absorbs `2 σ_a` = 0.024 mm⁻¹
//! (its albedo 0.9988 at 10 mm⁻¹): its light would reach 0.8 mm deep instead of the
//! medium's 2.1 mm. The tone's value is reached with the surface's internal reflection
//! (about 56 % of the diffuse light inside goes back in), not by a darker medium.

use super::potch::hemispherical_fresnel;
use crate::stone::Potch;

/// The body's layer: the potch's Kubelka–Munk ratio `K/S` and the surface's diffuse
/// reflectances; see the module.
#[derive(Clone, Copy, Debug)]
pub(crate) struct BodyLayer {
    /// `a = 1 + K/S` of the two-flux solution.
    a: f64,
    /// `b = √(a² − 1)`.
    b: f64,
    /// The share of the diffuse light inside that a polished surface reflects back in.
    r_inside: f64,
    /// The tone's value over the model's own thick-layer reflectance.
    scale: f64,
    /// The potch's Kubelka–Munk coefficients `K = 2σ_a` and `S = ¾σ_s(1 − g)`, per mm.
    k: f64,
    s: f64,
    /// Its physical scattering and extinction coefficients, per mm, and the share of a
    /// beam's scattering that Henyey–Greenstein sends back into the hemisphere it came from.
    sigma_s: f64,
    sigma_t: f64,
    back: f64,
}

impl BodyLayer {
    /// The layer of `potch` in a stone of index `n` whose thick body shows `tone_reflectance`
    /// (luminous, the gloss apart) under diffuse light.
    pub(crate) fn new(potch: &Potch, n: f32, tone_reflectance: f32) -> Self {
        let sigma_s = f64::from(potch.extinction_per_mm * potch.albedo);
        let sigma_a = f64::from(potch.extinction_per_mm * (1.0 - potch.albedo));
        let s = 0.75 * sigma_s * f64::from(1.0 - potch.anisotropy);
        // A lossless (or clear) body: K/S small but not 0, so that b stays positive.
        let ks = if s > 0.0 {
            (2.0 * sigma_a / s).max(1e-6)
        } else {
            1.0
        };
        let a = 1.0 + ks;
        let b = (a * a - 1.0).sqrt();
        let r_outside = f64::from(hemispherical_fresnel(n));
        // Diffuse light in and out of a smooth surface: (1 − r_o) = n² (1 − r_i).
        let r_inside = 1.0 - (1.0 - r_outside) / f64::from(n * n);
        let mut layer = BodyLayer {
            a,
            b,
            r_inside,
            scale: 1.0,
            k: ks * s,
            s,
            sigma_s,
            sigma_t: sigma_s + sigma_a,
            back: back_scattered(f64::from(potch.anisotropy)),
        };
        let thick = layer.seen(a - b, r_inside);
        layer.scale = f64::from(tone_reflectance) / thick.max(1e-9);
        layer
    }

    /// What a layer of scattering thickness `sx` (`S X`, [`super::trace`]'s `km_scattering`
    /// summed to the segment's end) shows, as `(R, T)`: its reflectance of the light above
    /// it, and its transmittance of the outside irradiance beyond (both seen from above
    /// through the surface, per unit irradiance, the tone's scale applied). `ground` is
    /// what lies beyond: `Some(r)` a backing of reflectance `r` in contact (nothing comes
    /// through), `None` a polished surface into the air (it reflects `r_inside` of the
    /// light back and lets the irradiance beyond in).
    ///
    /// `top` is the share of the body's own diffuse light that comes back to it from above:
    /// [`BodyLayer::r_inside`] under a polished surface, less under a colour bar whose dome
    /// carries part of it away to leave elsewhere ([`super::potch::PotchLight`]).
    pub(crate) fn of(&self, sx: f32, ground: Option<f32>, top: f32) -> (f32, f32) {
        let top = f64::from(top);
        let x = self.b * f64::from(sx.max(0.0));
        if x > 20.0 {
            return ((self.scale * self.seen(self.a - self.b, top)) as f32, 0.0);
        }
        // The layer alone, over black (Kubelka 1948): R = sinh / (a sinh + b cosh),
        // T = b / (a sinh + b cosh).
        let d = self.a * x.sinh() + self.b * x.cosh();
        let (r, t) = (x.sinh() / d, self.b / d);
        let rho = ground.map_or(self.r_inside, f64::from);
        // With the ground: light bounced between the layer and it.
        let bounce = 1.0 / (1.0 - r * rho);
        let r_ground = r + t * t * rho * bounce;
        let through = match ground {
            Some(_) => 0.0,
            // The irradiance beyond enters as `1 − r_o` does above; seen from above as the
            // layer's own reflection is (`seen` per unit of light that went in).
            None => t * bounce,
        };
        let reflected = self.scale * self.seen(r_ground, top);
        let transmitted = self.scale * self.seen(r_ground, top) * through / r_ground.max(1e-12);
        (reflected as f32, transmitted as f32)
    }

    /// What a layer `depth_mm` thick (of potch) shows of a collimated beam — a point or
    /// directional light — that went into it at `mu` (the cosine of its refracted direction
    /// to the layer's normal), per unit of light that went in, less `first` times the
    /// part of it scattered once (what [`super::trace`]'s single scattering shows exactly).
    ///
    /// Kubelka–Munk's two diffuse fluxes fed by the beam as it is dimmed (the three-flux
    /// model, Kubelka's collimated case): the beam scatters `σ_s/μ` per unit of depth, a
    /// share `B` of it into the upward flux (Henyey–Greenstein's backward hemisphere at
    /// normal incidence) and the rest into the downward one, and what reaches the back
    /// returns `beam_back` of itself (a polished back's Fresnel reflectance at the beam's
    /// angle, or a backing's reflectance). The polished top returns `top` of the upward
    /// flux and lets `1 − r_i` out; the back returns `ground`'s reflectance of the diffuse
    /// flux, or `r_i` where it is polished (`None`). Unlike the diffuse layer
    /// ([`BodyLayer::of`]) a thin body does not send the unscattered light back: a beam
    /// meets the polished back near normal incidence and 97 % of it goes out, where the
    /// diffuse `r_i` would return 56 %. What the back returns of the beam joins the upward
    /// diffuse flux (it is a mirror image of the lamp, not a glow: a small share). Against
    /// a Monte Carlo walk of a beam face-on into a slab with polished faces it is within
    /// 0.035 from a clear body to a white one (a test); the tone's scale, which the diffuse
    /// layer needs, is not applied: the tone is the walk's.
    pub(crate) fn collimated(
        &self,
        depth_mm: f32,
        mu: f32,
        ground: Option<f32>,
        beam_back: f32,
        top: f32,
        first: f32,
    ) -> f32 {
        let (k, s) = (self.k, self.s);
        if s <= 0.0 || depth_mm <= 0.0 {
            return 0.0;
        }
        let x = f64::from(depth_mm);
        let mu = f64::from(mu.clamp(0.05, 1.0));
        let (top, rho) = (f64::from(top), ground.map_or(self.r_inside, f64::from));
        // The beam: dimmed at `c`, feeding the downward flux `i` at `alpha` and the upward
        // flux `j` at `beta`, each `e^{−cz}`.
        let mut c = self.sigma_t / mu;
        let alpha = self.sigma_s * (1.0 - self.back) / mu;
        let beta = self.sigma_s * self.back / mu;
        let kappa = (k * (k + 2.0 * s)).sqrt();
        if (c - kappa).abs() < 1e-6 * c {
            c *= 1.0 + 1e-4;
        }
        let d = c * c - kappa * kappa;
        // The particular solution `(i, j) = (p, q) e^{−cz}`.
        let p = (-alpha * (k + s + c) - s * beta) / d;
        let q = (-beta * (k + s - c) - alpha * s) / d;
        // The free ones, `e^{κ(z − x)}` and `e^{−κz}`, with `j/i` of `u1` and `u2`.
        let (u1, u2) = ((kappa + k + s) / s, (-kappa + k + s) / s);
        let (e, g) = ((-kappa * x).exp(), (-c * x).exp());
        // The top returns `top` of `j`; the back `rho` of `i` and `beam_back` of the beam.
        let m = [
            [e * (1.0 - top * u1), 1.0 - top * u2],
            [u1 - rho, e * (u2 - rho)],
        ];
        let rhs = [top * q - p, (rho * p + f64::from(beam_back) - q) * g];
        let det = m[0][0] * m[1][1] - m[0][1] * m[1][0];
        if det.abs() < 1e-300 {
            return 0.0;
        }
        let d1 = (rhs[0] * m[1][1] - m[0][1] * rhs[1]) / det;
        let c2 = (m[0][0] * rhs[1] - rhs[0] * m[1][0]) / det;
        let up = q + u1 * d1 * e + u2 * c2;
        // Scattered once: the beam's upward share carried up, dimmed by the upward flux's
        // own `K + S`.
        let once = beta * (1.0 - (-(c + k + s) * x).exp()) / (c + k + s);
        ((1.0 - self.r_inside) * (up - f64::from(first) * once)).max(0.0) as f32
    }

    /// The depth of potch (mm) of a layer of scattering thickness `sx` (`S X`).
    pub(crate) fn potch_depth(&self, sx: f32) -> f32 {
        if self.s > 0.0 {
            (f64::from(sx) / self.s) as f32
        } else {
            0.0
        }
    }

    /// The share of the diffuse light inside that a polished surface reflects back in,
    /// `r_i = 1 − (1 − F̄)/n²`.
    pub(crate) fn r_inside(&self) -> f32 {
        self.r_inside as f32
    }

    /// The reflectance outside of a body whose diffuse reflectance inside is `r` (Saunderson
    /// 1942, the gloss apart): `(1 − r_o)(1 − r_i) r / (1 − r_i r)`, without the constant
    /// `1 − r_o`, which the scale takes. The light in enters as through a polished surface
    /// (`1 − r_i`: the light above is given as the irradiance outside that lights it as
    /// much); of the body's own light, `top` comes back to it from above (`r_i` under a
    /// polished surface).
    fn seen(&self, r: f64, top: f64) -> f64 {
        (1.0 - self.r_inside) * r / (1.0 - top * r)
    }
}

/// The share of a beam's Henyey–Greenstein scattering of anisotropy `g` that goes back into
/// the hemisphere it came from: `(1 − g)/(2g) · ((1 + g)/√(1 + g²) − 1)`, ½ at `g` = 0.
fn back_scattered(g: f64) -> f64 {
    if g.abs() < 1e-6 {
        return 0.5;
    }
    (1.0 - g) / (2.0 * g) * ((1.0 + g) / (1.0 + g * g).sqrt() - 1.0)
}

#[cfg(test)]
mod tests {
    use super::BodyLayer;
    use crate::geometry::fresnel_dielectric;
    use crate::sampling::{stage, Rng};
    use crate::stone::body::{hg_cos, munsell_y, potch_albedo};
    use crate::stone::Potch;

    /// The white preset's potch: 10 mm⁻¹, HG g = 0.4, N9 (Y 0.767), in silica of n_eff 1.442.
    const N: f32 = 1.442_26;
    const EXTINCTION: f64 = 10.0;
    const G: f64 = 0.4;

    /// A Monte Carlo walk through a slab `depth_mm` thick, both faces polished into the air:
    /// light entering face-on through the top, `(R, T)` the shares leaving through the top
    /// and the bottom (the top's `1 − F₀` on the way in included), each scattering weighing
    /// the albedo. The body module's calibration walk with a second face.
    fn slab_walk(depth_mm: f64, extinction: f64, albedo: f64, walks: usize) -> (f64, f64) {
        let mut rng = Rng::new(0, stage::STONE, 1 << 40);
        let (mut top, mut bottom) = (0.0, 0.0);
        for _ in 0..walks {
            let (mut z, mut mu, mut w) = (0.0f64, 1.0f64, 1.0f64);
            while w > 1e-6 {
                z += mu * -(1.0 - rng.uniform()).ln() / extinction;
                // The faces: escape by 1 − F, or the flight goes on mirrored.
                while !(0.0..=depth_mm).contains(&z) {
                    let f = f64::from(fresnel_dielectric(mu.abs() as f32, N, 1.0));
                    if rng.uniform() >= f {
                        *(if z < 0.0 { &mut top } else { &mut bottom }) += w;
                        w = 0.0;
                        break;
                    }
                    z = if z < 0.0 { -z } else { 2.0 * depth_mm - z };
                    mu = -mu;
                }
                w *= albedo;
                let cos = hg_cos(G, rng.uniform());
                let sin = (1.0 - cos * cos).max(0.0).sqrt();
                let phi = 2.0 * std::f64::consts::PI * rng.uniform();
                mu =
                    (mu * cos + (1.0 - mu * mu).max(0.0).sqrt() * sin * phi.cos()).clamp(-1.0, 1.0);
            }
        }
        let f0 = f64::from(fresnel_dielectric(1.0, 1.0, N));
        let scale = (1.0 - f0) / walks as f64;
        (top * scale, bottom * scale)
    }

    #[test]
    fn a_white_layer_reflects_and_lets_through_as_a_walk_through_the_slab_does() {
        let albedo = potch_albedo(9, G, f64::from(N));
        let potch = Potch {
            extinction_per_mm: EXTINCTION as f32,
            albedo,
            anisotropy: G as f32,
            domain_scattering_per_mm: 0.0,
        };
        let tone = 0.767;
        let layer = BodyLayer::new(&potch, N, tone);
        let s = 0.75 * EXTINCTION * f64::from(albedo) * (1.0 - G);
        // A slab 1 and 4 mm thick (the white preset's dome is 4 mm high at its centre), and
        // thick. The walks' standard error is under 0.006; Kubelka–Munk's two fluxes are an
        // approximation of the walk's angular transport, within 0.035 here.
        for depth in [1.0, 4.0, 40.0] {
            let (r_walk, t_walk) = slab_walk(depth, EXTINCTION, f64::from(albedo), 8000);
            let (r, t) = layer.of((s * depth) as f32, None, layer.r_inside());
            assert!(
                (f64::from(r) - r_walk).abs() < 0.035 && (f64::from(t) - t_walk).abs() < 0.035,
                "{depth} mm: layer R {r:.3} T {t:.3}, walk R {r_walk:.3} T {t_walk:.3}"
            );
        }
    }

    #[test]
    fn a_beam_into_a_layer_comes_back_as_a_walk_through_the_slab_brings_it() {
        // A beam face-on into a slab with polished faces: the collimated layer against the
        // walk, from a clear N5 body at 0.5 mm⁻¹ (whose diffuse layer, the tone's scale
        // applied, returns the unscattered light from the back: 0.25 for 1 mm where the walk
        // finds 0.11) to the white preset's.
        let f0 = f64::from(fresnel_dielectric(1.0, 1.0, N));
        let beam_back = fresnel_dielectric(1.0, N, 1.0);
        for (extinction, tone, depths) in [
            (0.5, 5u8, [1.0, 4.0, 10.0]),
            (EXTINCTION, 9u8, [1.0, 4.0, 40.0]),
        ] {
            let albedo = potch_albedo(tone, G, f64::from(N));
            let potch = Potch {
                extinction_per_mm: extinction as f32,
                albedo,
                anisotropy: G as f32,
                domain_scattering_per_mm: 0.0,
            };
            let layer = BodyLayer::new(&potch, N, munsell_y(f64::from(tone)) as f32);
            for depth in depths {
                let walks = if extinction < 1.0 { 20_000 } else { 4000 };
                let (r_walk, _) = slab_walk(depth, extinction, f64::from(albedo), walks);
                let r = (1.0 - f0)
                    * f64::from(layer.collimated(
                        depth as f32,
                        1.0,
                        None,
                        beam_back,
                        layer.r_inside(),
                        0.0,
                    ));
                let (diffuse, _) = layer.of(layer.s as f32 * depth as f32, None, layer.r_inside());
                eprintln!(
                    "{extinction} mm⁻¹, {depth} mm: beam {r:.4}, walk {r_walk:.4}, diffuse {diffuse:.4}"
                );
                assert!(
                    (r - r_walk).abs() < 0.035,
                    "{extinction} mm⁻¹, {depth} mm: beam {r:.4} walk {r_walk:.4}"
                );
            }
        }
    }
}

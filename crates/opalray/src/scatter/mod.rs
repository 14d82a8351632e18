//! What happens at a point of the stone, one interface for every integrator: the potch's
//! phase function ([`Phase`]), a domain's Bragg lobe over its normals ([`Mosaic`]) and a
//! backing ([`Lambert`]), each with its draw ([`Scatter::sample`]), the density of that draw
//! ([`Scatter::density`]) and its value ([`Scatter::eval`]). The path tracer draws its
//! directions and weighs its light estimates by them, the stored method's gather and the lobe
//! integrator evaluate them; `tests.rs` checks each draw against its density by a χ² test
//! over directions, as pbrt-v4's `SampledDistribution` tests do.
//!
//! A Bragg line's spectrum (which wavelength a lobe reflects, and how much) is the optics'
//! (`optics::BraggLine`); a [`Mosaic`] is only the spread of the normals that reflect it. The
//! polished surface is a smooth dielectric: it has no spread to draw from, and the path tracer
//! follows both its ways at once (`path::events`).

use std::f32::consts::PI;

use glam::Vec3;

#[cfg(test)]
mod tests;

/// Uniform draws in [0, 1): the path tracer's sampler, or a test's generator.
pub trait Draws {
    /// A draw with 24 bits or more.
    fn uniform_f32(&mut self) -> f32;
    /// A draw with as many bits as the source has (53 from a stream).
    fn uniform(&mut self) -> f64;
}

/// A scattering function at a point: what leaves towards a unit direction `d`, and how to
/// draw `d`.
pub trait Scatter {
    /// A unit direction drawn with the density [`Scatter::density`].
    fn sample<D: Draws>(&self, draws: &mut D) -> Vec3;
    /// The density per steradian of [`Scatter::sample`]'s draw at `d`.
    fn density(&self, d: Vec3) -> f32;
    /// The function's value towards `d`, per steradian: what a light estimate multiplies the
    /// radiance arriving from `d` by (for a phase function, the phase; for a surface, its
    /// reflectance's share times the cosine).
    fn eval(&self, d: Vec3) -> f32;
}

/// The Henyey–Greenstein phase function of anisotropy `g` for light travelling along
/// `incoming`: the potch's and a milky domain's haze (its albedo is applied apart).
#[derive(Clone, Copy, Debug)]
pub struct Phase {
    /// The direction of travel before the scattering (unit).
    pub incoming: Vec3,
    /// Mean cosine of the scattering angle, in (−1, 1).
    pub g: f32,
}

impl Scatter for Phase {
    fn sample<D: Draws>(&self, draws: &mut D) -> Vec3 {
        let cos = hg_cos(f64::from(self.g), draws.uniform()) as f32;
        let sin = (1.0 - cos * cos).max(0.0).sqrt();
        let phi = 2.0 * PI * draws.uniform_f32();
        let (t, b) = self.incoming.any_orthonormal_pair();
        (self.incoming * cos + (t * phi.cos() + b * phi.sin()) * sin).normalize()
    }

    fn density(&self, d: Vec3) -> f32 {
        hg_phase(self.g, d.dot(self.incoming))
    }

    fn eval(&self, d: Vec3) -> f32 {
        self.density(d)
    }
}

/// A cosine of the scattering angle drawn from the Henyey–Greenstein phase function of
/// anisotropy `g` by inversion (`u` uniform in [0, 1)).
pub fn hg_cos(g: f64, u: f64) -> f64 {
    if g.abs() < 1e-4 {
        return 1.0 - 2.0 * u;
    }
    let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u);
    ((1.0 + g * g - s * s) / (2.0 * g)).clamp(-1.0, 1.0)
}

/// The Henyey–Greenstein phase function of anisotropy `g` at cosine `cos`, per steradian.
pub fn hg_phase(g: f32, cos: f32) -> f32 {
    let denom = (1.0 + g * g - 2.0 * g * cos).max(1e-6);
    (1.0 - g * g) / (4.0 * PI * denom * denom.sqrt())
}

/// A domain's Bragg lobe over its normals: the family normal `normal` tilted by a Gaussian of
/// standard deviation `sigma` (radians; the mosaic spread, `Stone::lobe_sigma`), in any
/// direction about it. The reflected direction is the incoming one mirrored in the drawn
/// normal `h`; its density over directions is [`Scatter::density`]`(h) / (4 cos θ_h)`.
#[derive(Clone, Copy, Debug)]
pub struct Mosaic {
    /// The family normal (unit).
    pub normal: Vec3,
    /// The tilt's standard deviation, radians (> 0).
    pub sigma: f32,
}

impl Scatter for Mosaic {
    /// A normal drawn with the tilt's Rayleigh law and a uniform azimuth.
    fn sample<D: Draws>(&self, draws: &mut D) -> Vec3 {
        let u = (1.0 - draws.uniform_f32()).max(1e-12);
        let alpha = self.sigma * (-2.0 * u.ln()).sqrt();
        let phi = 2.0 * PI * draws.uniform_f32();
        let (t, b) = self.normal.any_orthonormal_pair();
        (self.normal * alpha.cos() + (t * phi.cos() + b * phi.sin()) * alpha.sin()).normalize()
    }

    fn density(&self, h: Vec3) -> f32 {
        mosaic_density(angle_between(h, self.normal), self.sigma)
    }

    fn eval(&self, h: Vec3) -> f32 {
        self.density(h)
    }
}

impl Mosaic {
    /// The lobe's density in its small-angle form, `e^(−α²/2σ²) / (2πσ²)`, zero beyond
    /// `sigmas` standard deviations (not renormalised: the Gaussian holds
    /// `1 − e^(−sigmas²/2)` of the lobe within them). For the lobes of opal (a few degrees)
    /// it differs from [`Scatter::density`] by `α / sin α − 1`, under 10⁻³ within 4σ of 3°.
    pub fn small_angle_density(&self, h: Vec3, sigmas: f32) -> f32 {
        let (alpha, sigma) = (angle_between(h, self.normal), self.sigma);
        if alpha < sigmas * sigma {
            (-0.5 * (alpha / sigma).powi(2)).exp() / (2.0 * PI * sigma * sigma)
        } else {
            0.0
        }
    }
}

/// The density over normals (per steradian) of [`Mosaic::sample`] at angle `alpha` from the
/// family normal: the Rayleigh law of the tilt over `2π sin α`.
pub fn mosaic_density(alpha: f32, sigma: f32) -> f32 {
    let gauss = (-0.5 * (alpha / sigma).powi(2)).exp() / (2.0 * PI * sigma * sigma);
    if alpha > 1e-4 {
        gauss * alpha / alpha.sin()
    } else {
        gauss
    }
}

/// A diffuse reflector of reflectance `albedo` facing +z: a backing seen from inside the
/// stone (its flat back's normal points up, into the stone).
#[derive(Clone, Copy, Debug)]
pub struct Lambert {
    /// The share of the light it sends back.
    pub albedo: f32,
}

impl Scatter for Lambert {
    /// A direction drawn with density `cos θ / π` about +z.
    fn sample<D: Draws>(&self, draws: &mut D) -> Vec3 {
        let r = draws.uniform_f32().sqrt();
        let phi = 2.0 * PI * draws.uniform_f32();
        Vec3::new(r * phi.cos(), r * phi.sin(), (1.0 - r * r).max(0.0).sqrt())
    }

    fn density(&self, d: Vec3) -> f32 {
        d.z.max(0.0) / PI
    }

    fn eval(&self, d: Vec3) -> f32 {
        self.albedo * self.density(d)
    }
}

/// The angle between the unit vectors `a` and `b`, radians, accurate near 0 (`2 asin(|a − b|/2)`;
/// `acos` of the dot product loses everything under ~3·10⁻⁴ rad in f32).
pub fn angle_between(a: Vec3, b: Vec3) -> f32 {
    2.0 * (0.5 * (a - b).length()).min(1.0).asin()
}

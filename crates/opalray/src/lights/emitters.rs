//! Area lights (`light.kind = "sphere"`, `"rect"`) and what a ray leaving the stone sees.
//!
//! Input: the light's placement and size → output: an [`AreaLight`] that is sampled from a
//! point `x` (direction, distance, value, density per steradian), evaluated along a ray
//! ([`AreaLight::hit`]) and asked for its density ([`AreaLight::pdf`]).
//!
//! Values are in the image's units (π × radiance, relative to the light's spectrum), uniform
//! over the emitting surface, set so that the irradiance at the stone's centre on a plane
//! facing the light is `light.intensity`, as for the point and directional lights:
//! - a ball of radius r at distance d subtends a cap of sin α = r/d: `E = π L sin² α`, so the
//!   value is `E / sin² α`;
//! - a rectangle of half sizes a × b facing the centre at distance d on its axis:
//!   `E = L G`, `G = ∫ cos θ dω = 2 [X/√(1+X²) atan(Y/√(1+X²)) + Y/√(1+Y²) atan(X/√(1+Y²))]`
//!   with X = a/d, Y = b/d (four times the corner form factor of a point below a corner of a
//!   parallel rectangle, Howell's catalogue C-11 × π), so the value is `π E / G`.
//!
//! Sampling: the ball uniformly over the cap of directions it fills as seen from `x`
//! (pbrt-v4 §6.2.4, density `1 / (2π (1 − cos α))`), the rectangle uniformly over its area,
//! converted to solid angle (`t² / (A cos θ_l)`); only its front face (towards the stone)
//! emits. The geometry is in f64: a ball of 1 mm at 10 m is a cap of 10⁻⁴ rad.

use std::f64::consts::PI;

use glam::{DVec3, Vec3};

use super::env::Environment;

/// A direction drawn towards an area light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LightSample {
    /// Unit direction from `x` towards the drawn point.
    pub direction: Vec3,
    /// Distance from `x` to the drawn point on the light, mm.
    pub distance_mm: f32,
    /// The light's value there (π × radiance, image units).
    pub value: f32,
    /// Density per steradian at `x` with which the direction was drawn.
    pub pdf: f32,
}

/// A sphere or rectangle light in the stone's frame.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum AreaLight {
    /// A glowing ball.
    Sphere {
        /// Centre, mm.
        center: DVec3,
        /// Radius, mm.
        radius_mm: f64,
        /// Value of its surface.
        value: f32,
    },
    /// A rectangle emitting from its front face.
    Rect {
        /// Centre, mm.
        center: DVec3,
        /// Unit normal of the emitting face (towards the stone's centre).
        normal: DVec3,
        /// Unit direction of the width.
        across: DVec3,
        /// Unit direction of the height.
        up: DVec3,
        /// Half the width and half the height, mm.
        half_mm: [f64; 2],
        /// Value of its front face.
        value: f32,
    },
}

impl AreaLight {
    /// A ball of `radius_mm` centred at `center` (mm from the stone's centre, beyond the
    /// ball's radius), giving irradiance `intensity` at the stone's centre.
    pub fn sphere(center: Vec3, radius_mm: f32, intensity: f32) -> Self {
        let center = center.as_dvec3();
        let sin2 = (f64::from(radius_mm) / center.length()).powi(2);
        AreaLight::Sphere {
            center,
            radius_mm: f64::from(radius_mm),
            value: (f64::from(intensity) / sin2) as f32,
        }
    }

    /// A rectangle of `size_mm` (width, height) centred at `center`, facing the stone's
    /// centre, its height along `up` (made perpendicular to the normal; not parallel to
    /// `center`), giving irradiance `intensity` at the stone's centre.
    pub fn rect(center: Vec3, size_mm: [f32; 2], up: Vec3, intensity: f32) -> Self {
        let center = center.as_dvec3();
        let d = center.length();
        let normal = -center / d;
        let up = up.as_dvec3();
        let up = (up - normal * up.dot(normal)).normalize();
        let across = up.cross(normal);
        let half_mm = [0.5 * f64::from(size_mm[0]), 0.5 * f64::from(size_mm[1])];
        let (x, y) = (half_mm[0] / d, half_mm[1] / d);
        let (sx, sy) = ((1.0 + x * x).sqrt(), (1.0 + y * y).sqrt());
        let g = 2.0 * (x / sx * (y / sx).atan() + y / sy * (x / sy).atan());
        AreaLight::Rect {
            center,
            normal,
            across,
            up,
            half_mm,
            value: (PI * f64::from(intensity) / g) as f32,
        }
    }

    /// The light's centre, mm (the stone's frame).
    pub fn center(&self) -> Vec3 {
        match *self {
            AreaLight::Sphere { center, .. } | AreaLight::Rect { center, .. } => center.as_vec3(),
        }
    }

    /// The light's value (uniform over its surface).
    pub fn value(&self) -> f32 {
        match *self {
            AreaLight::Sphere { value, .. } | AreaLight::Rect { value, .. } => value,
        }
    }

    /// A direction from `x` (outside the light) towards the light, drawn with `u ∈ [0, 1)²`;
    /// `None` where `x` sees nothing of it (inside the ball, behind the rectangle).
    pub fn sample(&self, x: Vec3, u: [f32; 2]) -> Option<LightSample> {
        let x = x.as_dvec3();
        let (u0, u1) = (f64::from(u[0]), f64::from(u[1]));
        match *self {
            AreaLight::Sphere {
                center,
                radius_mm,
                value,
            } => {
                let (axis, cap) = sphere_cap(center - x, radius_mm)?;
                // 1 − cos θ uniform over [0, 1 − cos α].
                let t = u0 * cap;
                let sin_theta = (t * (2.0 - t)).max(0.0).sqrt();
                let phi = 2.0 * PI * u1;
                let (a, b) = axis.any_orthonormal_pair();
                let dir =
                    (axis * (1.0 - t) + (a * phi.cos() + b * phi.sin()) * sin_theta).normalize();
                let distance = ray_sphere(x, dir, center, radius_mm)?;
                Some(LightSample {
                    direction: dir.as_vec3(),
                    distance_mm: distance as f32,
                    value,
                    pdf: cone_pdf(cap),
                })
            }
            AreaLight::Rect {
                center,
                normal,
                across,
                up,
                half_mm,
                value,
            } => {
                let p = center
                    + across * ((2.0 * u0 - 1.0) * half_mm[0])
                    + up * ((2.0 * u1 - 1.0) * half_mm[1]);
                let to = p - x;
                let distance = to.length();
                let dir = to / distance;
                let cos_l = -dir.dot(normal);
                if cos_l <= 0.0 || distance <= 0.0 {
                    return None;
                }
                Some(LightSample {
                    direction: dir.as_vec3(),
                    distance_mm: distance as f32,
                    value,
                    pdf: area_pdf(distance, cos_l, half_mm),
                })
            }
        }
    }

    /// The density per steradian with which [`AreaLight::sample`] draws `dir` (unit) from
    /// `x`; 0 where the ray misses the light.
    pub fn pdf(&self, x: Vec3, dir: Vec3) -> f32 {
        let x = x.as_dvec3();
        let dir = dir.as_dvec3().normalize();
        match *self {
            AreaLight::Sphere {
                center, radius_mm, ..
            } => match sphere_cap(center - x, radius_mm) {
                Some((axis, cap)) if in_cap(dir, axis, cap) => cone_pdf(cap),
                _ => 0.0,
            },
            AreaLight::Rect {
                normal, half_mm, ..
            } => self
                .rect_hit(x, dir)
                .map_or(0.0, |t| area_pdf(t, -dir.dot(normal), half_mm)),
        }
    }

    /// The ray from `x` along `dir` (unit): `(distance mm, value)` if it meets the light's
    /// emitting surface.
    pub fn hit(&self, x: Vec3, dir: Vec3) -> Option<(f32, f32)> {
        let x = x.as_dvec3();
        let dir = dir.as_dvec3().normalize();
        match *self {
            AreaLight::Sphere {
                center,
                radius_mm,
                value,
            } => {
                // The cap test (as `pdf`), then the distance.
                let (axis, cap) = sphere_cap(center - x, radius_mm)?;
                if !in_cap(dir, axis, cap) {
                    return None;
                }
                let t = ray_sphere(x, dir, center, radius_mm)?;
                Some((t as f32, value))
            }
            AreaLight::Rect { value, .. } => self.rect_hit(x, dir).map(|t| (t as f32, value)),
        }
    }

    /// Distance along the ray to the rectangle's front face, if it meets it.
    fn rect_hit(&self, x: DVec3, dir: DVec3) -> Option<f64> {
        let AreaLight::Rect {
            center,
            normal,
            across,
            up,
            half_mm,
            ..
        } = *self
        else {
            return None;
        };
        let facing = dir.dot(normal);
        if facing >= 0.0 {
            return None;
        }
        let t = (center - x).dot(normal) / facing;
        if t <= 0.0 {
            return None;
        }
        let local = x + dir * t - center;
        (local.dot(across).abs() <= half_mm[0] && local.dot(up).abs() <= half_mm[1]).then_some(t)
    }
}

/// The density per steradian of directions drawn uniformly over a cone of `1 − cos α = cap`.
fn cone_pdf(cap: f64) -> f32 {
    (1.0 / (2.0 * PI * cap)) as f32
}

/// The density per steradian of points drawn uniformly over a rectangle of half sizes
/// `half_mm`, seen at `distance` mm at `cos_l` to its normal: `t² / (A cos θ_l)`.
fn area_pdf(distance: f64, cos_l: f64, half_mm: [f64; 2]) -> f32 {
    (distance * distance / (4.0 * half_mm[0] * half_mm[1] * cos_l)) as f32
}

/// The cap of directions a ball fills seen from a point `to_center` away from its centre:
/// `(axis, 1 − cos α)`; `None` from inside the ball.
fn sphere_cap(to_center: DVec3, radius: f64) -> Option<(DVec3, f64)> {
    let d2 = to_center.length_squared();
    let sin2 = radius * radius / d2;
    if sin2 >= 1.0 {
        return None;
    }
    // 1 − cos α = sin² α / (1 + cos α): no cancellation for a small cap.
    let cap = sin2 / (1.0 + (1.0 - sin2).sqrt());
    Some((to_center / d2.sqrt(), cap))
}

/// Whether the unit `dir` lies in the cap about `axis` of `1 − cos α = cap`.
fn in_cap(dir: DVec3, axis: DVec3, cap: f64) -> bool {
    let cos = dir.dot(axis);
    // sin² θ ≤ sin² α, on the axis's side: precise for a small cap.
    let sin2 = dir.cross(axis).length_squared();
    cos > 0.0 && sin2 <= cap * (2.0 - cap)
}

/// Nearest distance > 0 from `x` along the unit `dir` to the ball, if it meets it (a ray
/// grazing the rim within rounding counts as meeting it there).
fn ray_sphere(x: DVec3, dir: DVec3, center: DVec3, radius: f64) -> Option<f64> {
    let oc = center - x;
    let b = oc.dot(dir);
    // The squared distance of the centre from the ray, without the cancellation of b² − c.
    let miss2 = (oc - dir * b).length_squared();
    let h2 = radius * radius - miss2;
    if b <= 0.0 || h2 < -1e-9 * radius * radius {
        return None;
    }
    Some(b - h2.max(0.0).sqrt())
}

/// What a ray leaving the stone at `origin` along `dir` (unit, the stone's frame) sees:
/// `(value, true)`, the area light where it meets it (the light hides the environment behind
/// it), else `(value, false)`, the environment.
pub fn seen(
    environment: &Environment,
    light: Option<&AreaLight>,
    origin: Vec3,
    dir: Vec3,
) -> (f32, bool) {
    match light.and_then(|l| l.hit(origin, dir)) {
        Some((_, value)) => (value, true),
        None => (environment.value(dir), false),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn sphere_samples_hit_the_ball_with_their_pdf() {
        let light = AreaLight::sphere(Vec3::new(30.0, -40.0, 120.0), 8.0, 1.0);
        let x = Vec3::new(1.0, 2.0, -0.5);
        let mut rng = Rng::new(3, 0, 0);
        for _ in 0..2000 {
            let s = light
                .sample(x, [rng.uniform_f32(), rng.uniform_f32()])
                .unwrap();
            let (t, v) = light
                .hit(x, s.direction)
                .expect("a sampled direction meets it");
            assert!((t - s.distance_mm).abs() < 1e-3, "{t} {}", s.distance_mm);
            assert_eq!(v, s.value);
            let pdf = light.pdf(x, s.direction);
            assert!((pdf - s.pdf).abs() <= 1e-5 * s.pdf, "{pdf} {}", s.pdf);
            let p = x.as_dvec3() + s.direction.as_dvec3() * f64::from(s.distance_mm);
            let r = (p - DVec3::new(30.0, -40.0, 120.0)).length();
            assert!((r - 8.0).abs() < 1e-3, "on the surface: {r}");
        }
        assert!(light.hit(x, -Vec3::Z).is_none());
        assert_eq!(light.pdf(x, -Vec3::Z), 0.0);
    }

    #[test]
    fn rect_samples_hit_the_face_with_their_pdf() {
        let light = AreaLight::rect(Vec3::new(0.0, 60.0, 80.0), [40.0, 20.0], Vec3::Y, 2.0);
        let x = Vec3::new(2.0, -1.0, 3.0);
        let mut rng = Rng::new(4, 0, 0);
        for _ in 0..2000 {
            let s = light
                .sample(x, [rng.uniform_f32(), rng.uniform_f32()])
                .unwrap();
            let (t, _) = light
                .hit(x, s.direction)
                .expect("a sampled direction meets it");
            assert!((t - s.distance_mm).abs() < 1e-3);
            let pdf = light.pdf(x, s.direction);
            assert!((pdf - s.pdf).abs() <= 1e-4 * s.pdf, "{pdf} {}", s.pdf);
        }
        // Its back does not emit.
        let behind = Vec3::new(0.0, 120.0, 160.0);
        assert!(light
            .hit(behind, (Vec3::new(0.0, 60.0, 80.0) - behind).normalize())
            .is_none());
        assert!(light.sample(behind, [0.5, 0.5]).is_none());
    }

    /// ∫ value cos θ dω over the light seen from the stone's centre, facing it, estimated by
    /// sampling the light: `intensity`, the irradiance the normalisation promises.
    fn centre_irradiance(light: &AreaLight, towards: Vec3, n: u32) -> (f64, f64) {
        let mut rng = Rng::new(5, 0, 0);
        let (mut sum, mut sum2) = (0.0, 0.0);
        for _ in 0..n {
            let s = light.sample(Vec3::ZERO, [rng.uniform_f32(), rng.uniform_f32()]);
            let e = s.map_or(0.0, |s| {
                f64::from(s.value) * f64::from(s.direction.dot(towards).max(0.0))
                    / f64::from(s.pdf)
                    / PI
            });
            sum += e;
            sum2 += e * e;
        }
        let mean = sum / f64::from(n);
        let se = ((sum2 / f64::from(n) - mean * mean) / f64::from(n)).sqrt();
        (mean, se)
    }

    #[test]
    fn area_lights_give_their_intensity_at_the_centre() {
        let towards = Vec3::new(0.6, 0.0, 0.8);
        for light in [
            AreaLight::sphere(towards * 100.0, 40.0, 1.5),
            AreaLight::rect(towards * 100.0, [150.0, 60.0], Vec3::Y, 1.5),
            AreaLight::rect(towards * 100.0, [10.0, 10.0], Vec3::Y, 1.5),
        ] {
            let (mean, se) = centre_irradiance(&light, towards, 40_000);
            assert!(
                (mean - 1.5).abs() < 4.0 * se + 1e-6,
                "{light:?}: {mean} ± {se}"
            );
        }
    }
}

//! The opal's shape: an axis-aligned ellipsoid centred at the origin.

use glam::{DVec3, Vec3};

use super::Ray;

/// Ellipsoid `(x/a)² + (y/b)² + (z/c)² = 1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ellipsoid {
    /// Semi-axes `(a, b, c)`, mm, all positive.
    semi_axes: Vec3,
    /// `1 / semi_axes`, the scale to the unit sphere (formed once: a ray is intersected
    /// millions of times per render).
    inv: DVec3,
}

impl Ellipsoid {
    /// Ellipsoid with semi-axes `(a, b, c)` in mm.
    pub fn new(semi_axes: Vec3) -> Self {
        Ellipsoid {
            semi_axes,
            inv: semi_axes.recip().as_dvec3(),
        }
    }

    /// Semi-axes `(a, b, c)`, mm.
    pub fn semi_axes(&self) -> Vec3 {
        self.semi_axes
    }

    /// Whether `p` is inside (or on) the surface.
    pub fn contains(&self, p: Vec3) -> bool {
        (p / self.semi_axes).length_squared() <= 1.0
    }

    /// A lower bound of the distance from `p` to the surface, mm (0 outside). The solid is
    /// convex and holds the ball of its least semi-axis `c`; `p` lies on the shrunk copy
    /// `r E`, r = |p / semi-axes|, so `p + (1 − r) c B ⊆ r E + (1 − r) E = E`.
    pub fn depth_bound(&self, p: Vec3) -> f32 {
        let r = (p / self.semi_axes).length();
        ((1.0 - r) * self.semi_axes.min_element()).max(0.0)
    }

    /// Parameters `(t_near, t_far)` where the full line of `ray` crosses the surface, or
    /// `None` if it misses. Solved in the frame scaled to the unit sphere, in f64 for
    /// accuracy at grazing incidence.
    pub fn intersect(&self, ray: &Ray) -> Option<(f32, f32)> {
        let inv = self.inv;
        let o = ray.origin.as_dvec3() * inv;
        let d = ray.direction.as_dvec3() * inv;
        let a = d.length_squared();
        let half_b = o.dot(d);
        let c = o.length_squared() - 1.0;
        let disc = half_b * half_b - a * c;
        if disc <= 0.0 {
            return None;
        }
        let root = disc.sqrt();
        // Numerically stable pair of roots (Numerical Recipes §5.6).
        let q = -(half_b + half_b.signum() * root);
        let (t0, t1) = if q == 0.0 {
            (-root / a, root / a)
        } else {
            let (r0, r1) = (q / a, c / q);
            (r0.min(r1), r0.max(r1))
        };
        Some((t0 as f32, t1 as f32))
    }

    /// Outward unit normal at a point `p` on the surface.
    pub fn normal(&self, p: Vec3) -> Vec3 {
        (p / (self.semi_axes * self.semi_axes)).normalize()
    }

    /// Radius of the bounding sphere, mm.
    pub fn bounding_radius(&self) -> f32 {
        self.semi_axes.max_element()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ray_along_an_axis_meets_the_semi_axis() {
        let e = Ellipsoid::new(Vec3::new(10.0, 7.5, 2.5));
        let ray = Ray::new(Vec3::new(0.0, 0.0, 100.0), -Vec3::Z);
        let (t0, t1) = e.intersect(&ray).unwrap();
        assert!((t0 - 97.5).abs() < 1e-4 && (t1 - 102.5).abs() < 1e-4);
        assert!((e.normal(ray.at(t0)) - Vec3::Z).length() < 1e-6);
    }

    #[test]
    fn hit_points_lie_on_the_surface() {
        let e = Ellipsoid::new(Vec3::new(10.0, 7.5, 2.5));
        let ray = Ray::new(Vec3::new(3.0, -2.0, 50.0), Vec3::new(-0.05, 0.03, -1.0));
        let (t0, t1) = e.intersect(&ray).unwrap();
        for t in [t0, t1] {
            let p = ray.at(t) / e.semi_axes;
            assert!((p.length_squared() - 1.0).abs() < 1e-4);
        }
    }

    #[test]
    fn a_ray_beside_the_ellipsoid_misses() {
        let e = Ellipsoid::new(Vec3::new(10.0, 7.5, 2.5));
        let ray = Ray::new(Vec3::new(0.0, 8.0, 100.0), -Vec3::Z);
        assert!(e.intersect(&ray).is_none());
    }
}

//! The stone's outer surface for the stone model: the paper's ellipsoid or a cabochon (an
//! elliptical dome over a flat or gently domed back). Both are convex, so a line meets the
//! surface at most twice.

use glam::Vec3;

use super::{Ellipsoid, Ray};

/// A closed convex surface a ray can be intersected with: what refraction at the surface
/// needs to know.
pub trait Surface {
    /// `(t_near, t_far)` where the full line of `ray` crosses the surface, or `None`.
    fn intersect(&self, ray: &Ray) -> Option<(f32, f32)>;
    /// Outward unit normal at a point `p` on the surface.
    fn normal(&self, p: Vec3) -> Vec3;
}

impl Surface for Ellipsoid {
    fn intersect(&self, ray: &Ray) -> Option<(f32, f32)> {
        Ellipsoid::intersect(self, ray)
    }
    fn normal(&self, p: Vec3) -> Vec3 {
        Ellipsoid::normal(self, p)
    }
}

/// A cabochon: the girdle, an ellipse of semi-axes `a × b` in the plane `z = girdle_z`; above
/// it a half-ellipsoid dome of height `dome`, below it a half-ellipsoid back of height `back`
/// (0: a flat back). The two halves meet the girdle vertically, so their union is convex.
/// Placed so that its height is centred on `z = 0`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cabochon {
    dome: Ellipsoid,
    /// `None`: a flat back.
    back: Option<Ellipsoid>,
    girdle_z: f32,
    girdle: (f32, f32),
}

impl Cabochon {
    /// A cabochon of girdle semi-axes `a`, `b`, dome height `dome` and back height `back`
    /// (mm; `back` 0 for a flat back).
    pub fn new(a: f32, b: f32, dome: f32, back: f32) -> Self {
        let girdle_z = 0.5 * (back - dome);
        Cabochon {
            dome: Ellipsoid::new(Vec3::new(a, b, dome)),
            back: (back > 0.0).then(|| Ellipsoid::new(Vec3::new(a, b, back))),
            girdle_z,
            girdle: (a, b),
        }
    }

    /// Height of the girdle plane, mm.
    pub fn girdle_z(&self) -> f32 {
        self.girdle_z
    }

    /// Highest point (the dome's apex), mm.
    pub fn top_z(&self) -> f32 {
        self.girdle_z + self.dome.semi_axes().z
    }

    /// Lowest point, mm.
    pub fn bottom_z(&self) -> f32 {
        self.girdle_z - self.back.map_or(0.0, |b| b.semi_axes().z)
    }

    /// Whether the back is flat.
    pub fn flat_back(&self) -> bool {
        self.back.is_none()
    }

    fn local(&self, ray: &Ray) -> Ray {
        Ray {
            origin: ray.origin - Vec3::Z * self.girdle_z,
            direction: ray.direction,
        }
    }

    /// Whether `p` is inside (or on) the surface.
    pub fn contains(&self, p: Vec3) -> bool {
        let q = p - Vec3::Z * self.girdle_z;
        if q.z >= 0.0 {
            self.dome.contains(q)
        } else {
            self.back.is_some_and(|b| b.contains(q))
        }
    }

    /// A lower bound of the distance from `p` to the surface, mm (0 outside). The solid holds
    /// its dome's half-ellipsoid (and its back's), each the intersection of a full ellipsoid
    /// with a half-space, and the ellipsoid of its girdle and the lower of its two heights.
    pub fn depth_bound(&self, p: Vec3) -> f32 {
        let q = p - Vec3::Z * self.girdle_z;
        let half = if q.z >= 0.0 {
            self.dome.depth_bound(q).min(q.z)
        } else {
            self.back.map_or(0.0, |b| b.depth_bound(q).min(-q.z))
        };
        let Some(back) = &self.back else {
            return half;
        };
        let (a, b) = self.girdle;
        let low = self.dome.semi_axes().z.min(back.semi_axes().z);
        half.max(Ellipsoid::new(Vec3::new(a, b, low)).depth_bound(q))
    }

    /// `(t_near, t_far)` where the full line of `ray` crosses the surface, or `None`.
    pub fn intersect(&self, ray: &Ray) -> Option<(f32, f32)> {
        let local = self.local(ray);
        let dz = local.direction.z;
        let oz = local.origin.z;
        // The line's interval in the upper half-space `z ≥ 0` and in the lower one.
        let plane_t = if dz != 0.0 { -oz / dz } else { f32::NAN };
        let (upper, lower) = if dz > 0.0 {
            ((plane_t, f32::INFINITY), (f32::NEG_INFINITY, plane_t))
        } else if dz < 0.0 {
            ((f32::NEG_INFINITY, plane_t), (plane_t, f32::INFINITY))
        } else if oz >= 0.0 {
            ((f32::NEG_INFINITY, f32::INFINITY), (1.0, 0.0))
        } else {
            ((1.0, 0.0), (f32::NEG_INFINITY, f32::INFINITY))
        };
        let clip = |a: (f32, f32), b: (f32, f32)| {
            let lo = a.0.max(b.0);
            let hi = a.1.min(b.1);
            (lo <= hi).then_some((lo, hi))
        };
        let top = self.dome.intersect(&local).and_then(|i| clip(i, upper));
        // A flat back: the dome cut by the girdle plane is the whole solid.
        let Some(back) = &self.back else {
            return top;
        };
        let bottom = back.intersect(&local).and_then(|i| clip(i, lower));
        match (top, bottom) {
            // Convex: the two pieces of the line meet at the girdle plane.
            (Some(t), Some(b)) => Some((t.0.min(b.0), t.1.max(b.1))),
            (t, b) => t.or(b),
        }
    }

    /// Outward unit normal at a point `p` on the surface.
    pub fn normal(&self, p: Vec3) -> Vec3 {
        let q = p - Vec3::Z * self.girdle_z;
        if q.z >= 0.0 {
            // On the flat back's plane only when inside the girdle and low enough.
            if self.back.is_none() && q.z < 1e-4 && !self.on_dome(q) {
                return -Vec3::Z;
            }
            self.dome.normal(q)
        } else {
            match &self.back {
                Some(b) => b.normal(q),
                None => -Vec3::Z,
            }
        }
    }

    fn on_dome(&self, q: Vec3) -> bool {
        let s = self.dome.semi_axes();
        ((q / s).length_squared() - 1.0).abs() < 1e-3
    }

    /// Radius of the bounding sphere about the origin, mm.
    pub fn bounding_radius(&self) -> f32 {
        let (a, b) = self.girdle;
        let h = self.top_z().max(-self.bottom_z());
        a.max(b).hypot(h)
    }
}

/// The stone's outer surface.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Outline {
    /// The paper's ellipsoid.
    Ellipsoid(Ellipsoid),
    /// A cabochon.
    Cabochon(Cabochon),
}

impl Outline {
    /// Whether `p` is inside (or on) the surface.
    pub fn contains(&self, p: Vec3) -> bool {
        match self {
            Outline::Ellipsoid(e) => e.contains(p),
            Outline::Cabochon(c) => c.contains(p),
        }
    }

    /// Semi-axes of the bounding box about the origin, mm (an ellipsoid's own semi-axes).
    pub fn semi_axes(&self) -> Vec3 {
        match self {
            Outline::Ellipsoid(e) => e.semi_axes(),
            Outline::Cabochon(c) => {
                Vec3::new(c.girdle.0, c.girdle.1, 0.5 * (c.top_z() - c.bottom_z()))
            }
        }
    }

    /// Radius of the bounding sphere about the origin, mm.
    pub fn bounding_radius(&self) -> f32 {
        match self {
            Outline::Ellipsoid(e) => e.bounding_radius(),
            Outline::Cabochon(c) => c.bounding_radius(),
        }
    }

    /// A lower bound of the distance from `p` to the surface, mm (0 outside).
    pub fn depth_bound(&self, p: Vec3) -> f32 {
        match self {
            Outline::Ellipsoid(e) => e.depth_bound(p),
            Outline::Cabochon(c) => c.depth_bound(p),
        }
    }

    /// `(t_near, t_far)` where the full line of `ray` crosses the surface, or `None`.
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<(f32, f32)> {
        match self {
            Outline::Ellipsoid(e) => e.intersect(ray),
            Outline::Cabochon(c) => c.intersect(ray),
        }
    }

    /// Outward unit normal at a point `p` on the surface.
    #[inline]
    pub fn normal(&self, p: Vec3) -> Vec3 {
        match self {
            Outline::Ellipsoid(e) => e.normal(p),
            Outline::Cabochon(c) => c.normal(p),
        }
    }
}

impl Surface for Outline {
    fn intersect(&self, ray: &Ray) -> Option<(f32, f32)> {
        Outline::intersect(self, ray)
    }
    fn normal(&self, p: Vec3) -> Vec3 {
        Outline::normal(self, p)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn cab() -> Cabochon {
        Cabochon::new(10.0, 7.5, 3.0, 0.0)
    }

    #[test]
    fn a_vertical_ray_meets_the_apex_and_the_flat_back() {
        let c = cab();
        let ray = Ray::new(Vec3::new(0.0, 0.0, 50.0), -Vec3::Z);
        let (t0, t1) = c.intersect(&ray).unwrap();
        assert!((ray.at(t0).z - 1.5).abs() < 1e-4, "{}", ray.at(t0).z);
        assert!((ray.at(t1).z + 1.5).abs() < 1e-4, "{}", ray.at(t1).z);
        assert!((c.normal(ray.at(t0)) - Vec3::Z).length() < 1e-5);
        assert_eq!(c.normal(ray.at(t1)), -Vec3::Z);
    }

    #[test]
    fn a_ray_beside_the_girdle_misses_and_one_below_the_back_misses() {
        let c = cab();
        assert!(c
            .intersect(&Ray::new(Vec3::new(11.0, 0.0, 50.0), -Vec3::Z))
            .is_none());
        // Horizontal, under the flat back.
        assert!(c
            .intersect(&Ray::new(Vec3::new(-50.0, 0.0, -1.6), Vec3::X))
            .is_none());
    }

    #[test]
    fn random_chords_have_their_ends_on_the_surface_and_their_middle_inside() {
        let mut rng = crate::sampling::Rng::new(7, 0, 0);
        for c in [cab(), Cabochon::new(8.0, 6.0, 2.5, 0.8)] {
            let mut hits = 0;
            for _ in 0..2000 {
                let o = rng.unit_vector() * 30.0;
                let target = Vec3::new(
                    rng.uniform_f32() * 16.0 - 8.0,
                    rng.uniform_f32() * 12.0 - 6.0,
                    rng.uniform_f32() * 4.0 - 2.0,
                );
                let ray = Ray::new(o, target - o);
                let Some((t0, t1)) = c.intersect(&ray) else {
                    assert!(!c.contains(target), "{target}");
                    continue;
                };
                hits += 1;
                let mid = ray.at(0.5 * (t0 + t1));
                assert!(c.contains(mid), "{mid}");
                for t in [t0, t1] {
                    let p = ray.at(t);
                    // The flat back's rim is an edge: its normal is either side's.
                    let q = p - Vec3::Z * c.girdle_z();
                    let rim = (q.x / c.girdle.0).powi(2) + (q.y / c.girdle.1).powi(2);
                    if c.flat_back() && q.z.abs() < 1e-3 && rim > 0.99 {
                        continue;
                    }
                    assert!(c.contains(p - 1e-3 * c.normal(p)), "{p}");
                    assert!(!c.contains(p + 1e-3 * c.normal(p)), "{p}");
                }
            }
            assert!(hits > 500, "{hits}");
        }
    }

    #[test]
    fn the_depth_bound_never_exceeds_the_distance_to_the_surface_and_is_exact_at_the_centre() {
        // Independent: the distance from p to the surface is the least exit distance over all
        // directions from p (2000 random ones, and the six axes).
        let mut rng = crate::sampling::Rng::new(3, 0, 0);
        let shapes = [
            Outline::Cabochon(cab()),
            Outline::Cabochon(Cabochon::new(8.0, 6.0, 2.5, 0.8)),
            Outline::Ellipsoid(Ellipsoid::new(Vec3::new(10.0, 7.5, 2.5))),
        ];
        for shape in shapes {
            let s = shape.semi_axes();
            let mut inside = 0;
            for _ in 0..300 {
                let p = Vec3::new(
                    (rng.uniform_f32() * 2.0 - 1.0) * s.x,
                    (rng.uniform_f32() * 2.0 - 1.0) * s.y,
                    (rng.uniform_f32() * 2.0 - 1.0) * s.z,
                );
                let bound = shape.depth_bound(p);
                if !shape.contains(p) {
                    assert_eq!(bound, 0.0, "{p}");
                    continue;
                }
                inside += 1;
                let axes = [Vec3::X, Vec3::Y, Vec3::Z, -Vec3::X, -Vec3::Y, -Vec3::Z];
                let nearest = (0..2000)
                    .map(|_| rng.unit_vector())
                    .chain(axes)
                    .filter_map(|d| shape.intersect(&Ray::new(p, d)).map(|(_, t1)| t1))
                    .fold(f32::INFINITY, f32::min);
                assert!(bound <= nearest + 1e-4, "{p}: {bound} > {nearest}");
            }
            assert!(inside > 50, "{inside}");
        }
        // At the flat-backed dome's centre of height, the nearest surface is the back or the
        // apex, half the height away.
        let c = cab();
        let centre = Vec3::new(0.0, 0.0, c.girdle_z() + 1.5);
        assert!((c.depth_bound(centre) - 1.5).abs() < 1e-5);
    }
}

//! Light sources as seen from the opal's frame, and how light-pass rays are drawn from them.

pub use crate::geometry::LightSource;

use crate::geometry::{Ellipsoid, Ray};
use crate::sampling::Rng;

/// Rays of the light pass: a stratified `side × side` lattice, each ray carrying an equal
/// share of the power that falls on the opal's bounding sphere.
#[derive(Clone, Copy, Debug)]
pub struct RayLattice {
    source: LightSource,
    side: u64,
    radius: f32,
    /// Power carried by each ray, in units of (irradiance 1) × mm².
    pub power_per_ray: f32,
}

impl RayLattice {
    /// About `rays` rays (rounded to a square lattice) covering `shape` as seen from `source`.
    pub fn new(source: LightSource, shape: &Ellipsoid, rays: u64) -> Self {
        let side = ((rays as f64).sqrt().round() as u64).max(1);
        let radius = shape.bounding_radius() * 1.001;
        let power_per_ray = match source {
            // A square of side 2r perpendicular to the beam, irradiance 1.
            LightSource::Directional { .. } => (2.0 * radius).powi(2) / (side * side) as f32,
            // Solid angle of the bounding cone; intensity d² gives irradiance 1 at the centre.
            LightSource::Point { position } => {
                let d = position.length();
                let cos_max = (1.0 - (radius / d).powi(2)).max(0.0).sqrt();
                2.0 * std::f32::consts::PI * (1.0 - cos_max) * d * d / (side * side) as f32
            }
        };
        RayLattice {
            source,
            side,
            radius,
            power_per_ray,
        }
    }

    /// Largest irradiance (relative to the opal's centre) anywhere on the stone.
    pub fn max_irradiance(&self) -> f32 {
        match self.source {
            LightSource::Directional { .. } => 1.0,
            LightSource::Point { position } => {
                let d = position.length();
                (d / (d - self.radius).max(1e-3)).powi(2)
            }
        }
    }

    /// Rays per side of the square lattice.
    pub fn side(&self) -> u64 {
        self.side
    }

    /// Width of one lattice cell at the stone, mm (for a point light, of the cone's base at
    /// the stone's centre, roughly).
    pub fn spacing(&self) -> f32 {
        2.0 * self.radius / self.side as f32
    }

    /// Number of rays.
    pub fn len(&self) -> u64 {
        self.side * self.side
    }

    /// Whether the lattice has no rays (never: at least one).
    pub fn is_empty(&self) -> bool {
        self.side == 0
    }

    /// Ray `index`, jittered within its lattice cell by `rng`.
    pub fn ray(&self, index: u64, rng: &mut Rng) -> Ray {
        let fu = rng.uniform_f32();
        let fv = rng.uniform_f32();
        self.ray_in(index, fu, fv)
    }

    /// The ray through the point `(fu, fv)` (each in [0, 1)) of lattice cell `index`.
    pub fn ray_in(&self, index: u64, fu: f32, fv: f32) -> Ray {
        let (i, j) = (index % self.side, index / self.side);
        let u = ((i as f32 + fu) / self.side as f32) * 2.0 - 1.0;
        let v = ((j as f32 + fv) / self.side as f32) * 2.0 - 1.0;
        match self.source {
            LightSource::Directional { direction } => {
                let (a, b) = direction.any_orthonormal_pair();
                let origin = (a * u + b * v) * self.radius - direction * (4.0 * self.radius);
                Ray::new(origin, direction)
            }
            LightSource::Point { position } => {
                // Uniform in solid angle within the cone towards the bounding sphere.
                let axis = -position.normalize();
                let d = position.length();
                let cos_max = (1.0 - (self.radius / d).powi(2)).max(0.0).sqrt();
                let (su, sv) = ((u + 1.0) * 0.5, (v + 1.0) * 0.5);
                let cos_t = 1.0 - su * (1.0 - cos_max);
                let sin_t = (1.0 - cos_t * cos_t).max(0.0).sqrt();
                let phi = std::f32::consts::TAU * sv;
                let (a, b) = axis.any_orthonormal_pair();
                let dir = axis * cos_t + (a * phi.cos() + b * phi.sin()) * sin_t;
                Ray::new(position, dir)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use glam::Vec3;

    #[test]
    fn directional_lattice_delivers_unit_irradiance() {
        // The power of the rays that hit a disc of radius 5 facing the beam must be its area.
        let shape = Ellipsoid::new(Vec3::new(10.0, 7.5, 2.5));
        let source = LightSource::Directional {
            direction: -Vec3::Z,
        };
        let lattice = RayLattice::new(source, &shape, 250_000);
        let mut rng = Rng::new(1, 0, 0);
        let hits = (0..lattice.len())
            .filter(|&i| {
                let r = lattice.ray(i, &mut rng);
                r.origin.truncate().length() < 5.0
            })
            .count();
        let power = hits as f32 * lattice.power_per_ray;
        let area = std::f32::consts::PI * 25.0;
        assert!((power / area - 1.0).abs() < 0.01, "{power} vs {area}");
    }

    #[test]
    fn point_lattice_delivers_unit_irradiance_at_the_centre() {
        // Rays crossing a small disc of radius 1 at the centre, facing the light 100 mm away.
        let shape = Ellipsoid::new(Vec3::new(10.0, 7.5, 2.5));
        let source = LightSource::Point {
            position: Vec3::new(0.0, 0.0, 100.0),
        };
        let lattice = RayLattice::new(source, &shape, 1_000_000);
        let mut rng = Rng::new(1, 0, 0);
        let hits = (0..lattice.len())
            .filter(|&i| {
                let r = lattice.ray(i, &mut rng);
                let t = -r.origin.z / r.direction.z;
                r.at(t).truncate().length() < 1.0
            })
            .count();
        let power = hits as f32 * lattice.power_per_ray;
        assert!((power / std::f32::consts::PI - 1.0).abs() < 0.03, "{power}");
    }
}

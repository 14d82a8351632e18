//! Geometry foundations: the ellipsoid's and the cabochon's surfaces, Fresnel optics at it, exact traversal of
//! the cell grid (3-D DDA) and the pinhole camera. Depends on no stage.

mod camera;
mod ellipsoid;
mod grid;
mod light;
mod outline;
mod surface;

pub use camera::Camera;
pub use ellipsoid::Ellipsoid;
pub use grid::{CellGrid, Segment};
pub use light::{refracted_entry, LightSource};
pub use outline::{Cabochon, Outline, Surface};
pub use surface::{fresnel_dielectric, fresnel_dielectric_sp, reflect, refract};

use glam::Vec3;

/// A ray `origin + t · direction`, `direction` unit length.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ray {
    /// Start point, mm.
    pub origin: Vec3,
    /// Unit direction.
    pub direction: Vec3,
}

impl Ray {
    /// A ray; `direction` is normalised.
    pub fn new(origin: Vec3, direction: Vec3) -> Self {
        Ray {
            origin,
            direction: direction.normalize(),
        }
    }

    /// The point at parameter `t` (mm along the ray).
    pub fn at(&self, t: f32) -> Vec3 {
        self.origin + t * self.direction
    }
}

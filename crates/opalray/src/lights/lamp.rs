//! The scene's point or directional light as the stone model's methods see it: where it is
//! ([`LightSource`]), its irradiance scale and the disc the gloss shows of it. How a method
//! estimates it inside the stone is that method's (the path tracer's `path/lamp.rs`, the lobe
//! integrator's `lobe/trace/lit.rs`, the stored method's `stored/light.rs`).

use glam::Vec3;

use crate::geometry::LightSource;

/// The scene's point or directional light (`light.kind = "point"` or `"directional"`).
#[derive(Clone, Copy, Debug)]
pub struct Lamp {
    /// Where it is.
    pub source: LightSource,
    /// Irradiance scale (`light.intensity`).
    pub intensity: f32,
    /// Angular radius of its disc as seen in the gloss, radians (0: no disc).
    pub disc_radius_rad: f32,
}

impl Lamp {
    /// Its disc seen along `dir` from outside (the gloss's image of the lamp), in image
    /// units: the irradiance over the disc's solid angle π r², times π; 0 off the disc.
    pub fn disc(&self, dir: Vec3) -> f32 {
        let r = self.disc_radius_rad;
        let to_light = self.source.direction_to_light(Vec3::ZERO);
        if r > 0.0 && dir.dot(to_light) >= r.cos() {
            self.intensity / (r * r)
        } else {
            0.0
        }
    }
}

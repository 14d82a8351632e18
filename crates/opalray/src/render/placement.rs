//! The light and camera placed in the opal's frame for a light angle (fig. 10), the scene's
//! area light built where its point light is, and the light's spectrum.

use glam::{Quat, Vec3};

use super::Prepared;
use crate::color::illuminant_spectrum;
use crate::geometry::Camera;
use crate::light_pass::LightSource;
use crate::lights::AreaLight;
use crate::scene::{LightKind, Scene};

impl Prepared {
    /// The light and camera in the opal's frame, for light angle `light_angle_deg` (fig. 10:
    /// the angle between the view direction and the light-to-opal direction, about the
    /// camera's up axis; positive puts the light on the camera's right).
    pub fn placement(&self, light_angle_deg: f64) -> (Camera, LightSource) {
        let s = &self.scene;
        let to_opal = lab_to_stone(s);
        let eye = to_opal * Vec3::new(0.0, 0.0, s.camera.distance_mm as f32);
        let up = to_opal * Vec3::Y;
        let camera = Camera::look_at(
            eye,
            Vec3::ZERO,
            up,
            s.camera.fov_deg as f32,
            s.render.width as usize,
            s.render.height as usize,
        );
        let theta = (light_angle_deg as f32).to_radians();
        let travel = to_opal * Vec3::new(-theta.sin(), 0.0, -theta.cos());
        let source = match s.light.kind {
            LightKind::Directional | LightKind::None => {
                LightSource::Directional { direction: travel }
            }
            // A sphere or rect light is placed as the point light; `area_light` makes it.
            LightKind::Point | LightKind::Sphere | LightKind::Rect => LightSource::Point {
                position: -travel * s.light.distance_mm as f32,
            },
        };
        (camera, source)
    }

    /// The light's spectrum per bin, scaled by its intensity.
    pub fn light_spectrum(&self) -> Vec<f32> {
        let k = self.scene.light.intensity as f32;
        illuminant_spectrum(self.scene.light.illuminant, &self.scene.spectrum)
            .into_iter()
            .map(|v| v * k)
            .collect()
    }
}

impl Prepared {
    /// The scene's sphere or rect light centred where `source` (its point light) is, the
    /// rect's height along `up`; `None` for other lights.
    pub fn area_light(&self, source: LightSource, up: Vec3) -> Option<AreaLight> {
        let light = &self.scene.light;
        let LightSource::Point { position } = source else {
            return None;
        };
        let intensity = light.intensity as f32;
        match light.kind {
            LightKind::Sphere => Some(AreaLight::sphere(
                position,
                light.radius_mm as f32,
                intensity,
            )),
            LightKind::Rect => Some(AreaLight::rect(
                position,
                light.size_mm.map(|v| v as f32),
                up,
                intensity,
            )),
            _ => None,
        }
    }
}

/// The camera's up axis in the opal's frame (the picture's up).
pub(crate) fn camera_up(s: &Scene) -> Vec3 {
    lab_to_stone(s) * Vec3::Y
}

/// The rotation from the room (camera and lights fixed, the camera on +z) into the opal's
/// frame: the opal is turned by `camera.turn_deg` about its face's normal, then tilted by
/// `camera.tilt_deg` about the picture's horizontal axis.
fn lab_to_stone(s: &Scene) -> Quat {
    Quat::from_rotation_z(-(s.camera.turn_deg as f32).to_radians())
        * Quat::from_rotation_x(-(s.camera.tilt_deg as f32).to_radians())
}

/// Angular radius of the scene light's disc as the path integrator's gloss shows it, degrees
/// (a small lamp or the sun: 0.5°).
pub const LIGHT_DISC_RADIUS_DEG: f32 = 0.5;

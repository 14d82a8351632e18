//! The set-up the lobe integrator's unit tests share: a small view of the stone that reads
//! its tables and its tracer without rendering an image.

use glam::Vec3;

use super::LobeSetup;
use crate::film::SpectralSampler;
use crate::geometry::Camera;
use crate::lights::Environment;

/// An 8 × 8 view straight down at the stone from 100 mm above, 10° wide, one ray a pixel,
/// lit by `environment` alone (no light, no area light), the gloss in full, a black body,
/// seed 1, the trapped reflections not walked, the edges' rays reading back the centres'.
pub(super) fn eight_by_eight<'a>(
    environment: &'a Environment,
    spectral: &'a SpectralSampler,
) -> LobeSetup<'a> {
    LobeSetup {
        camera: Camera::look_at(Vec3::new(0.0, 0.0, 100.0), Vec3::ZERO, Vec3::Y, 10.0, 8, 8),
        width: 8,
        height: 8,
        spp: 1,
        light: None,
        area_light: None,
        light_intensity: 0.0,
        environment,
        gloss: 1.0,
        seed: 1,
        body_reflectance: 0.0,
        spectral,
        trapped: false,
        reuse: true,
    }
}

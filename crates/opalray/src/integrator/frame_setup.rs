//! What a frame of the methods that render the stone model (path, stored, lobe) starts from,
//! set up in one place for all three: the stone and its environment, the camera and the light
//! placed for one light angle, the wavelength sampler, the image's size and the sample seed.

use crate::film::SpectralSampler;
use crate::geometry::Camera;
use crate::lights::{AreaLight, Environment, Lamp};
use crate::render::{camera_up, sample_seed, Prepared, LIGHT_DISC_RADIUS_DEG};
use crate::scene::LightKind;
use crate::stone::Stone;

/// One frame's set-up for a method that renders the stone model
/// ([`Prepared::frame_setup`]).
pub(crate) struct FrameSetup<'a> {
    /// The stone model, built once by `prepare`.
    pub stone: &'a Stone,
    /// Its environment, posed with the camera.
    pub environment: &'a Environment,
    /// The camera in the stone's frame.
    pub camera: Camera,
    /// The scene's directional or point light placed for the light angle (`None` for other
    /// kinds).
    pub light: Option<Lamp>,
    /// The scene's sphere or rect light centred where the point light would be (`None` for
    /// other kinds).
    pub area_light: Option<AreaLight>,
    /// The wavelength sampler and colour matching of the scene's light.
    pub sampler: SpectralSampler,
    /// Image width, pixels.
    pub width: usize,
    /// Image height, pixels.
    pub height: usize,
    /// The gloss's weight (`render.gloss`).
    pub gloss: f32,
    /// The sample seed: the method's `integrator.seed` mixed with `structure.seed`.
    pub seed: u64,
}

impl Prepared {
    /// The set-up of a frame at light angle `light_angle_deg` (degrees, fig. 10) for a method
    /// that renders the stone model: `wavelengths` drawn per contribution, its own
    /// `integrator.seed` as `integrator_seed`. The stone and environment are those
    /// [`Prepared::build_stone`] built.
    pub(crate) fn frame_setup(
        &self,
        light_angle_deg: f64,
        wavelengths: u32,
        integrator_seed: u64,
    ) -> FrameSetup<'_> {
        let s = &self.scene;
        let (Some(stone), Some(environment)) = (&self.stone, &self.environment) else {
            unreachable!("the stone's methods build the stone when prepared")
        };
        let (camera, source) = self.placement(light_angle_deg);
        // A sphere or rect light is an area light centred where the point light would be.
        let light =
            matches!(s.light.kind, LightKind::Directional | LightKind::Point).then_some(Lamp {
                source,
                intensity: s.light.intensity as f32,
                disc_radius_rad: LIGHT_DISC_RADIUS_DEG.to_radians(),
            });
        FrameSetup {
            stone,
            environment,
            camera,
            light,
            area_light: self.area_light(source, camera_up(s)),
            sampler: SpectralSampler::new(s.light.illuminant, &s.spectrum, wavelengths as usize),
            width: s.render.width as usize,
            height: s.render.height as usize,
            gloss: s.render.gloss as f32,
            seed: sample_seed(s.structure.seed, integrator_seed),
        }
    }
}

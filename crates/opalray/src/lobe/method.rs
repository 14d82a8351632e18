//! The lobe integrator as an integrator of the table (`integrator.method = "lobe"`): what it
//! refuses and its frame.

use std::time::Instant;

use crate::error::Result;
use crate::integrator::Integrator;
use crate::path::Passes;
use crate::render::{camera_up, sample_seed, seconds, Frame, Prepared};
use crate::scene::{IntegratorConfig, LobeConfig, Method, Scene, DEFAULT_WAVELENGTHS};
use crate::stone::body::munsell_y;

use super::{render_lobes, LobeSetup};

/// Every Bragg lobe integrated against the lights, deterministic.
pub struct LobeMethod;

impl Integrator for LobeMethod {
    fn method(&self) -> Method {
        Method::Lobe
    }

    /// Every light and the environment: nothing to refuse.
    fn check(&self, _scene: &Scene) -> Result<()> {
        Ok(())
    }

    fn prepare(&self, prepared: &mut Prepared) -> Result<()> {
        prepared.build_stone()
    }

    fn render(&self, prepared: &Prepared, light_angle_deg: f64, _passes: &Passes) -> Frame {
        let s = &prepared.scene;
        let c = match &s.integrator {
            IntegratorConfig::Lobe(c) => c.clone(),
            _ => LobeConfig::default(),
        };
        let (stone, environment) = prepared.stone_inputs();
        let mut times = prepared.times;
        let (camera, source) = prepared.placement(light_angle_deg);
        let sampler = prepared.spectral_sampler(DEFAULT_WAVELENGTHS);
        let setup = LobeSetup {
            camera,
            width: s.render.width as usize,
            height: s.render.height as usize,
            spp: c.spp,
            light: prepared.scene_light(source),
            area_light: prepared.area_light(source, camera_up(s)),
            light_intensity: s.light.intensity as f32,
            environment,
            gloss: s.render.gloss as f32,
            seed: sample_seed(s.structure.seed, c.seed),
            body_reflectance: munsell_y(f64::from(s.render.body_tone)) as f32,
            spectral: &sampler,
        };
        let start = Instant::now();
        let image = render_lobes(stone, &setup);
        times.view_pass = seconds(start);
        prepared.deterministic_frame(times, image.spectral, &image.xyz, &sampler, None)
    }
}

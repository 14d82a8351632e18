//! The lobe integrator as an integrator of the table (`integrator.method = "lobe"`): what it
//! refuses and its frame.

use std::time::Instant;

use crate::error::Result;
use crate::film::DEFAULT_WAVELENGTHS;
use crate::integrator::{Integrator, Passes, Work};
use crate::render::{seconds, Frame, Prepared};
use crate::scene::{IntegratorConfig, LobeConfig, Method, Scene};
use crate::stone::body::munsell_y;

use super::{render_lobes_reporting, LobeSetup};

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

    /// Its camera rays, scaled to the stone ([`super::lobe_factor`]), and each frame's set-up.
    fn work(&self, scene: &Scene, frames: f64) -> Work {
        super::work::work(scene, frames)
    }

    fn prepare(&self, prepared: &mut Prepared) -> Result<()> {
        prepared.build_stone()
    }

    /// Its frame, each row of the view pass reported to `passes.on_rows`.
    fn render(&self, prepared: &Prepared, light_angle_deg: f64, passes: &Passes) -> Frame {
        let s = &prepared.scene;
        let c = match &s.integrator {
            IntegratorConfig::Lobe(c) => c.clone(),
            _ => LobeConfig::default(),
        };
        let mut times = prepared.times;
        let f = prepared.frame_setup(light_angle_deg, DEFAULT_WAVELENGTHS, c.seed);
        let setup = LobeSetup {
            camera: f.camera,
            width: f.width,
            height: f.height,
            spp: c.spp,
            light: f.light,
            area_light: f.area_light,
            light_intensity: s.light.intensity as f32,
            environment: f.environment,
            gloss: f.gloss,
            seed: f.seed,
            body_reflectance: munsell_y(f64::from(s.render.body_tone)) as f32,
            spectral: &f.sampler,
            trapped: c.trapped,
            reuse: true,
        };
        let start = Instant::now();
        let image = render_lobes_reporting(f.stone, &setup, passes);
        times.view_pass = seconds(start);
        prepared.deterministic_frame(times, image.spectral, &image.xyz, &f.sampler, None)
    }
}

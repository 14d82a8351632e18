//! The path tracer as an integrator (`integrator.method = "path"`): it takes every light the
//! scene offers, renders in passes (a time limit, a report after each), and filters its
//! image with `integrator.denoise`.

use std::time::Instant;

use crate::error::Result;
use crate::film::denoise::{denoise, NlMeans};
use crate::integrator::{pixels, Integrator, Passes, Work};
use crate::render::{rgb_of_xyz, seconds, Frame, Prepared};
use crate::scene::{IntegratorConfig, Method, PathConfig, Scene};

use super::{trace_passes, DenoiseBias, PathImage, PathSetup, PathStats, Sampling};

/// Processor seconds of one path-traced sample of one pixel of a gem (the black opal
/// path-traced at 64 × 48 took 1.9 s at 1 and 14.5 s at 8 samples per pixel, 2026-12-06:
/// 580 µs a pixel's sample; the harlequin 300 µs).
const PATH_SAMPLE_CPU_S: f64 = 600e-6;

/// The spectral path tracer on the stone model (the reference).
pub struct PathTracer;

/// The path tracer's settings of `scene` (its defaults under another method).
fn config(scene: &Scene) -> PathConfig {
    match &scene.integrator {
        IntegratorConfig::Path(c) => c.clone(),
        _ => PathConfig::default(),
    }
}

impl Integrator for PathTracer {
    fn method(&self) -> Method {
        Method::Path
    }

    /// Every light and environment; what is refused of them is refused for every method
    /// ([`Scene::validate`]).
    fn check(&self, _scene: &Scene) -> Result<()> {
        Ok(())
    }

    fn renders_in_passes(&self) -> bool {
        true
    }

    /// `"path"`: its samples, passes and noise ([`PathStats`]).
    fn stats_key(&self) -> Option<&'static str> {
        Some("path")
    }

    /// Pixels × `integrator.spp` samples.
    fn work(&self, scene: &Scene, frames: f64) -> Work {
        let spp = f64::from(scene.integrator.spp().unwrap_or(1));
        let samples = pixels(scene, frames) * spp;
        Work {
            samples,
            cpu_s: samples * PATH_SAMPLE_CPU_S,
            ..Work::default()
        }
    }

    fn prepare(&self, prepared: &mut Prepared) -> Result<()> {
        prepared.build_stone()
    }

    /// Its passes, the filter with `integrator.denoise` (timed as colour), and its samples
    /// and noise.
    fn render(&self, prepared: &Prepared, light_angle_deg: f64, passes: &Passes) -> Frame {
        let s = &prepared.scene;
        let c = config(s);
        let mut times = prepared.times;
        let start = Instant::now();
        let (image, m) = prepared.trace_path(light_angle_deg, passes, Sampling::default());
        times.view_pass = seconds(start);
        let (width, height) = (s.render.width as usize, s.render.height as usize);
        let start = Instant::now();
        let denoised = c
            .denoise
            .then(|| denoise(&image, width, height, &NlMeans::default()))
            .flatten();
        let rgb = rgb_of_xyz(
            denoised.as_ref().map_or(&image.xyz, |d| &d.xyz),
            m,
            width,
            height,
        );
        times.color = seconds(start);
        let time_limit_s = passes.time_limit.map(|t| t.as_secs_f64());
        let path = PathStats {
            spp: image.spp,
            target_spp: c.spp,
            passes: image.passes,
            time_limit_s,
            stopped_by_time_limit: time_limit_s.is_some() && image.spp < c.spp,
            noise: image.noise(m),
            denoise_bias: denoised.as_ref().map(|d| DenoiseBias {
                firefly_cut_xyz: d.cut_share,
                bias_xyz: d.bias,
            }),
            denoised: denoised.map(|d| d.noise(&image.on_stone, image.spp, m)),
            bragg_orders: image.bragg_orders,
        };
        Frame {
            spectral: image.spectral,
            rgb,
            times,
            report: Some(Box::new(path)),
        }
    }
}

impl Prepared {
    /// The path integrator's image for light angle `light_angle_deg`, in passes as `passes`
    /// says, its samples the points `sampling` says ([`Sampling::Sobol`] as a frame's), with
    /// the map from its XYZ to the frame's linear RGB (colour space and exposure); `None` for
    /// a scene of another method. The per-pixel variance and half differences it carries are
    /// for statistical comparisons of renders.
    pub fn render_path_image(
        &self,
        light_angle_deg: f64,
        passes: &Passes,
        sampling: Sampling,
    ) -> Option<(PathImage, glam::Mat3)> {
        matches!(self.scene.integrator, IntegratorConfig::Path(_))
            .then(|| self.trace_path(light_angle_deg, passes, sampling))
    }

    /// [`Prepared::render_path_image`] of a path-traced scene.
    fn trace_path(
        &self,
        light_angle_deg: f64,
        passes: &Passes,
        sampling: Sampling,
    ) -> (PathImage, glam::Mat3) {
        let s = &self.scene;
        let c = config(s);
        let f = self.frame_setup(light_angle_deg, c.wavelengths, c.seed);
        let image = trace_passes(
            f.stone,
            &PathSetup {
                camera: f.camera,
                width: f.width,
                height: f.height,
                spp: c.spp,
                max_depth: c.max_depth,
                max_scatterings: c.max_scatterings,
                light: f.light,
                environment: f.environment.clone(),
                area_light: f.area_light,
                gloss: f.gloss,
                seed: f.seed,
                sampling,
                spectral: &f.sampler,
            },
            passes,
        );
        (image, self.display_matrix(f.sampler.white_xyz))
    }
}

//! A rendered frame and what it reports (stage times; its method's own report, a [`Report`]:
//! the path integrator's samples, noise and the denoiser's bias, the stored method's light),
//! and the colour stage every method ends with: XYZ → the scene's linear RGB, adapted to its
//! white and scaled by its exposure.

use std::time::Instant;

use serde::Serialize;

use super::{seconds, Prepared};
use crate::color::RgbImage;
use crate::color::{xyz_to_rgb_adapted, RgbSpace};
use crate::film::SpectralSampler;
use crate::scene::{Method, Scene};
use crate::spectrum::SpectralImage;

/// Seconds spent in each stage (the paper reports the same breakdown).
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct StageTimes {
    /// Growing the cluster structure.
    pub structure: f64,
    /// Building the cluster optics tables.
    pub optics: f64,
    /// Tracing light from the source.
    pub light_pass: f64,
    /// Tracing rays from the camera (including shading the stored light).
    pub view_pass: f64,
    /// Spectrum → RGB (path: with `integrator.denoise`, the filter before it).
    pub color: f64,
}

impl StageTimes {
    /// Sum of all stages.
    pub fn total(&self) -> f64 {
        self.structure + self.optics + self.light_pass + self.view_pass + self.color
    }

    /// `(name, seconds)` for every stage, then `("total", …)`.
    pub fn named(&self) -> [(&'static str, f64); 6] {
        [
            ("structure", self.structure),
            ("optics", self.optics),
            ("light_pass", self.light_pass),
            ("view_pass", self.view_pass),
            ("color", self.color),
            ("total", self.total()),
        ]
    }
}

/// One rendered frame.
#[derive(Clone, Debug)]
pub struct Frame {
    /// The spectral image.
    pub spectral: SpectralImage,
    /// Linear RGB in the scene's colour space.
    pub rgb: RgbImage,
    /// Seconds per stage (structure and optics as prepared).
    pub times: StageTimes,
    /// What its method reports of itself (`None` for a method with nothing to add): the
    /// path integrator's samples and noise (`Frame::path`), the stored method's samples and
    /// stored light (`Frame::stored`), the two passes' energy ledger and void ratio
    /// (`Frame::two_pass`).
    pub report: Option<Box<dyn Report>>,
}

/// What a method reports of a frame beyond its image: its section of the statistics (under
/// its `Integrator::stats_key`), the samples per pixel it rendered and its notes. Its typed
/// form is read back by the method's own accessor on [`Frame`] (`Frame::path`).
pub trait Report: std::any::Any + std::fmt::Debug + Send + Sync {
    /// Its section of the `--stats` JSON and of the Python frame's stats.
    fn to_json(&self) -> serde_json::Value;

    /// Samples per pixel rendered, where it renders samples: a time-limited path tracer's
    /// may stop short of `integrator.spp` (a file's recorded scene takes this, so that it
    /// renders again exactly).
    fn spp(&self) -> Option<u32> {
        None
    }

    /// Record the caller's time limit, seconds (the passes had what the preparation left
    /// of it).
    fn set_time_limit(&mut self, _time_limit_s: Option<f64>) {}

    /// Lines for the terminal after a render of `scene`.
    fn notes(&self, scene: &Scene) -> Vec<String>;

    /// A boxed copy (a [`Frame`] is `Clone`).
    fn clone_box(&self) -> Box<dyn Report>;
}

impl Clone for Box<dyn Report> {
    fn clone(&self) -> Self {
        self.clone_box()
    }
}

impl Frame {
    /// The methods' sections of the statistics: for every method with one
    /// (`Integrator::stats_key`), this frame's report where `method` is that method (the
    /// frame's), else null.
    pub fn method_stats(&self, method: Method) -> serde_json::Map<String, serde_json::Value> {
        crate::integrator::INTEGRATORS
            .iter()
            .filter_map(|i| {
                let key = i.stats_key()?;
                let report = self.report.as_ref().filter(|_| i.method() == method);
                Some((
                    key.to_string(),
                    report.map_or(serde_json::Value::Null, |r| r.to_json()),
                ))
            })
            .collect()
    }

    /// The report, as the type its method made it (`None` for a frame of another method).
    pub fn report_as<T: Report>(&self) -> Option<&T> {
        let report: &dyn std::any::Any = self.report.as_deref()?;
        report.downcast_ref()
    }
}

impl Prepared {
    /// The frame of a method without passes (stored, lobe): its XYZ image `xyz` to the
    /// scene's RGB (timed as colour), and its `spectral` image.
    pub(crate) fn deterministic_frame(
        &self,
        mut times: StageTimes,
        spectral: SpectralImage,
        xyz: &[[f32; 3]],
        sampler: &SpectralSampler,
        report: Option<Box<dyn Report>>,
    ) -> Frame {
        let start = Instant::now();
        let m = self.display_matrix(sampler.white_xyz);
        let (width, height) = (spectral.width, spectral.height);
        let rgb = rgb_of_xyz(xyz, m, width, height);
        times.color = seconds(start);
        Frame {
            spectral,
            rgb,
            times,
            report,
        }
    }

    /// XYZ (relative to the light's white `white_xyz`) → the scene's linear RGB, adapted to
    /// its white and scaled by the exposure.
    pub(crate) fn display_matrix(&self, white_xyz: [f64; 3]) -> glam::Mat3 {
        let s = &self.scene;
        (xyz_to_rgb_adapted(RgbSpace::of(s.color.space), white_xyz)
            * 2f64.powf(s.color.exposure_ev))
        .as_mat3()
    }
}

/// A linear RGB image of the XYZ pixels `xyz` by the matrix `m`.
pub(crate) fn rgb_of_xyz(xyz: &[[f32; 3]], m: glam::Mat3, width: usize, height: usize) -> RgbImage {
    let data = xyz
        .iter()
        .map(|&v| (m * glam::Vec3::from_array(v)).to_array())
        .collect();
    RgbImage {
        width,
        height,
        data,
    }
}

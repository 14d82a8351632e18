//! A rendered frame and what it reports (stage times, the path integrator's samples and
//! noise, the denoiser's bias), and the colour stage every method ends with: XYZ → the scene's
//! linear RGB, adapted to its white and scaled by its exposure.

use std::time::Instant;

use serde::Serialize;

use super::{seconds, Prepared};
use crate::color::RgbImage;
use crate::color::{xyz_to_rgb_adapted, RgbSpace};
use crate::film::{Noise, SpectralSampler};
use crate::light_pass::EnergyLedger;
use crate::path::BraggOrders;
use crate::spectrum::SpectralImage;
use crate::stored::StoredStats;

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
    /// Light rays traced.
    pub light_rays: u64,
    /// The light pass's energy bookkeeping.
    pub ledger: EnergyLedger,
    /// Seconds per stage (structure and optics as prepared).
    pub times: StageTimes,
    /// Void ratio of the paper's grown structure (void cells / inside cells); `None` for
    /// the methods that render the stone model (which do not grow it).
    pub void_ratio: Option<f64>,
    /// The path integrator's samples and noise (`None` for the other methods).
    pub path: Option<PathStats>,
    /// The stored method's samples and stored light (`None` for the other methods).
    pub stored: Option<StoredStats>,
}

/// What the path integrator rendered: its samples, passes and noise.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct PathStats {
    /// Samples per pixel rendered. The image is the same bytes as a render of the same scene
    /// with `integrator.spp` set to this, with or without a time limit.
    pub spp: u32,
    /// Samples per pixel asked for (`integrator.spp`).
    pub target_spp: u32,
    /// Passes rendered.
    pub passes: u32,
    /// The time limit, seconds, if any.
    pub time_limit_s: Option<f64>,
    /// Whether the time limit stopped the render short of `target_spp`.
    pub stopped_by_time_limit: bool,
    /// The image's noise over the stone (`None` below two samples per pixel).
    pub noise: Option<Noise>,
    /// With `integrator.denoise` (and two samples per pixel or more): `Some`, holding the
    /// noise left after the filter as its filtered halves estimate it (blind to its bias).
    pub denoised: Option<Option<Noise>>,
    /// With the filter: the share of the image's X, Y, Z its firefly cut took (and returned
    /// about the fireflies), and its bias in the image's mean X, Y, Z (filtered over raw,
    /// less 1).
    pub denoise_bias: Option<DenoiseBias>,
    /// The share of the stone's luminance per class of path: its Bragg events, whether one
    /// came after an internal reflection, the body, a backing ([`crate::path::orders`]).
    pub bragg_orders: Option<BraggOrders>,
}

/// What the denoiser did to the image's energy and colour ([`crate::denoise::Denoised`]).
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct DenoiseBias {
    /// Share of X, Y, Z the firefly cut took before the filter (returned after it).
    pub firefly_cut_xyz: [f64; 3],
    /// The filtered image's mean X, Y, Z over the raw image's, less 1.
    pub bias_xyz: [f64; 3],
}

impl PathStats {
    /// The `path` section of the `--stats` JSON (and of the Python frame's stats): these
    /// fields, and how to render the same image again.
    pub fn to_json(&self) -> serde_json::Value {
        serde_json::json!({
            "spp": self.spp,
            "target_spp": self.target_spp,
            "passes": self.passes,
            "time_limit_s": self.time_limit_s,
            "stopped_by_time_limit": self.stopped_by_time_limit,
            "deterministic_given_spp": true,
            "same_image_with": format!("--spp {} (integrator.spp)", self.spp),
            "noise": self.noise,
            "denoised": self.denoised.map(|noise| serde_json::json!({
                "noise_estimate": noise,
                "noise_estimate_is": "the filtered halves' difference: the noise left, not the filter's bias",
                "firefly_cut_xyz": self.denoise_bias.map(|b| b.firefly_cut_xyz),
                "bias_xyz": self.denoise_bias.map(|b| b.bias_xyz),
                "bias_is": "filtered over raw mean X, Y, Z, less 1, on the same samples (the firefly cut's and the filter's residual returned about each pixel: zero to rounding)",
            })),
            "bragg_orders": self.bragg_orders.map(|b| b.to_json()),
        })
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
        stored: Option<StoredStats>,
    ) -> Frame {
        let start = Instant::now();
        let m = self.display_matrix(sampler.white_xyz);
        let (width, height) = (spectral.width, spectral.height);
        let rgb = rgb_of_xyz(xyz, m, width, height);
        times.color = seconds(start);
        Frame {
            spectral,
            rgb,
            light_rays: 0,
            ledger: EnergyLedger::default(),
            times,
            void_ratio: None,
            path: None,
            stored,
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

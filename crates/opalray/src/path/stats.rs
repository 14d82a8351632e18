//! What the path tracer reports of a frame ([`PathStats`], the frame's [`Report`]): its
//! samples, passes and noise, and the denoiser's bias; read back with [`Frame::path`].

use serde::Serialize;

use crate::film::Noise;
use crate::render::{Frame, Report};
use crate::scene::Scene;

use super::BraggOrders;

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

impl Report for PathStats {
    fn to_json(&self) -> serde_json::Value {
        PathStats::to_json(self)
    }

    fn spp(&self) -> Option<u32> {
        Some(self.spp)
    }

    fn set_time_limit(&mut self, time_limit_s: Option<f64>) {
        self.time_limit_s = time_limit_s;
    }

    /// Its samples, passes and noise; whether the filter ran and the noise it left.
    fn notes(&self, scene: &Scene) -> Vec<String> {
        let noise = self
            .noise
            .and_then(|n| n.relative_rms)
            .map_or("unknown (one sample per pixel)".to_string(), |n| {
                format!("{:.2} %", 100.0 * n)
            });
        let mut notes = vec![format!(
            "{} samples per pixel in {} passes{} | noise over the stone {noise}",
            self.spp,
            self.passes,
            if self.stopped_by_time_limit {
                " (time limit)"
            } else {
                ""
            }
        )];
        let denoise = scene.integrator.flag("denoise") == Some(true);
        if denoise && self.denoised.is_none() {
            notes.push(
                "not denoised: the filter needs two samples per pixel or more (--spp 2)".into(),
            );
        }
        if let Some(left) = self.denoised {
            let left = left
                .and_then(|n| n.relative_rms)
                .map_or("unknown".into(), |n| format!("{:.2} %", 100.0 * n));
            notes.push(format!(
                "denoised | noise left about {left} (not counting the filter's bias)"
            ));
        }
        notes
    }

    fn clone_box(&self) -> Box<dyn Report> {
        Box::new(*self)
    }
}

impl Frame {
    /// The path integrator's samples and noise (`None` for a frame of another method).
    pub fn path(&self) -> Option<&PathStats> {
        self.report_as()
    }
}

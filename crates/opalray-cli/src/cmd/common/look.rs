//! The flags that override the scene's look (size, method, samples, light, …), shared by
//! `render`, `sweep` and `bench`, and the flag an error of the field they set is named by.

use anyhow::Result;
use opalray::Scene;

/// Flags that override the scene's look, shared by `render`, `sweep` and `bench`.
#[derive(clap::Args, Debug, Clone, Default)]
pub struct LookArgs {
    /// Image width, pixels (render.width).
    #[arg(long, value_name = "PX", allow_hyphen_values = true)]
    pub width: Option<u32>,
    /// Image height, pixels (render.height).
    #[arg(long, value_name = "PX", allow_hyphen_values = true)]
    pub height: Option<u32>,
    /// Silica sphere diameter, nm (crystal.sphere_diameter_nm): ~250 flashes orange face-on,
    /// smaller spheres green and blue.
    #[arg(long, value_name = "NM", allow_hyphen_values = true)]
    pub diameter: Option<f64>,
    /// Wavelength bins over the spectrum's range (spectrum.bins).
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub bins: Option<usize>,
    /// Cells of the light pass's ray lattice: one ray each, 2 × 2 where the light is trapped
    /// near the rim (light.rays).
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub rays: Option<u64>,
    /// Light weaker than this fraction of its ray's power is cut, or plays roulette
    /// (light.cutoff, default 0.02): smaller misses a little less light and costs more.
    #[arg(long, value_name = "F", allow_hyphen_values = true)]
    pub cutoff: Option<f64>,
    /// Russian roulette for light below the cutoff instead of cutting it (light.roulette):
    /// the unbiased estimate, slower and noisier; for reference renders.
    #[arg(long)]
    pub roulette: bool,
    /// Body tone, 1 (N1, black opal) … 9 (N9, white opal) (render.body_tone).
    #[arg(long, value_name = "N")]
    pub body_tone: Option<u8>,
    /// Exposure compensation in stops (color.exposure_ev).
    #[arg(long, value_name = "EV", allow_hyphen_values = true)]
    pub exposure: Option<f64>,
    /// Samples per pixel of the path integrator (integrator.spp): more for smoother edges and
    /// less noise, in proportion to the time; the stored method's camera rays per pixel; the
    /// lobe integrator's rays through each pixel at an edge.
    #[arg(long, value_name = "N", allow_hyphen_values = true)]
    pub spp: Option<u32>,
    /// The renderer (integrator.method): lobe (the gem presets': every Bragg lobe integrated
    /// against the lights, seconds a frame, no noise), path (the reference path tracer: add
    /// --denoise and --spp 8 or more), stored, or two-pass (the paper's).
    #[arg(long, value_name = "NAME", value_parser = clap::builder::PossibleValuesParser::new(
        opalray::scene::Method::ALL.map(opalray::scene::Method::name)
    ))]
    pub method: Option<String>,
    /// Rock the stone: tilt it towards the camera about the picture's horizontal axis,
    /// degrees, the lights staying with the camera (camera.tilt_deg).
    #[arg(long, value_name = "DEG", allow_hyphen_values = true)]
    pub tilt: Option<f64>,
    /// Path integrator: filter the noise after the last pass (integrator.denoise, off unless a
    /// scene sets it): non-local means between the even and the odd samples, about a second
    /// per million pixels; much smoother at a small bias. The spectral image stays unfiltered.
    #[arg(long, conflicts_with = "no_denoise")]
    pub denoise: bool,
    /// Path integrator: leave the image as the samples' mean (integrator.denoise = false):
    /// the unbiased estimate, for comparisons and references.
    #[arg(long)]
    pub no_denoise: bool,
}

impl LookArgs {
    /// Set `integrator.method` from `--method`, if given, keeping the `[integrator]` fields
    /// the new method takes and dropping the others (a file is refused them instead).
    pub fn apply_method(&self, scene: &mut Scene) -> Result<()> {
        if let Some(name) = &self.method {
            let method: opalray::scene::Method = serde_json::from_value(serde_json::json!(name))
                .map_err(|e| anyhow::anyhow!("--method {name}: {e}"))?;
            // The flag keeps the fields the new method takes and drops the others.
            scene.integrator = scene.integrator.switched(method);
        }
        Ok(())
    }

    /// Apply the flags to `scene` and validate the result.
    pub fn apply(&self, scene: &mut Scene) -> Result<()> {
        if let Some(v) = self.width {
            scene.render.width = v;
        }
        if let Some(v) = self.height {
            scene.render.height = v;
        }
        if let Some(v) = self.diameter {
            scene.crystal.sphere_diameter_nm = v;
        }
        if let Some(v) = self.bins {
            scene.spectrum.bins = v;
        }
        if let Some(v) = self.rays {
            scene.light.rays = v;
        }
        if let Some(v) = self.cutoff {
            scene.light.cutoff = v;
        }
        if self.roulette {
            scene.light.roulette = true;
        }
        if let Some(v) = self.body_tone {
            scene.render.body_tone = v;
        }
        if let Some(v) = self.exposure {
            scene.color.exposure_ev = v;
        }
        self.apply_method(scene)?;
        if let Some(v) = self.spp {
            // Checked whatever the method; the paper's two passes take no samples per pixel.
            opalray::scene::check_spp(v).map_err(|err| self.named(err))?;
            scene.integrator.set_spp(v);
        }
        if let Some(v) = self.tilt {
            scene.camera.tilt_deg = v;
        }
        if self.denoise || self.no_denoise {
            // Without the filter there is nothing to switch off.
            if !scene.integrator.set_flag("denoise", self.denoise) && !self.no_denoise {
                return Err(self.named(opalray::Error::field(
                    "integrator.denoise",
                    "filters the path integrator's image only; set integrator.method = \
                     \"path\" (--method path) or drop the flag",
                )));
            }
        }
        opalray::integrator::check(scene).map_err(|err| self.named(err))?;
        Ok(())
    }

    /// `err`, a field the user set with a flag named by that flag.
    fn named(&self, err: opalray::Error) -> anyhow::Error {
        match &err {
            opalray::Error::InvalidField { field, message } => match self.flag_of(field) {
                Some(flag) => anyhow::anyhow!("{flag} ({field}): {message}"),
                None => anyhow::Error::new(err)
                    .context("checking the scene with the command-line flags applied"),
            },
            _ => anyhow::Error::new(err)
                .context("checking the scene with the command-line flags applied"),
        }
    }

    /// The flag that set scene field `field`, if one did.
    fn flag_of(&self, field: &str) -> Option<&'static str> {
        let given = [
            ("render.width", "--width", self.width.is_some()),
            ("render.height", "--height", self.height.is_some()),
            (
                "crystal.sphere_diameter_nm",
                "--diameter",
                self.diameter.is_some(),
            ),
            ("spectrum.bins", "--bins", self.bins.is_some()),
            ("light.rays", "--rays", self.rays.is_some()),
            ("light.cutoff", "--cutoff", self.cutoff.is_some()),
            ("render.body_tone", "--body-tone", self.body_tone.is_some()),
            ("color.exposure_ev", "--exposure", self.exposure.is_some()),
            ("integrator.spp", "--spp", self.spp.is_some()),
            ("integrator.method", "--method", self.method.is_some()),
            ("camera.tilt_deg", "--tilt", self.tilt.is_some()),
            ("integrator.denoise", "--denoise", self.denoise),
        ];
        given
            .iter()
            .find(|(f, _, set)| *set && *f == field)
            .map(|(_, flag, _)| *flag)
    }
}

//! The orchestrator: scene → [`prepare`] (the scene checked, the structure and optics, then
//! what its integrator builds once) → [`Prepared::render`] per light angle (its integrator's
//! frame, through the table in [`crate::integrator`]) → colour, timing every stage. Also the
//! pieces the integrators share: the light and camera placed, the frame, the colour stage.

use std::sync::OnceLock;
use std::time::Instant;

use glam::{Quat, Vec3};
use serde::Serialize;

use crate::color::{illuminant_spectrum, RgbImage};
use crate::color::{xyz_to_rgb_adapted, RgbSpace};
use crate::error::Result;
use crate::film::{Noise, SpectralSampler};
use crate::geometry::Camera;
use crate::light_pass::{EnergyLedger, LightSource, StoneCells};
use crate::lights::{AreaLight, Environment};
use crate::optics::{build_optics, OpticsTables};
use crate::path::{BraggOrders, Passes};
use crate::sampling::mix64;
use crate::scene::{LightKind, Scene};
use crate::spectrum::SpectralImage;
use crate::stone::Stone;
use crate::stored::StoredStats;
use crate::structure::{grow_structure, Structure};

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

/// The light-independent part of a render, computed once and reused for every light angle.
#[derive(Clone, Debug)]
pub struct Prepared {
    /// The scene.
    pub scene: Scene,
    /// The grown structure ([`Prepared::structure`]): grown by `prepare` for the paper's two
    /// passes, on first use for the other methods (which do not read it).
    structure: OnceLock<Structure>,
    /// The cluster optics tables ([`Prepared::optics`]), built as the structure is.
    optics: OnceLock<OpticsTables>,
    /// The stone model of the methods that render it (path, stored, lobe).
    pub stone: Option<std::sync::Arc<Stone>>,
    /// Their environment, its map read and its sampling distribution built (the stored
    /// method's: the backdrop).
    pub environment: Option<Environment>,
    /// Time of the structure and optics stages.
    pub times: StageTimes,
    /// The paper's two passes: the stone's cells, laid out at the first frame and shared by
    /// every later one (a sweep's).
    pub(crate) cells: OnceLock<StoneCells>,
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

/// Seconds since `since`.
pub(crate) fn seconds(since: Instant) -> f64 {
    since.elapsed().as_secs_f64()
}

/// Check `scene` (its fields, then what its method refuses) and build what its integrator
/// reads whatever the light angle: the structure and optics for the paper's two passes, the
/// stone model and environment for the others.
pub fn prepare(scene: &Scene) -> Result<Prepared> {
    crate::integrator::check(scene)?;
    let mut prepared = Prepared {
        scene: scene.clone(),
        structure: OnceLock::new(),
        optics: OnceLock::new(),
        stone: None,
        environment: None,
        times: StageTimes::default(),
        cells: OnceLock::new(),
    };
    prepared.integrator().prepare(&mut prepared)?;
    Ok(prepared)
}

impl Prepared {
    /// The grown structure (paper §2.4): the paper's two passes grow it in `prepare`; for
    /// another method it is grown now, on first use (not timed).
    pub fn structure(&self) -> Result<&Structure> {
        if let Some(structure) = self.structure.get() {
            return Ok(structure);
        }
        let structure = grow_structure(&self.scene.structure)?;
        Ok(self.structure.get_or_init(|| structure))
    }

    /// The cluster optics tables (paper §3.1), built as [`Prepared::structure`] is grown.
    pub fn optics(&self) -> Result<&OpticsTables> {
        if let Some(optics) = self.optics.get() {
            return Ok(optics);
        }
        let optics = build_optics(&self.scene.crystal, &self.scene.spectrum)?;
        Ok(self.optics.get_or_init(|| optics))
    }

    /// The structure to edit before rendering (tests of the passes on a structure made by
    /// hand); the cells laid out from the grown one are dropped.
    pub fn structure_mut(&mut self) -> Result<&mut Structure> {
        self.structure()?;
        self.cells = OnceLock::new();
        Ok(self.structure.get_mut().expect("grown just above"))
    }

    /// The optics tables to edit before rendering (tests: an index-matched furnace).
    pub fn optics_mut(&mut self) -> Result<&mut OpticsTables> {
        self.optics()?;
        Ok(self.optics.get_mut().expect("built just above"))
    }

    /// Grow the structure and build the optics now, timed as their stages: the paper's two
    /// passes' `prepare`.
    pub(crate) fn grow(&mut self) -> Result<()> {
        let start = Instant::now();
        self.structure()?;
        self.times.structure = seconds(start);
        let start = Instant::now();
        self.optics()?;
        self.times.optics = seconds(start);
        Ok(())
    }
}

impl Prepared {
    /// The same stone and optics seen in another pose: `scene`'s tilt, turn and environment
    /// rotation (`camera.tilt_deg`, `camera.turn_deg`, `environment.rotation_deg`) replace
    /// this one's. A sweep of the stone rocked and turned prepares it once.
    pub fn posed(
        &self,
        camera: &crate::scene::CameraConfig,
        rotation_deg: f64,
    ) -> Result<Prepared> {
        let mut posed = self.clone();
        posed.scene.camera = camera.clone();
        posed.scene.environment.rotation_deg = rotation_deg;
        crate::integrator::check(&posed.scene)?;
        posed.environment = posed
            .environment
            .map(|e| e.posed(&posed.scene.environment, &posed.scene.camera));
        Ok(posed)
    }
}

/// Render `scene` end to end.
pub fn render(scene: &Scene) -> Result<Frame> {
    let prepared = prepare(scene)?;
    Ok(prepared.render(scene.light.angle_deg))
}

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

    /// The frame for light angle `light_angle_deg`, by the scene's integrator.
    pub fn render(&self, light_angle_deg: f64) -> Frame {
        self.render_progressive(light_angle_deg, &Passes::default())
    }

    /// [`Prepared::render`], the path integrator's passes as `passes` says (a time limit, a
    /// report after each pass); the other methods ignore `passes`.
    pub fn render_progressive(&self, light_angle_deg: f64, passes: &Passes) -> Frame {
        self.integrator().render(self, light_angle_deg, passes)
    }

    /// [`Prepared::render_progressive`] under `cancel` (see [`crate::cancel`]): the frame, or
    /// [`Error::Cancelled`](crate::error::Error::Cancelled) soon after `cancel` is set from
    /// another thread (the rows, tiles and passes not yet begun are skipped).
    pub fn render_cancellable(
        &self,
        light_angle_deg: f64,
        passes: &Passes,
        cancel: &crate::cancel::Cancel,
    ) -> Result<Frame> {
        let frame = cancel.scope(|| self.render_progressive(light_angle_deg, passes));
        cancel.check()?;
        Ok(frame)
    }

    /// The scene's integrator.
    pub fn integrator(&self) -> &'static dyn crate::integrator::Integrator {
        crate::integrator::of(self.scene.integrator.method())
    }

    /// Build the stone model and the environment (timed as structure and light pass): the
    /// inputs of the methods that render the stone.
    pub(crate) fn build_stone(&mut self) -> Result<()> {
        let scene = &self.scene;
        let start = Instant::now();
        let stone = Stone::new(scene)?;
        self.times.structure += seconds(start);
        // The lights are built once, for every frame: timed as the light pass.
        let start = Instant::now();
        let environment = Environment::new(&scene.environment, scene.render.background as f32)?
            .posed(&scene.environment, &scene.camera);
        self.times.light_pass = seconds(start);
        self.stone = Some(std::sync::Arc::new(stone));
        self.environment = Some(environment);
        Ok(())
    }

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

/// The path integrator's sample seed: `integrator.seed` mixed with `structure.seed`, so that
/// either changes every sample stream.
pub(crate) fn sample_seed(structure_seed: u64, integrator_seed: u64) -> u64 {
    mix64(structure_seed ^ mix64(integrator_seed))
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{preset, IntegratorConfig, Method};

    /// `name` at 8 × 6.
    fn tiny(name: &str) -> Scene {
        let mut scene = preset(name).unwrap();
        scene.render.width = 8;
        scene.render.height = 6;
        scene
    }

    #[test]
    fn each_method_prepares_only_what_it_reads() {
        // The stone's methods grow no cell grid and build no optics tables.
        for method in [Method::Path, Method::Stored, Method::Lobe] {
            let mut scene = tiny("paper");
            scene.integrator = IntegratorConfig::of(method);
            let prepared = prepare(&scene).unwrap();
            assert!(prepared.stone.is_some(), "{method:?}");
            assert!(prepared.structure.get().is_none(), "{method:?}");
            assert!(prepared.optics.get().is_none(), "{method:?}");
            assert_eq!(prepared.render(30.0).void_ratio, None, "{method:?}");
        }
        // The paper's two passes build no stone model.
        let prepared = prepare(&tiny("paper")).unwrap();
        assert!(prepared.stone.is_none() && prepared.environment.is_none());
        assert!(prepared.structure.get().is_some() && prepared.cells.get().is_some());
    }

    #[test]
    fn a_structure_asked_of_a_stone_method_is_the_two_passes_one() {
        let two_pass = prepare(&tiny("paper")).unwrap();
        let mut scene = tiny("paper");
        scene.integrator = IntegratorConfig::of(Method::Lobe);
        let lobe = prepare(&scene).unwrap();
        let (a, b) = (two_pass.structure().unwrap(), lobe.structure().unwrap());
        assert_eq!(a.cells, b.cells);
        assert_eq!(a.stats.void_ratio, b.stats.void_ratio);
        let (a, b) = (two_pass.optics().unwrap(), lobe.optics().unwrap());
        assert_eq!(a.reflectance, b.reflectance);
    }
}

//! The orchestrator: the only module that knows the whole chain
//! scene → structure → optics → light pass → view pass → colour, timing every stage.

use std::time::Instant;

use glam::{Quat, Vec3};
use serde::Serialize;

use crate::color::{illuminant_spectrum, to_rgb, RgbImage};
use crate::color::{xyz_to_rgb_adapted, RgbSpace};
use crate::denoise::{denoise, NlMeans};
use crate::error::Result;
use crate::geometry::Camera;
use crate::light_pass::{
    trace_light, ClusterOptics, EnergyLedger, LightField, LightSetup, LightSource, StoneCells,
    Termination,
};
use crate::lights::{AreaLight, Environment};
use crate::lobe::{render_lobes, LobeSetup};
use crate::optics::{build_optics, OpticsTables};
use crate::path::{trace_passes, Noise, Passes, PathImage, PathLight, PathSetup, SpectralSampler};
use crate::sampling::mix64;
use crate::scene::{LightKind, Method, Scene, BODY_EXTINCTION_PER_MM};
use crate::spectrum::SpectralImage;
use crate::stone::body::munsell_y;
use crate::stone::Stone;
use crate::stored::{gather_view, store_light, StoredSetup, StoredStats};
use crate::structure::{grow_structure, Structure};
use crate::view_pass::{trace_view, Shading, ViewSetup};

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
    /// The grown structure.
    pub structure: Structure,
    /// The cluster optics tables.
    pub optics: OpticsTables,
    /// The stone model of the path integrator and the stored method (`integrator.method =
    /// "path"` or `"stored"`).
    pub stone: Option<std::sync::Arc<Stone>>,
    /// The path integrator's environment, its map read and its sampling distribution built
    /// (the stored method's: the backdrop).
    pub environment: Option<Environment>,
    /// Time of the structure and optics stages.
    pub times: StageTimes,
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
    /// Void ratio of the structure (void cells / inside cells).
    pub void_ratio: f64,
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
                "bias_is": "filtered over raw mean X, Y, Z, less 1, on the same samples (the firefly cut's light returned about the fireflies)",
            })),
        })
    }
}

fn seconds(since: Instant) -> f64 {
    since.elapsed().as_secs_f64()
}

/// Grow the structure and build the optics of `scene` (validated first).
pub fn prepare(scene: &Scene) -> Result<Prepared> {
    scene.validate()?;
    let mut times = StageTimes::default();
    let start = Instant::now();
    let structure = grow_structure(&scene.structure)?;
    times.structure = seconds(start);
    let start = Instant::now();
    let optics = build_optics(&scene.crystal, &scene.spectrum)?;
    times.optics = seconds(start);
    let (stone, environment) = match scene.integrator.method {
        Method::TwoPass => (None, None),
        Method::Path | Method::Stored | Method::Lobe => {
            let start = Instant::now();
            let stone = Stone::new(scene)?;
            times.structure += seconds(start);
            // The lights are built once, for every frame: timed as the light pass.
            let start = Instant::now();
            let environment = Environment::new(&scene.environment, scene.render.background as f32)?
                .posed(&scene.environment, &scene.camera);
            times.light_pass = seconds(start);
            (Some(std::sync::Arc::new(stone)), Some(environment))
        }
    };
    Ok(Prepared {
        scene: scene.clone(),
        structure,
        optics,
        stone,
        environment,
        times,
    })
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
        posed.scene.validate()?;
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

    /// Light pass, view pass and colour for one light angle. (Laying out the stone's cells
    /// for the passes is timed with the light pass.)
    pub fn render(&self, light_angle_deg: f64) -> Frame {
        self.render_progressive(light_angle_deg, &Passes::default())
    }

    /// [`Prepared::render`], the path integrator's passes as `passes` says (a time limit, a
    /// report after each pass); the two passes ignore `passes`.
    pub fn render_progressive(&self, light_angle_deg: f64, passes: &Passes) -> Frame {
        if let (Some(stone), Some(environment)) = (&self.stone, &self.environment) {
            match self.scene.integrator.method {
                Method::Stored => return self.render_stored(stone, environment, light_angle_deg),
                Method::Lobe => return self.render_lobe(stone, environment, light_angle_deg),
                _ => {}
            }
            return self.render_path(stone, environment, light_angle_deg, passes);
        }
        let start = Instant::now();
        let cells = StoneCells::new(&self.structure);
        let layout = seconds(start);
        let mut frame = self.render_in(&cells, light_angle_deg);
        frame.times.light_pass += layout;
        frame
    }

    /// [`Prepared::render`] with the stone's cells laid out once, for many frames (a sweep):
    /// `cells` must be [`StoneCells::new`] of this structure.
    pub fn render_in(&self, cells: &StoneCells, light_angle_deg: f64) -> Frame {
        if self.stone.is_some() {
            return self.render_progressive(light_angle_deg, &Passes::default());
        }
        let s = &self.scene;
        let mut times = self.times;
        let (camera, source) = self.placement(light_angle_deg);
        let spectrum = self.light_spectrum();
        let body_albedo = s.render.body_albedo();

        let start = Instant::now();
        let mut light = self.trace_light_in(cells, source, &spectrum);
        times.light_pass = seconds(start);

        let start = Instant::now();
        let phong_exponent = s.render.phong_exponent as f32;
        let shading = Shading::new(
            &self.structure,
            cells,
            &ClusterOptics::new(&self.optics),
            &light,
            phong_exponent,
            body_albedo,
        );
        // The shading holds what the view pass needs of the stored spectra; freeing them
        // before the image is allocated keeps the peak memory down.
        light.fluence = Vec::new();
        let spectral = trace_view(
            &self.structure,
            &self.optics,
            &light,
            &shading,
            &ViewSetup {
                camera,
                width: s.render.width as usize,
                height: s.render.height as usize,
                source,
                light_spectrum: &spectrum,
                phong_exponent,
                gloss: s.render.gloss as f32,
                background: s.render.background as f32,
                body_extinction_per_mm: BODY_EXTINCTION_PER_MM,
                reflection_block: s.render.reflection_block as usize,
            },
        );
        times.view_pass = seconds(start);

        let start = Instant::now();
        let rgb = to_rgb(&spectral, &s.color, s.light.illuminant);
        times.color = seconds(start);
        Frame {
            spectral,
            rgb,
            light_rays: light.ledger.rays,
            ledger: light.ledger,
            times,
            void_ratio: self.structure.stats.void_ratio,
            path: None,
            stored: None,
        }
    }
}

impl Prepared {
    /// The light pass alone (paper §3.2) for light angle `light_angle_deg`: the light stored
    /// in every inside cell, as the view pass of [`Prepared::render_in`] would receive it.
    /// `cells` must be [`StoneCells::new`] of this structure. Defined for the two passes
    /// only: with `integrator.method = "path"` there is no stored light, and the result is
    /// that of the same scene's two passes.
    pub fn light_pass_in(&self, cells: &StoneCells, light_angle_deg: f64) -> LightField {
        let (_, source) = self.placement(light_angle_deg);
        self.trace_light_in(cells, source, &self.light_spectrum())
    }

    /// [`trace_light`] with this scene's light settings, from `source` with `spectrum`.
    fn trace_light_in(
        &self,
        cells: &StoneCells,
        source: LightSource,
        spectrum: &[f32],
    ) -> LightField {
        let s = &self.scene;
        trace_light(
            &self.structure,
            cells,
            &self.optics,
            &LightSetup {
                source,
                spectrum,
                rays: s.light.rays,
                seed: s.structure.seed,
                body_albedo: s.render.body_albedo(),
                body_extinction_per_mm: BODY_EXTINCTION_PER_MM,
                termination: Termination::of(s.light.cutoff, s.light.roulette),
            },
        )
    }

    /// The path integrator's frame for light angle `light_angle_deg`.
    fn render_path(
        &self,
        stone: &Stone,
        environment: &Environment,
        light_angle_deg: f64,
        passes: &Passes,
    ) -> Frame {
        let s = &self.scene;
        let mut times = self.times;
        let start = Instant::now();
        let (image, m) = self.trace_path(stone, environment, light_angle_deg, passes);
        times.view_pass = seconds(start);
        let (width, height) = (s.render.width as usize, s.render.height as usize);
        let start = Instant::now();
        let denoised = s
            .integrator
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
            target_spp: s.integrator.spp,
            passes: image.passes,
            time_limit_s,
            stopped_by_time_limit: time_limit_s.is_some() && image.spp < s.integrator.spp,
            noise: image.noise(m),
            denoise_bias: denoised.as_ref().map(|d| DenoiseBias {
                firefly_cut_xyz: d.cut_share,
                bias_xyz: d.bias,
            }),
            denoised: denoised.map(|d| d.noise(&image.on_stone, image.spp, m)),
        };
        Frame {
            spectral: image.spectral,
            rgb,
            light_rays: 0,
            ledger: EnergyLedger::default(),
            times,
            void_ratio: self.structure.stats.void_ratio,
            path: Some(path),
            stored: None,
        }
    }

    /// The stored method's frame for light angle `light_angle_deg`: the light pass timed as
    /// such, the view pass as such.
    fn render_stored(
        &self,
        stone: &Stone,
        environment: &Environment,
        light_angle_deg: f64,
    ) -> Frame {
        let s = &self.scene;
        let mut times = self.times;
        let (camera, source) = self.placement(light_angle_deg);
        let sampler = self.spectral_sampler();
        let setup = StoredSetup {
            camera,
            width: s.render.width as usize,
            height: s.render.height as usize,
            spp: s.integrator.spp,
            light: PathLight {
                source,
                intensity: s.light.intensity as f32,
                disc_radius_rad: LIGHT_DISC_RADIUS_DEG.to_radians(),
            },
            environment,
            gloss: s.render.gloss as f32,
            seed: sample_seed(s.structure.seed, s.integrator.seed),
            cell_mm: s.integrator.cell_mm,
            spectral: &sampler,
        };
        let start = Instant::now();
        let light = store_light(stone, &setup);
        times.light_pass += seconds(start);
        let start = Instant::now();
        let image = gather_view(stone, &light, &setup);
        times.view_pass = seconds(start);
        let stats = StoredStats {
            spp: setup.spp,
            light: light.stats(),
        };
        self.deterministic_frame(times, image.spectral, &image.xyz, &sampler, Some(stats))
    }

    /// The frame of a method without passes (stored, lobe): its XYZ image `xyz` to the
    /// scene's RGB (timed as colour), and its `spectral` image.
    fn deterministic_frame(
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
            void_ratio: self.structure.stats.void_ratio,
            path: None,
            stored,
        }
    }

    /// The wavelength sampler and colour matching of this scene's light.
    fn spectral_sampler(&self) -> SpectralSampler {
        let s = &self.scene;
        SpectralSampler::new(
            s.light.illuminant,
            &s.spectrum,
            s.integrator.wavelengths as usize,
        )
    }

    /// The scene's directional or point light at `source` for the stone model's methods
    /// (`None` for other kinds: a sphere or rect light is an [`AreaLight`]).
    fn scene_light(&self, source: LightSource) -> Option<PathLight> {
        let s = &self.scene;
        matches!(s.light.kind, LightKind::Directional | LightKind::Point).then_some(PathLight {
            source,
            intensity: s.light.intensity as f32,
            disc_radius_rad: LIGHT_DISC_RADIUS_DEG.to_radians(),
        })
    }

    /// The lobe integrator's frame for light angle `light_angle_deg`.
    fn render_lobe(&self, stone: &Stone, environment: &Environment, light_angle_deg: f64) -> Frame {
        let s = &self.scene;
        let mut times = self.times;
        let (camera, source) = self.placement(light_angle_deg);
        let sampler = self.spectral_sampler();
        let light = self.scene_light(source);
        let area_light = self.area_light(source, camera_up(s));
        let setup = LobeSetup {
            camera,
            width: s.render.width as usize,
            height: s.render.height as usize,
            spp: s.integrator.spp,
            light,
            area_light,
            light_intensity: s.light.intensity as f32,
            environment,
            gloss: s.render.gloss as f32,
            seed: sample_seed(s.structure.seed, s.integrator.seed),
            body_reflectance: munsell_y(f64::from(s.render.body_tone)) as f32,
            spectral: &sampler,
        };
        let start = Instant::now();
        let image = render_lobes(stone, &setup);
        times.view_pass = seconds(start);
        self.deterministic_frame(times, image.spectral, &image.xyz, &sampler, None)
    }

    /// The path integrator's image for light angle `light_angle_deg`, in passes as `passes`
    /// says, with the map from its XYZ to the frame's linear RGB (colour space and exposure);
    /// `None` for the two passes. The per-pixel variance and half differences it carries are
    /// for statistical comparisons of renders.
    pub fn render_path_image(
        &self,
        light_angle_deg: f64,
        passes: &Passes,
    ) -> Option<(PathImage, glam::Mat3)> {
        let stone = self.stone.as_ref()?;
        let environment = self.environment.as_ref()?;
        Some(self.trace_path(stone, environment, light_angle_deg, passes))
    }

    /// [`Prepared::render_path_image`] of `stone`.
    fn trace_path(
        &self,
        stone: &Stone,
        environment: &Environment,
        light_angle_deg: f64,
        passes: &Passes,
    ) -> (PathImage, glam::Mat3) {
        let s = &self.scene;
        let (camera, source) = self.placement(light_angle_deg);
        let sampler = self.spectral_sampler();
        let light = self.scene_light(source);
        let area_light = self.area_light(source, camera_up(s));
        let image = trace_passes(
            stone,
            &PathSetup {
                camera,
                width: s.render.width as usize,
                height: s.render.height as usize,
                spp: s.integrator.spp,
                max_depth: s.integrator.max_depth,
                light,
                environment: environment.clone(),
                area_light,
                gloss: s.render.gloss as f32,
                seed: sample_seed(s.structure.seed, s.integrator.seed),
                spectral: &sampler,
            },
            passes,
        );
        (image, self.display_matrix(sampler.white_xyz))
    }

    /// XYZ (relative to the light's white `white_xyz`) → the scene's linear RGB, adapted to
    /// its white and scaled by the exposure.
    fn display_matrix(&self, white_xyz: [f64; 3]) -> glam::Mat3 {
        let s = &self.scene;
        (xyz_to_rgb_adapted(RgbSpace::of(s.color.space), white_xyz)
            * 2f64.powf(s.color.exposure_ev))
        .as_mat3()
    }
}

/// A linear RGB image of the XYZ pixels `xyz` by the matrix `m`.
fn rgb_of_xyz(xyz: &[[f32; 3]], m: glam::Mat3, width: usize, height: usize) -> RgbImage {
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
fn sample_seed(structure_seed: u64, integrator_seed: u64) -> u64 {
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
fn camera_up(s: &Scene) -> Vec3 {
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

    #[test]
    fn light_pass_in_is_the_light_the_render_stores() {
        let (prepared, cells) = StoneCells::of_default_scene([24, 18, 6]);
        let light = prepared.light_pass_in(&cells, -20.0);
        let frame = prepared.render_in(&cells, -20.0);
        assert_eq!(light.ledger, frame.ledger);
        assert_eq!(light.slot_of_cell, cells.slot_of_cell);
        let bins = prepared.optics.grid.bins;
        assert_eq!(
            light.fluence.len(),
            cells.slots() * crate::light_pass::LOBES * (bins + 4)
        );
    }
}

//! The orchestrator: the only module that knows the whole chain
//! scene → structure → optics → light pass → view pass → colour, timing every stage.

use std::time::Instant;

use glam::{Quat, Vec3};
use serde::Serialize;

use crate::color::{illuminant_spectrum, to_rgb, RgbImage};
use crate::color::{xyz_to_rgb_adapted, RgbSpace};
use crate::error::Result;
use crate::geometry::Camera;
use crate::light_pass::{
    trace_light, ClusterOptics, EnergyLedger, LightSetup, LightSource, StoneCells, Termination,
};
use crate::optics::{build_optics, OpticsTables};
use crate::path::{trace_paths, AreaLight, Environment, PathLight, PathSetup, SpectralSampler};
use crate::scene::{LightKind, Method, Scene, BODY_EXTINCTION_PER_MM};
use crate::spectrum::SpectralImage;
use crate::stone::Stone;
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
    /// Spectrum → RGB.
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
    /// The stone model of the path integrator (`integrator.method = "path"`).
    pub stone: Option<std::sync::Arc<Stone>>,
    /// The path integrator's environment, its map read and its sampling distribution built.
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
        Method::Path => {
            let start = Instant::now();
            let stone = Stone::new(scene)?;
            times.structure += seconds(start);
            // The lights are built once, for every frame: timed as the light pass.
            let start = Instant::now();
            let environment = Environment::new(&scene.environment, scene.render.background as f32)?;
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
        let to_opal = Quat::from_rotation_x(-(s.camera.tilt_deg as f32).to_radians());
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
        if let (Some(stone), Some(environment)) = (&self.stone, &self.environment) {
            return self.render_path(stone, environment, light_angle_deg);
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
        if let (Some(stone), Some(environment)) = (&self.stone, &self.environment) {
            return self.render_path(stone, environment, light_angle_deg);
        }
        let s = &self.scene;
        let mut times = self.times;
        let (camera, source) = self.placement(light_angle_deg);
        let spectrum = self.light_spectrum();
        let body_albedo = s.render.body_albedo();

        let start = Instant::now();
        let mut light = trace_light(
            &self.structure,
            cells,
            &self.optics,
            &LightSetup {
                source,
                spectrum: &spectrum,
                rays: s.light.rays,
                seed: s.structure.seed,
                body_albedo,
                body_extinction_per_mm: BODY_EXTINCTION_PER_MM,
                termination: Termination::of(s.light.cutoff, s.light.roulette),
            },
        );
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
        }
    }
}

impl Prepared {
    /// The path integrator's frame for light angle `light_angle_deg`.
    fn render_path(&self, stone: &Stone, environment: &Environment, light_angle_deg: f64) -> Frame {
        let s = &self.scene;
        let mut times = self.times;
        let (camera, source) = self.placement(light_angle_deg);
        let start = Instant::now();
        let sampler = SpectralSampler::new(
            s.light.illuminant,
            &s.spectrum,
            s.integrator.wavelengths as usize,
        );
        let light = matches!(s.light.kind, LightKind::Directional | LightKind::Point).then_some(
            PathLight {
                source,
                intensity: s.light.intensity as f32,
                disc_radius_rad: LIGHT_DISC_RADIUS_DEG.to_radians(),
            },
        );
        let area_light = self.area_light(source, camera_up(s));
        let image = trace_paths(
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
                seed: s.structure.seed,
                spectral: &sampler,
            },
        );
        times.view_pass = seconds(start);
        let start = Instant::now();
        let m = xyz_to_rgb_adapted(RgbSpace::of(s.color.space), sampler.white_xyz)
            * 2f64.powf(s.color.exposure_ev);
        let m = m.as_mat3();
        let data = image
            .xyz
            .iter()
            .map(|&v| (m * glam::Vec3::from_array(v)).to_array())
            .collect();
        let rgb = RgbImage {
            width: s.render.width as usize,
            height: s.render.height as usize,
            data,
        };
        times.color = seconds(start);
        Frame {
            spectral: image.spectral,
            rgb,
            light_rays: 0,
            ledger: EnergyLedger::default(),
            times,
            void_ratio: self.structure.stats.void_ratio,
        }
    }
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
    Quat::from_rotation_x(-(s.camera.tilt_deg as f32).to_radians()) * Vec3::Y
}

/// Angular radius of the scene light's disc as the path integrator's gloss shows it, degrees
/// (a small lamp or the sun: 0.5°).
pub const LIGHT_DISC_RADIUS_DEG: f32 = 0.5;

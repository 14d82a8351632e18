//! The environment: radiance from every direction, built in or read from a map, and its
//! importance sampling.
//!
//! The environment's zenith is +z, the side of the stone's broad face where the camera
//! stands (a gem photographed from above, lying on a table); `rotation_deg` turns it about that
//! axis (counter-clockwise seen from above). Values are in the image's units (π × radiance,
//! relative to the light's spectrum): a white diffuser facing an emitter of value 1 that fills
//! its view shows 1.
//!
//! - `studio`: a softbox 50° from the zenith towards the top of the picture (+y), 22° in
//!   angular radius, value 1; two strip lights low at the left and right (15° × 60°, value
//!   0.8 and 0.5); a dark room (0.004) and a black velvet table (0.0004).
//! - `window`: a window 50° wide and 40° high, 20–60° above the horizon towards −x and +y,
//!   value 1, in a room of 0.04 over a floor of 0.02.
//! - `overcast`: the CIE overcast sky, `(1 + 2 sin h)/3` at elevation h, over ground of 0.1.
//! - `tent`: a light tent, the diffuse white dome gem photographers put over a stone: value 1
//!   from 10° above the horizon to the zenith but for the camera's port (a dark disc 6° in
//!   radius about the zenith, 0.004), its hem (0–10° above the horizon) 0.3, over black
//!   velvet (0.0004).
//! - `uniform`: 1 everywhere (a furnace).
//! - `none`: black, but for the backdrop (`render.background`) behind the stone (z < 0).
//! - `file`: an equirectangular (latitude–longitude) map ([`env_map`](super::env_map)), twice
//!   as wide as high. Row 0 looks at the zenith (+z), the last row at the nadir; the centre
//!   column looks towards +y (the top of the picture), and the picture's right runs clockwise
//!   seen from above (towards +x, then −y at the edges): pixel `(u, v)` ∈ [0, 1)² looks along
//!   θ = π v from +z, azimuth φ = 3π/2 − 2π u from +x. A pixel's value is its luminance Y
//!   (nearest pixel, no filtering) times `intensity`: the map's colour beyond its luminance
//!   is not used (the light's spectrum, `light.illuminant`, colours every emitter).
//!
//! **Sampling.** A piecewise-constant density over the equirectangular square (pbrt-v4
//! §12.5.2): a marginal over rows and a conditional over each row's columns, the weight of
//! a texel its value (plus a floor of 1 % of the mean) times sin θ at its centre; the
//! density per steradian is `p(u, v) / (2π² sin θ)`. A map's raster is the map itself; a
//! built-in environment is rasterised on [`BUILT_IN_GRID`] texels, each the mean of
//! [`BUILT_IN_SUBSAMPLES`]² values, while its value stays analytic: the floor keeps the
//! density positive wherever the value is, so an estimate `value / pdf` stays unbiased.

use std::f64::consts::PI;
use std::sync::Arc;

use glam::{DQuat, DVec3, Vec3};

use super::env_map::{read_map, LuminanceMap};
use crate::error::{Error, Result};
use crate::sampling::distribution::Distribution2D;
use crate::scene::{CameraConfig, EnvironmentConfig, EnvironmentKind};

mod built_in;
pub(crate) mod filter;
#[cfg(test)]
mod tests;

use built_in::{SOFTBOX_AXIS, SOFTBOX_RADIUS_DEG, TENT_PORT_RADIUS_DEG};

/// Texels (width, height) of a built-in environment's sampling raster.
pub const BUILT_IN_GRID: (usize, usize) = (256, 128);
/// Values per texel side when a built-in environment is rasterised (4 × 4 a texel).
pub const BUILT_IN_SUBSAMPLES: usize = 4;
/// Floor of every texel's sampling weight, relative to the mean value over the sphere.
const FLOOR: f64 = 0.01;

/// An environment ready to be looked up and sampled. Cheap to clone (the map and its
/// distribution are shared).
#[derive(Clone)]
pub struct Environment {
    kind: EnvironmentKind,
    intensity: f32,
    /// The turn from the stone's frame into the environment's.
    to_env: DQuat,
    background: f32,
    map: Option<Arc<LuminanceMap>>,
    /// A map's mip chain (each level the 2 × 2 means of the one before), for
    /// [`Environment::filtered`].
    mips: Arc<Vec<LuminanceMap>>,
    distribution: Arc<Distribution2D>,
    /// The brightest texel's value ([`Environment::peak`]).
    peak: f32,
}

impl std::fmt::Debug for Environment {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Environment")
            .field("kind", &self.kind)
            .field("intensity", &self.intensity)
            .field("map", &self.map.as_ref().map(|m| (m.width, m.height)))
            .field("raster", &self.distribution.size())
            .finish()
    }
}

/// A direction drawn from the environment.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EnvSample {
    /// Unit direction towards the environment, in the stone's frame.
    pub direction: Vec3,
    /// [`Environment::value`] along it.
    pub value: f32,
    /// Density per steradian it was drawn with (0: a degenerate draw at a pole; skip it).
    pub pdf: f32,
}

impl Environment {
    /// The environment of `config`; `background` is the backdrop of `none`. A `file`
    /// environment reads `config.path` (taken as it is: see [`crate::Scene::resolve_paths`]);
    /// a missing, unreadable or not equirectangular file is an error naming
    /// `environment.path`.
    pub fn new(config: &EnvironmentConfig, background: f32) -> Result<Self> {
        let map = if config.kind == EnvironmentKind::File {
            Some(load_map(&config.path)?)
        } else {
            None
        };
        Ok(Self::of(config, background, map))
    }

    /// The uniform environment of value 1 in every direction, unturned: a furnace, in which
    /// a lossless stone shows 1 wherever it is seen.
    pub fn uniform() -> Self {
        let config = EnvironmentConfig {
            kind: EnvironmentKind::Uniform,
            ..EnvironmentConfig::default()
        };
        Self::of(&config, 0.0, None)
    }

    /// The environment of `config` (its map `map`, read, for a `file` one): its sampling
    /// raster and distribution built.
    fn of(config: &EnvironmentConfig, background: f32, map: Option<LuminanceMap>) -> Self {
        let mut env = Environment {
            kind: config.kind,
            intensity: config.intensity as f32,
            to_env: DQuat::from_rotation_z(-config.rotation_deg.to_radians()),
            background,
            map: None,
            mips: Arc::new(Vec::new()),
            distribution: Arc::new(Distribution2D::new(&[1.0], 1, 1)),
            peak: 0.0,
        };
        let (weights, width, height) = if let Some(map) = map {
            let weights = map.luminance.clone();
            let (w, h) = (map.width, map.height);
            env.mips = Arc::new(filter::mip_chain(&map));
            env.map = Some(Arc::new(map));
            (weights, w, h)
        } else {
            (env.rasterise(), BUILT_IN_GRID.0, BUILT_IN_GRID.1)
        };
        // A map's raster is its luminance; a built-in's holds the intensity already.
        let scale = if env.map.is_some() {
            env.intensity
        } else {
            1.0
        };
        env.peak = weights.iter().fold(0.0f32, |m, &v| m.max(v)) * scale;
        env.distribution = Arc::new(sampling_distribution(weights, width, height));
        env
    }

    /// The environment turned by `config.rotation_deg` and seen from a stone turned by
    /// `camera.turn_deg` about its face's normal (z), then tilted by `camera.tilt_deg` about
    /// the picture's horizontal axis (x): the room turns with the camera, as the point light
    /// does, so moving the camera is moving the stone under fixed lights. Replaces any
    /// earlier pose.
    pub fn posed(mut self, config: &EnvironmentConfig, camera: &CameraConfig) -> Self {
        self.to_env = DQuat::from_rotation_z(-config.rotation_deg.to_radians())
            * DQuat::from_rotation_x(camera.tilt_deg.to_radians())
            * DQuat::from_rotation_z(camera.turn_deg.to_radians());
        self
    }

    /// The brightest value over its sampling raster: a map's brightest pixel, a built-in's
    /// brightest texel (the mean of its subsamples).
    pub fn peak(&self) -> f32 {
        self.peak
    }

    /// Value seen looking along `dir` (unit, in the stone's frame).
    pub fn value(&self, dir: Vec3) -> f32 {
        let d = (self.to_env * dir.as_dvec3()).as_vec3();
        if let Some(map) = &self.map {
            let [u, v] = square_of(d.as_dvec3());
            let column = ((u * map.width as f64) as usize).min(map.width - 1);
            let row = ((v * map.height as f64) as usize).min(map.height - 1);
            return map.luminance[row * map.width + column] * self.intensity;
        }
        self.built_in(d, dir)
    }

    /// A direction drawn with `u ∈ [0, 1)²` in proportion to the sampling raster.
    pub fn sample(&self, u: [f32; 2]) -> EnvSample {
        let ([x, y], density) = self.distribution.sample([f64::from(u[0]), f64::from(u[1])]);
        let d = direction_of([x, y]);
        let sin_theta = (PI * y).sin();
        let direction = (self.to_env.inverse() * d).normalize().as_vec3();
        let pdf = if sin_theta > 1e-9 {
            (density / (2.0 * PI * PI * sin_theta)) as f32
        } else {
            0.0
        };
        EnvSample {
            direction,
            value: self.value(direction),
            pdf,
        }
    }

    /// The density per steradian with which [`Environment::sample`] draws `dir` (unit).
    pub fn pdf(&self, dir: Vec3) -> f32 {
        let d = self.to_env * dir.as_dvec3();
        let [u, v] = square_of(d);
        let sin_theta = (d.x * d.x + d.y * d.y).sqrt() / d.length();
        if sin_theta > 1e-9 {
            (self.distribution.density(u, v) / (2.0 * PI * PI * sin_theta)) as f32
        } else {
            0.0
        }
    }
}

/// The point of the equirectangular square `[0, 1)²` looking along `d` (the environment's
/// frame; need not be unit).
fn square_of(d: DVec3) -> [f64; 2] {
    let theta = d.z.atan2((d.x * d.x + d.y * d.y).sqrt());
    let v = (0.5 - theta / PI).clamp(0.0, 1.0);
    let phi = d.y.atan2(d.x);
    let u = (0.75 - phi / (2.0 * PI)).rem_euclid(1.0);
    [u, v]
}

/// The unit direction (the environment's frame) of the square's point `(u, v)`.
fn direction_of([u, v]: [f64; 2]) -> DVec3 {
    let theta = PI * v;
    let phi = 1.5 * PI - 2.0 * PI * u;
    let (sin_theta, cos_theta) = theta.sin_cos();
    DVec3::new(sin_theta * phi.cos(), sin_theta * phi.sin(), cos_theta)
}

/// The sampling distribution of a raster of values: each texel's value plus the floor,
/// times sin θ at its centre.
fn sampling_distribution(mut weights: Vec<f32>, width: usize, height: usize) -> Distribution2D {
    let sin_theta: Vec<f64> = (0..height)
        .map(|row| (PI * (row as f64 + 0.5) / height as f64).sin())
        .collect();
    // The mean value over the sphere (solid-angle weighted).
    let (mut sum, mut area) = (0.0f64, 0.0f64);
    for (row, values) in weights.chunks(width).enumerate() {
        let s: f64 = values.iter().map(|&v| f64::from(v.max(0.0))).sum();
        sum += s * sin_theta[row];
        area += width as f64 * sin_theta[row];
    }
    let floor = if sum > 0.0 { FLOOR * sum / area } else { 1.0 };
    for (row, values) in weights.chunks_mut(width).enumerate() {
        for v in values {
            *v = ((f64::from(v.max(0.0)) + floor) * sin_theta[row]) as f32;
        }
    }
    Distribution2D::new(&weights, width, height)
}

/// Read the map `path` (`environment.path`), twice as wide as high.
fn load_map(path: &str) -> Result<LuminanceMap> {
    let map = read_map(std::path::Path::new(path))
        .map_err(|message| Error::field("environment.path", format!("{path}: {message}")))?;
    if map.width != 2 * map.height {
        return Err(Error::field(
            "environment.path",
            format!(
                "{path}: {} × {} pixels is not an equirectangular (latitude–longitude) map,                  which is twice as wide as high; give a 2:1 map",
                map.width, map.height
            ),
        ));
    }
    Ok(map)
}

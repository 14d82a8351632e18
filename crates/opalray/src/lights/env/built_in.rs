//! The built-in environments (`studio`, `window`, `overcast`, `tent`, `uniform`, `none`):
//! their values along a direction, analytic, and their rasterisation on [`BUILT_IN_GRID`]
//! texels for sampling. The scenes they stand for are listed in [`super`]'s outline.

use glam::Vec3;
use rayon::prelude::*;

use super::{direction_of, Environment, BUILT_IN_GRID, BUILT_IN_SUBSAMPLES};
use crate::scene::EnvironmentKind;

impl Environment {
    /// The built-in environment's values averaged over each texel of [`BUILT_IN_GRID`]
    /// (in the environment's frame: the distribution is turned with it).
    pub(super) fn rasterise(&self) -> Vec<f32> {
        let (w, h) = BUILT_IN_GRID;
        let n = BUILT_IN_SUBSAMPLES;
        let mut out = vec![0.0f32; w * h];
        // Rows in parallel into their own slices: the same values at any thread count.
        out.par_chunks_mut(w).enumerate().for_each(|(row, texels)| {
            for (column, texel) in texels.iter_mut().enumerate() {
                let mut sum = 0.0f64;
                for k in 0..n * n {
                    let u = (column as f64 + ((k % n) as f64 + 0.5) / n as f64) / w as f64;
                    let v = (row as f64 + ((k / n) as f64 + 0.5) / n as f64) / h as f64;
                    let d = direction_of([u, v]).as_vec3();
                    // `d` is in the environment's frame; the backdrop of `none` depends on z
                    // alone, which the turn keeps.
                    sum += f64::from(self.built_in(d, d));
                }
                *texel = (sum / (n * n) as f64) as f32;
            }
        });
        out
    }

    /// A built-in environment along `d` (its frame); `dir` is the same direction in the
    /// stone's frame.
    pub(super) fn built_in(&self, d: Vec3, dir: Vec3) -> f32 {
        let elevation = d.z.clamp(-1.0, 1.0).asin();
        let azimuth = d.y.atan2(d.x);
        let v = match self.kind {
            EnvironmentKind::None | EnvironmentKind::File => {
                return if dir.z < 0.0 { self.background } else { 0.0 };
            }
            EnvironmentKind::Studio => {
                if d.z < 0.0 {
                    0.0004
                } else if within_cap(d, SOFTBOX_AXIS, SOFTBOX_RADIUS_DEG) {
                    1.0
                } else if strip(azimuth, elevation, 0.0, 15.0) {
                    0.8
                } else if strip(azimuth, elevation, 180.0, 15.0) {
                    0.5
                } else {
                    0.004
                }
            }
            EnvironmentKind::Window => {
                let h = elevation.to_degrees();
                let az = azimuth.to_degrees();
                if d.z < 0.0 {
                    0.02
                } else if (20.0..=60.0).contains(&h) && (90.0..=140.0).contains(&az) {
                    1.0
                } else {
                    0.04
                }
            }
            EnvironmentKind::Uniform => 1.0,
            EnvironmentKind::Tent => {
                let h = elevation.to_degrees();
                if d.z < 0.0 {
                    0.0004
                } else if h > 90.0 - TENT_PORT_RADIUS_DEG {
                    0.004
                } else if h < 10.0 {
                    0.3
                } else {
                    1.0
                }
            }
            EnvironmentKind::Overcast => {
                if d.z < 0.0 {
                    0.1
                } else {
                    (1.0 + 2.0 * d.z) / 3.0
                }
            }
        };
        v * self.intensity
    }
}

/// The studio softbox's centre: 50° from the zenith towards +y.
pub(super) const SOFTBOX_AXIS: Vec3 = Vec3::new(0.0, 0.766_044_4, 0.642_787_6);
/// Angular radius of the light tent's camera port about the zenith, degrees.
pub(super) const TENT_PORT_RADIUS_DEG: f32 = 6.0;
/// The studio softbox's angular radius, degrees.
pub(super) const SOFTBOX_RADIUS_DEG: f32 = 22.0;

/// Whether `d` lies within `radius_deg` of `axis`.
fn within_cap(d: Vec3, axis: Vec3, radius_deg: f32) -> bool {
    d.dot(axis.normalize()) >= radius_deg.to_radians().cos()
}

/// A strip light: 60° wide in azimuth about `azimuth_deg`, `height_deg` high from 10° above
/// the horizon.
fn strip(azimuth: f32, elevation: f32, azimuth_deg: f32, height_deg: f32) -> bool {
    let mut da = azimuth.to_degrees() - azimuth_deg;
    while da > 180.0 {
        da -= 360.0;
    }
    while da < -180.0 {
        da += 360.0;
    }
    let h = elevation.to_degrees();
    da.abs() <= 30.0 && (10.0..=10.0 + height_deg).contains(&h)
}

//! Built-in environments: radiance from every direction, no file needed.
//!
//! The environment's zenith is +z, the side of the stone's broad face where the camera
//! stands (a gem photographed from above, lying on a table); `rotation_deg` turns it about that
//! axis. Values are in the image's units (π × radiance, relative to the light's spectrum): a
//! white diffuser facing an emitter of value 1 that fills its view shows 1.
//!
//! - `studio`: a softbox 50° from the zenith towards the top of the picture (+y), 22° in
//!   angular radius, value 1; two strip lights low at the left and right (15° × 60°, value
//!   0.8 and 0.5); a dark room (0.004) and a black velvet table (0.0004).
//! - `window`: a window 50° wide and 40° high, 20–60° above the horizon towards −x and +y,
//!   value 1, in a room of 0.04 over a floor of 0.02.
//! - `overcast`: the CIE overcast sky, `(1 + 2 sin h)/3` at elevation h, over ground of 0.1.
//! - `uniform`: 1 everywhere (a furnace).
//! - `none`: black, but for the backdrop (`render.background`) behind the stone (z < 0).

use glam::Vec3;

use crate::scene::{EnvironmentConfig, EnvironmentKind};

/// An environment ready to be looked up.
#[derive(Clone, Copy, Debug)]
pub struct Environment {
    kind: EnvironmentKind,
    intensity: f32,
    /// cos and sin of the rotation about z.
    turn: (f32, f32),
    background: f32,
}

impl Environment {
    /// The environment of `config`; `background` is the backdrop of `none`.
    pub fn new(config: &EnvironmentConfig, background: f32) -> Self {
        let a = (config.rotation_deg as f32).to_radians();
        Environment {
            kind: config.kind,
            intensity: config.intensity as f32,
            turn: (a.cos(), a.sin()),
            background,
        }
    }

    /// Value seen looking along `dir` (unit, in the stone's frame).
    pub fn value(&self, dir: Vec3) -> f32 {
        // Into the environment's frame: undo its turn about z.
        let (c, s) = self.turn;
        let d = Vec3::new(c * dir.x + s * dir.y, -s * dir.x + c * dir.y, dir.z);
        let elevation = d.z.clamp(-1.0, 1.0).asin();
        let azimuth = d.y.atan2(d.x);
        let v = match self.kind {
            EnvironmentKind::None => {
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
const SOFTBOX_AXIS: Vec3 = Vec3::new(0.0, 0.766_044_4, 0.642_787_6);
/// The studio softbox's angular radius, degrees.
const SOFTBOX_RADIUS_DEG: f32 = 22.0;

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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_studio_softbox_is_overhead_and_the_table_dark() {
        let env = Environment::new(
            &EnvironmentConfig {
                kind: EnvironmentKind::Studio,
                ..EnvironmentConfig::default()
            },
            0.0,
        );
        assert_eq!(env.value(SOFTBOX_AXIS), 1.0);
        assert!(env.value(-Vec3::Z) < 0.01);
    }

    #[test]
    fn rotation_turns_the_environment_about_z() {
        let config = EnvironmentConfig {
            kind: EnvironmentKind::Window,
            rotation_deg: 90.0,
            ..EnvironmentConfig::default()
        };
        let env = Environment::new(&config, 0.0);
        let plain = Environment::new(
            &EnvironmentConfig {
                rotation_deg: 0.0,
                ..config
            },
            0.0,
        );
        let d = Vec3::new(-0.3, 0.7, 0.6).normalize();
        let turned = Vec3::new(-d.y, d.x, d.z);
        assert_eq!(plain.value(d), env.value(turned));
    }
}

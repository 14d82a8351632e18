//! Named scenes. Each preset is also shipped as `scenes/NAME.toml`.

use super::{
    DomainsConfig, EnvironmentKind, IntegratorConfig, LightKind, Method, OrientationLaw, Pattern,
    Scene,
};
use crate::error::{Error, Result};

/// Names accepted by [`preset`].
pub const PRESET_NAMES: &[&str] = &[
    "paper",
    "paper-path",
    "harlequin",
    "pinfire",
    "broad-flash",
    "ribbon",
];

/// The scene called `name`.
///
/// - `paper`: the paper's figures: ellipsoid of 100 × 75 × 25 cells, R = 6, void ratio 0.2,
///   light at 30° to the view direction (fig. 10), 640 × 480, the two-pass renderer.
/// - `paper-path`: the paper's stone and light rendered by the path tracer on the stone model
///   (domains as the growth's balls, every plane family, the rocking width, the half-vector
///   law, a 3 % spread of sphere sizes).
/// - `harlequin`: a black opal (body tone N1) of angular grains 3 mm across, each its own
///   orientation, under the studio environment.
/// - `pinfire`: a black opal of grains 0.8 mm across: pin-points of colour.
/// - `broad-flash`: grains 4 mm across whose orientations follow parents 12 mm across: broad
///   sheets of colour that flash together.
/// - `ribbon`: grains stretched six times along y: ribbons of colour.
pub fn preset(name: &str) -> Result<Scene> {
    let studio = |domains: DomainsConfig| {
        let mut scene = Scene {
            domains,
            integrator: IntegratorConfig {
                method: Method::Path,
                ..IntegratorConfig::default()
            },
            ..Scene::default()
        };
        scene.environment.kind = EnvironmentKind::Studio;
        scene.environment.intensity = 2.5;
        scene.light.kind = LightKind::None;
        scene.render.body_tone = 1;
        scene.crystal.diffuse_fraction = 0.0;
        scene
    };
    let grains = |size: f64| DomainsConfig {
        pattern: Pattern::Grains,
        grain_size_mm: size,
        void_fraction: 0.05,
        ..DomainsConfig::default()
    };
    match name {
        "paper" => Ok(Scene::default()),
        "paper-path" => {
            let mut scene = Scene::default();
            scene.integrator.method = Method::Path;
            scene.crystal.diffuse_fraction = 0.0;
            // The paper's balls are large, single domains: an imperfect one tilts its planes
            // by a few degrees across its width.
            scene.domains.mosaic_spread_deg = 4.0;
            Ok(scene)
        }
        "harlequin" => Ok(studio(grains(3.0))),
        "pinfire" => Ok(studio(grains(0.8))),
        "broad-flash" => Ok(studio(DomainsConfig {
            orientation: OrientationLaw::Correlated,
            correlation_mm: 12.0,
            orientation_spread_deg: 12.0,
            ..grains(4.0)
        })),
        "ribbon" => Ok(studio(DomainsConfig {
            stretch: [1.0, 6.0, 1.0],
            ..grains(1.5)
        })),
        other => Err(Error::argument(
            "--preset",
            format!(
                "unknown preset `{other}`; choose one of: {}",
                PRESET_NAMES.join(", ")
            ),
        )),
    }
}

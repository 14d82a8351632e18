//! Named scenes. Each preset is also shipped as `scenes/NAME.toml`.

use super::Scene;
use crate::error::{Error, Result};

/// Names accepted by [`preset`].
pub const PRESET_NAMES: &[&str] = &["paper"];

/// The scene called `name`.
///
/// - `paper`: the paper's figures: ellipsoid of 100 × 75 × 25 cells, R = 6, void ratio 0.2,
///   light at 30° to the view direction (fig. 10), 640 × 480.
pub fn preset(name: &str) -> Result<Scene> {
    match name {
        "paper" => Ok(Scene::default()),
        other => Err(Error::argument(
            "--preset",
            format!(
                "unknown preset `{other}`; choose one of: {}",
                PRESET_NAMES.join(", ")
            ),
        )),
    }
}

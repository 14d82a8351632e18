//! Named scenes: the files in `scenes/`, included at build time and parsed into a [`Scene`].
//!
//! Each file is complete (every field written out) and says in a comment why each of its
//! choices is made; how the gem presets' stones and poses were picked is in `BENCHMARKS.md`.

use super::Scene;
use crate::error::{Error, Result};

/// Names accepted by [`preset`].
pub const PRESET_NAMES: &[&str] = &[
    "black-opal",
    "harlequin",
    "pinfire",
    "broad-flash",
    "ribbon",
    "white",
    "crystal",
    "boulder",
    "doublet",
    "triplet",
    "paper",
    "paper-path",
    "paper-stone",
];

/// The preset `opalray render` renders when given no scene.
pub const DEFAULT_RENDER_PRESET: &str = "black-opal";

/// The pair of a preset's name and its scene file's text, included at build time.
macro_rules! preset_file {
    ($name:literal) => {
        (
            $name,
            include_str!(concat!("../../../../scenes/", $name, ".toml")),
        )
    };
}

/// Every preset's scene file, by name, in the order of [`PRESET_NAMES`].
const PRESET_FILES: &[(&str, &str)] = &[
    preset_file!("black-opal"),
    preset_file!("harlequin"),
    preset_file!("pinfire"),
    preset_file!("broad-flash"),
    preset_file!("ribbon"),
    preset_file!("white"),
    preset_file!("crystal"),
    preset_file!("boulder"),
    preset_file!("doublet"),
    preset_file!("triplet"),
    preset_file!("paper"),
    preset_file!("paper-path"),
    preset_file!("paper-stone"),
];

/// The scene called `name`, parsed from `scenes/NAME.toml` as it was when the library was
/// built.
///
/// The gem presets are cabochons 20 × 15 mm (or slices: `doublet`, `triplet`; a thin layer
/// on ironstone: `boulder`) under the studio environment, rendered by the lobe integrator
/// (4 rays through each pixel at an edge; `integrator.method = "path"` renders the same stone
/// by the path tracer, the reference):
///
/// - `black-opal`: a fine black opal, a 2 mm colour bar of settled plates over black potch,
///   rocked by 10°;
/// - `harlequin`: large settled plates with straight edges, broad angular patches;
/// - `pinfire`: grains 0.6 mm across, pin-points of colour;
/// - `broad-flash`: large plates whose tilts are alike, rocked by 10°;
/// - `ribbon`: plates stretched six times along y, ribbons of colour;
/// - `white`: a white opal (N9), pastel colour over white potch, rocked by 10°;
/// - `crystal`: a clear crystal opal with rolling flash;
/// - `boulder`: a thin layer of opal on brown ironstone, rocked by 10°;
/// - `doublet`: a 1.5 mm opal slice glued on black;
/// - `triplet`: a 0.8 mm slice on black under a clear quartz dome, rocked by 10°.
///
/// The paper's scene: `paper` (the default scene: its figures, the two-pass renderer),
/// `paper-path` (its stone and light, path-traced on the stone model) and `paper-stone`
/// (the same rendered by the stored method).
///
/// An unknown name is an error naming `--preset` and listing the names.
pub fn preset(name: &str) -> Result<Scene> {
    let Some((_, text)) = PRESET_FILES.iter().find(|(known, _)| *known == name) else {
        return Err(Error::argument(
            "--preset",
            format!(
                "unknown preset `{name}`; choose one of: {}",
                PRESET_NAMES.join(", ")
            ),
        ));
    };
    Scene::from_toml_str(text, &format!("preset {name}"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn preset_files_are_the_preset_names() {
        let files: Vec<&str> = PRESET_FILES.iter().map(|(name, _)| *name).collect();
        assert_eq!(files, PRESET_NAMES);
    }

    #[test]
    fn preset_unknown_name_is_refused_naming_the_flag() {
        let message = preset("opal").unwrap_err().to_string();
        assert!(message.contains("--preset"), "{message}");
        assert!(message.contains("black-opal"), "{message}");
    }
}

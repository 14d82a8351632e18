//! Reading a scene: TOML text, a TOML value (a Python dict, a JS object) or a file of
//! bounded size into a [`Scene`], every error one line naming the field path (and, from
//! text, its line); then [`Scene::validate`].

use std::path::Path;

use super::{shape, Scene};
use crate::error::{Error, Result};

/// A parser's message on one line (it may span several).
fn one_line(message: &str) -> String {
    message
        .lines()
        .map(str::trim)
        .filter(|line| !line.is_empty())
        .collect::<Vec<_>>()
        .join(": ")
}

/// A TOML array where a section is expected would fill the section by position: refuse it,
/// naming the section.
fn refuse_misplaced_tables(given: &toml::Table, origin: &str) -> Result<()> {
    if let Ok(toml::Value::Table(template)) = toml::Value::try_from(Scene::default()) {
        if let Some((path, found)) = shape::misplaced_table(given, &template, "") {
            return Err(Error::SceneParse {
                origin: origin.to_string(),
                message: format!(
                    "field `{path}`: must be a table (a `[{path}]` section of `key = value` \
                     lines), found {found}"
                ),
            });
        }
    }
    Ok(())
}

impl Scene {
    /// Parse TOML text. `origin` names the source in errors (a path, `preset paper`).
    /// The result is validated.
    pub fn from_toml_str(text: &str, origin: &str) -> Result<Scene> {
        let de = toml::Deserializer::new(text);
        let scene: Scene = serde_path_to_error::deserialize(de).map_err(|e| {
            let path = e.path().to_string();
            let inner = e.into_inner();
            let message = one_line(inner.message());
            let location = inner
                .span()
                .map(|span| {
                    let line = text[..span.start.min(text.len())].matches('\n').count() + 1;
                    format!(" (line {line})")
                })
                .unwrap_or_default();
            // An error the parser finds before any field (a number too large for TOML) is
            // named by the key on its line.
            let key = inner
                .span()
                .and_then(|span| shape::key_at(text, span.start));
            let message = if let (true, Some(key)) = (path.is_empty() || path == ".", &key) {
                format!("field `{key}`{location}: {message}")
            } else if path.is_empty() || path == "." {
                format!("{message}{location}")
            } else {
                format!("field `{path}`{location}: {message}")
            };
            Error::SceneParse {
                origin: origin.to_string(),
                message,
            }
        })?;
        if let Ok(given) = text.parse::<toml::Table>() {
            refuse_misplaced_tables(&given, origin)?;
        }
        scene.validate()?;
        Ok(scene)
    }

    /// A scene from a TOML value (a Python dict or a JS object turned into one), with the
    /// messages of a scene file less its line numbers. `origin` names the source in errors.
    /// The result is validated.
    pub fn from_toml_value(value: toml::Value, origin: &str) -> Result<Scene> {
        if let toml::Value::Table(given) = &value {
            refuse_misplaced_tables(given, origin)?;
        }
        let scene: Scene = serde_path_to_error::deserialize(value).map_err(|e| {
            let path = e.path().to_string();
            let message = one_line(e.into_inner().message());
            let message = if path.is_empty() || path == "." {
                message
            } else {
                format!("field `{path}`: {message}")
            };
            Error::SceneParse {
                origin: origin.to_string(),
                message,
            }
        })?;
        scene.validate()?;
        Ok(scene)
    }

    /// Read and parse a TOML scene file of at most [`MAX_SCENE_FILE_BYTES`]; a relative
    /// `environment.path` is taken from the file's folder ([`Scene::resolve_paths`]).
    pub fn load(path: &Path) -> Result<Scene> {
        let text = read_text_limited(path, MAX_SCENE_FILE_BYTES)?;
        let mut scene = Scene::from_toml_str(&text, &path.display().to_string())?;
        scene.resolve_paths(path.parent().unwrap_or(Path::new("")));
        Ok(scene)
    }

    /// The complete scene as TOML, every field written out.
    pub fn to_toml(&self) -> String {
        toml::to_string(self).expect("a Scene always serialises to TOML")
    }

    /// Take a relative `environment.path` from the folder `base` (the scene file's): a scene
    /// read from a file names its map relative to that file. An absolute or empty path is
    /// left as it is.
    pub fn resolve_paths(&mut self, base: &Path) {
        let path = Path::new(&self.environment.path);
        if !self.environment.path.is_empty() && path.is_relative() {
            self.environment.path = base.join(path).display().to_string();
        }
    }
}

/// Largest scene file [`Scene::load`] reads, bytes (a complete scene is about 1.5 kB).
pub const MAX_SCENE_FILE_BYTES: u64 = 1 << 20;

/// Read the UTF-8 text file `path` of at most `limit` bytes, reading no more than
/// `limit + 1` whatever the file (`/dev/zero` is refused at once).
pub fn read_text_limited(path: &Path, limit: u64) -> Result<String> {
    use std::io::Read;
    let file = std::fs::File::open(path).map_err(|e| Error::io(path, e))?;
    let mut bytes = Vec::new();
    file.take(limit + 1)
        .read_to_end(&mut bytes)
        .map_err(|e| Error::io(path, e))?;
    if bytes.len() as u64 > limit {
        return Err(Error::InvalidData {
            path: path.to_path_buf(),
            message: format!("larger than the limit of {limit} bytes; give a smaller file"),
        });
    }
    String::from_utf8(bytes).map_err(|e| Error::InvalidData {
        path: path.to_path_buf(),
        message: format!(
            "not UTF-8 text (byte {}); save it as UTF-8",
            e.utf8_error().valid_up_to()
        ),
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::{IntegratorConfig, PathConfig};

    #[test]
    fn default_scene_round_trips_through_toml() {
        let scene = Scene::default();
        let text = scene.to_toml();
        assert_eq!(Scene::from_toml_str(&text, "test").unwrap(), scene);
    }

    #[test]
    fn empty_text_is_the_default_scene() {
        assert_eq!(Scene::from_toml_str("", "test").unwrap(), Scene::default());
    }

    #[test]
    fn unknown_field_is_named_with_its_path() {
        let err = Scene::from_toml_str("[structure]\nvoid_ratoi = 0.3\n", "s.toml")
            .unwrap_err()
            .to_string();
        assert!(err.contains("structure.void_ratoi"), "{err}");
        assert!(
            err.contains("void_ratio"),
            "suggests the known fields: {err}"
        );
    }

    #[test]
    fn wrong_type_is_named_with_its_path() {
        let err = Scene::from_toml_str("[render]\nwidth = \"wide\"\n", "s.toml")
            .unwrap_err()
            .to_string();
        assert!(err.contains("render.width"), "{err}");
    }

    #[test]
    fn seed_beyond_toml_integers_is_refused() {
        let mut scene = Scene::default();
        scene.structure.seed = u64::MAX;
        let err = scene.validate().unwrap_err().to_string();
        assert!(err.contains("structure.seed"), "{err}");
        let scene = Scene {
            integrator: IntegratorConfig::Path(PathConfig {
                seed: u64::MAX,
                ..PathConfig::default()
            }),
            ..Scene::default()
        };
        let err = scene.validate().unwrap_err().to_string();
        assert!(err.contains("integrator.seed"), "{err}");
    }

    #[test]
    fn an_endless_file_is_refused_at_once() {
        let err = Scene::load(Path::new("/dev/zero")).unwrap_err().to_string();
        assert!(err.contains("larger than the limit"), "{err}");
    }

    #[test]
    fn silently_accepted_shapes_are_refused() {
        for (text, expected) in [
            ("[structure]\ngrid = [1, 2, 3, 4]", "structure.grid"),
            (
                "[structure]\nsemi_axes_mm = [1.0, 2.0, 3.0, 4.0]",
                "structure.semi_axes_mm",
            ),
            (
                "[domains]\nstretch = [1.0, 2.0, 3.0, 4.0]",
                "domains.stretch",
            ),
            ("[domains]\nstretch = [1.0, 2.0]", "domains.stretch"),
            ("[light]\nsize_mm = [10.0, 20.0, 30.0]", "light.size_mm"),
            ("[light]\nsize_mm = [10.0]", "light.size_mm"),
            (
                "structure = [[1, 2, 3]]",
                "field `structure`: must be a table",
            ),
            (
                "[render]\nwidth = 99999999999999999999",
                "field `render.width`",
            ),
        ] {
            let err = Scene::from_toml_str(text, "t").unwrap_err().to_string();
            assert!(err.contains(expected), "{text}: {err}");
        }
        let err = Scene::from_toml_str("[structure]\ngrid = [1, 2, 3, 4]", "t")
            .unwrap_err()
            .to_string();
        assert!(err.contains("length 4"), "{err}");
    }

    #[test]
    fn malformed_toml_is_reported_with_a_line() {
        let err = Scene::from_toml_str("[structure\n", "s.toml")
            .unwrap_err()
            .to_string();
        assert!(err.starts_with("s.toml"), "{err}");
        assert!(err.contains("line"), "{err}");
        assert!(!err.contains('\n'), "one line: {err}");
    }

    #[test]
    fn the_lights_new_fields_are_refused_by_name_on_one_line() {
        // `true`: under the path integrator (what a method refuses: `integrator::tests`).
        for (path, text, field) in [
            (true, "[light]\nradius_mm = 0.0", "light.radius_mm"),
            (true, "[light]\nradius_mm = nan", "light.radius_mm"),
            (true, "[light]\nsize_mm = [100.0, -1.0]", "light.size_mm"),
            (true, "[light]\nsize_mm = [1e9, 10.0]", "light.size_mm"),
            (true, "[light]\nkind = \"disc\"", "light.kind"),
            (
                true,
                "[light]\nkind = \"sphere\"\nradius_mm = 95.0",
                "light.radius_mm",
            ),
            (
                true,
                "[light]\nkind = \"rect\"\ndistance_mm = 5.0",
                "light.distance_mm",
            ),
            (true, "[environment]\nkind = \"file\"", "environment.path"),
            (
                true,
                "[environment]\nkind = \"file\"\npath = \"studio.png\"",
                "environment.path",
            ),
            (
                true,
                "[environment]\nkind = \"studio\"\npath = \"studio.hdr\"",
                "environment.path",
            ),
            (true, "[environment]\nkind = \"map\"", "environment.kind"),
            (true, "[environment]\npath = 3", "environment.path"),
        ] {
            let prefix = if path {
                "[integrator]\nmethod = \"path\"\n"
            } else {
                ""
            };
            let text = format!("{prefix}{text}");
            let err = Scene::from_toml_str(&text, "t").unwrap_err().to_string();
            assert!(err.contains(field), "{text}: {err}");
            assert!(!err.contains('\n'), "one line: {err}");
        }
        // What is valid passes.
        for text in [
            "[light]\nkind = \"sphere\"\nradius_mm = 20.0",
            "[light]\nkind = \"rect\"\nsize_mm = [300.0, 150.0]",
            "[environment]\nkind = \"file\"\npath = \"maps/studio.EXR\"",
        ] {
            let text = format!("[integrator]\nmethod = \"path\"\n{text}");
            Scene::from_toml_str(&text, "t").unwrap();
        }
    }
}

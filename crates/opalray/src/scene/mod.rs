//! The scene: everything a render needs, as plain data with a default for every field.
//!
//! Input: TOML text (a file, a preset) → output: a validated [`Scene`]. Unknown fields are
//! errors naming their path; [`Scene::validate`] checks ranges, NaN and the memory a grid
//! would need before anything is allocated. Field tables: `docs/scene-format.md`.

mod body;
mod integrator;
mod look;
mod methods;
mod presets;
mod shape;
mod stone;
mod studio;

pub use body::{Backing, BodyConfig, Cut};
pub use integrator::{
    check_spp, IntegratorConfig, LobeConfig, Method, PathConfig, StoredConfig, TwoPassConfig,
    DEFAULT_WAVELENGTHS, MAX_SPP,
};
pub use look::{
    CameraConfig, ColorConfig, ColorSpaceChoice, GamutMapping, Illuminant, LightConfig, LightKind,
    RenderConfig, BODY_EXTINCTION_PER_MM,
};
pub use presets::{preset, DEFAULT_RENDER_PRESET, PRESET_NAMES};
pub use stone::{CrystalConfig, StructureConfig, MAX_CELLS};
pub use studio::{
    map_format, DomainsConfig, EnvironmentConfig, EnvironmentKind, FamilyChoice, MapFormat,
    OrientationLaw, Pattern, COLUMN_HEIGHT, OUTLINE_SUBDIVISION,
};

use std::path::Path;

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::spectrum::WavelengthGrid;

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

/// Most grains of a `domains.pattern = "grains"` stone (about 100 MB of grain data).
pub const MAX_GRAINS: u64 = 250_000;

/// Largest spectral image accepted, bytes (4 GiB).
pub const MAX_SPECTRAL_IMAGE_BYTES: u64 = 4 << 30;

/// A complete scene. Every section and field is optional in TOML; missing ones take the
/// defaults of the `paper` preset (the paper's fig. 10 set-up).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct Scene {
    /// Opal shape, cell grid and cluster growth (paper §2.4).
    pub structure: StructureConfig,
    /// The FCC crystal inside a cluster (paper §2.3, §3.1).
    pub crystal: CrystalConfig,
    /// Wavelength bins of every spectral quantity.
    pub spectrum: WavelengthGrid,
    /// The light source (paper fig. 10).
    pub light: LightConfig,
    /// The camera (paper fig. 10).
    pub camera: CameraConfig,
    /// Image size and shading controls (paper §3.3).
    pub render: RenderConfig,
    /// Spectrum → RGB (paper §3.4).
    pub color: ColorConfig,
    /// The domains as geometry (path integrator).
    pub domains: DomainsConfig,
    /// The stone's cut, backing and potch (path integrator).
    pub body: BodyConfig,
    /// Light from every direction (path integrator).
    pub environment: EnvironmentConfig,
    /// Which renderer, and its sampling.
    pub integrator: IntegratorConfig,
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

    /// Check every field's range; the first problem found is returned with its field path.
    pub fn validate(&self) -> Result<()> {
        self.structure.validate()?;
        self.crystal.validate()?;
        self.spectrum.validate("spectrum")?;
        self.light.validate()?;
        self.camera.validate()?;
        self.render.validate()?;
        self.color.validate()?;
        self.domains.validate()?;
        self.body.validate(self.structure.semi_axes_mm)?;
        self.environment.validate()?;
        self.integrator.validate()?;
        if self.domains.pattern == Pattern::Grains {
            self.check_grains()?;
            if self.domains.orientation == OrientationLaw::Correlated {
                self.check_parent_grains()?;
            }
        }
        self.validate_area_light()?;
        // The spectral image is width × height × bins floats: refuse what cannot fit.
        let bytes = u64::from(self.render.width)
            * u64::from(self.render.height)
            * self.spectrum.bins as u64
            * 4;
        if bytes > MAX_SPECTRAL_IMAGE_BYTES {
            return Err(Error::field(
                "render.width",
                format!(
                    "{} × {} pixels × {} bins would need {:.1} GiB for the spectral image, more \
                     than the limit of 4 GiB; lower render.width/height or spectrum.bins",
                    self.render.width,
                    self.render.height,
                    self.spectrum.bins,
                    bytes as f64 / (1u64 << 30) as f64
                ),
            ));
        }
        Ok(())
    }
}

impl Scene {
    /// A sphere or rect light must lie beyond the stone.
    fn validate_area_light(&self) -> Result<()> {
        let kind = self.light.kind;
        if !matches!(kind, LightKind::Sphere | LightKind::Rect) {
            return Ok(());
        }
        let stone = self
            .structure
            .semi_axes_mm
            .iter()
            .fold(0.0f64, |a, &b| a.max(b));
        let d = self.light.distance_mm;
        if kind == LightKind::Sphere && self.light.radius_mm + stone >= d {
            return Err(Error::field(
                "light.radius_mm",
                format!(
                    "a ball of {} mm at {d} mm touches the stone (semi-axis up to {stone} mm); \
                     use a radius below {:.3} mm or a larger light.distance_mm",
                    self.light.radius_mm,
                    d - stone
                ),
            ));
        }
        if kind == LightKind::Rect && stone >= d {
            return Err(Error::field(
                "light.distance_mm",
                format!(
                    "a rect light at {d} mm cuts the stone (semi-axis up to {stone} mm); place \
                     it beyond {stone} mm"
                ),
            ));
        }
        Ok(())
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

impl Scene {
    /// Refuse more grains than [`MAX_GRAINS`], naming the smallest `domains.grain_size_mm`
    /// (in hundredths) that fits.
    fn check_grains(&self) -> Result<()> {
        let axes = self.body.box_semi_axes(self.structure.semi_axes_mm);
        let count_at = |size_mm: f64| {
            DomainsConfig {
                grain_size_mm: size_mm,
                ..self.domains.clone()
            }
            .grain_count(axes)
        };
        let size = self.domains.grain_size_mm;
        let grains = count_at(size);
        if grains <= MAX_GRAINS as f64 {
            return Ok(());
        }
        // The count falls about as the size cubed (less near the box's margins): step up to
        // the first hundredth that fits.
        let mut smallest = (size * (grains / MAX_GRAINS as f64).cbrt() * 100.0).ceil() / 100.0;
        while count_at(smallest) > MAX_GRAINS as f64 {
            smallest += 0.01;
        }
        Err(Error::field(
            "domains.grain_size_mm",
            format!(
                "{size} mm grains would make about {grains:.0} grains in this stone, more than \
                 the limit of {MAX_GRAINS}; use at least {smallest:.2} mm"
            ),
        ))
    }

    /// Correlated orientations draw from parent grains of `domains.correlation_mm`: refuse
    /// more of them than [`MAX_GRAINS`] (they take as long to grow as grains do), naming the
    /// smallest length that fits.
    fn check_parent_grains(&self) -> Result<()> {
        let axes = self.body.box_semi_axes(self.structure.semi_axes_mm);
        let count_at = |length_mm: f64| {
            let parents = DomainsConfig {
                grain_size_mm: length_mm,
                stretch: [1.0; 3],
                boundary_roughness: 0.0,
                ..self.domains.clone()
            };
            parents.grain_count(axes)
        };
        let length = self.domains.correlation_mm;
        let count = count_at(length);
        if count <= MAX_GRAINS as f64 {
            return Ok(());
        }
        // The count falls about as the length cubed; step up to the first hundredth that fits.
        let mut smallest = (length * (count / MAX_GRAINS as f64).cbrt() * 100.0).ceil() / 100.0;
        while count_at(smallest) > MAX_GRAINS as f64 {
            smallest += 0.01;
        }
        Err(Error::field(
            "domains.correlation_mm",
            format!(
                "{length} mm parent grains would make about {count:.0} of them in this stone, \
                 more than the limit of {MAX_GRAINS}; use at least {smallest:.2} mm"
            ),
        ))
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

/// Check that `value` is finite and within `[lo, hi]`; the error names `field` and a fix.
pub(crate) fn check_range(field: &str, value: f64, lo: f64, hi: f64, example: f64) -> Result<()> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(Error::field(
            field,
            format!("must be a number in [{lo}, {hi}], got {value}; try {example}"),
        ))
    }
}

/// Check that the whole number `value` lies in `range`; the error says what the field `must
/// be` and what to `try`.
pub(crate) fn check_count(
    field: &str,
    value: u64,
    range: std::ops::RangeInclusive<u64>,
    must_be: &str,
    try_instead: &str,
) -> Result<()> {
    if range.contains(&value) {
        Ok(())
    } else {
        Err(Error::field(
            field,
            format!("must be {must_be}, got {value}; try {try_instead}"),
        ))
    }
}

/// Check that `value` is finite and strictly positive and at most `hi`.
pub(crate) fn check_positive(field: &str, value: f64, hi: f64, example: f64) -> Result<()> {
    if value.is_finite() && value > 0.0 && value <= hi {
        Ok(())
    } else {
        Err(Error::field(
            field,
            format!("must be a positive number at most {hi}, got {value}; try {example}"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

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
    fn correlated_grains_too_fine_to_grow_in_time_are_refused() {
        let text = "[integrator]\nmethod = \"path\"\n[domains]\npattern = \"grains\"\n\
                    orientation = \"correlated\"\ncorrelation_mm = 0.1";
        let err = Scene::from_toml_str(text, "t").unwrap_err().to_string();
        assert!(err.contains("domains.correlation_mm"), "{err}");
        // The length it names fits, a hundredth less does not.
        let fits: f64 = err
            .rsplit("at least ")
            .next()
            .and_then(|t| t.strip_suffix(" mm"))
            .and_then(|t| t.parse().ok())
            .unwrap_or_else(|| panic!("no length in {err}"));
        let with =
            |length: f64| Scene::from_toml_str(&text.replace("0.1", &format!("{length}")), "t");
        assert!(with(fits).is_ok(), "{fits}");
        assert!(with(fits - 0.01).is_err(), "{fits}");
    }

    #[test]
    fn the_grain_size_named_for_too_many_grains_fits() {
        // 0.05 mm grains in the paper's stone: about 23 million, over `MAX_GRAINS`.
        let text = "[domains]\npattern = \"grains\"\ngrain_size_mm = 0.05";
        let err = Scene::from_toml_str(text, "t").unwrap_err().to_string();
        assert!(err.contains("domains.grain_size_mm"), "{err}");
        let fits: f64 = err
            .rsplit("at least ")
            .next()
            .and_then(|t| t.strip_suffix(" mm"))
            .and_then(|t| t.parse().ok())
            .unwrap_or_else(|| panic!("no size in {err}"));
        let with = |size: f64| Scene::from_toml_str(&text.replace("0.05", &format!("{size}")), "t");
        assert!(with(fits).is_ok(), "{fits}: {}", with(fits).unwrap_err());
        assert!(with(fits - 0.01).is_err(), "{fits}");
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

    #[test]
    fn out_of_range_values_are_refused() {
        for (text, field) in [
            ("[structure]\nvoid_ratio = 1.5", "structure.void_ratio"),
            ("[structure]\nvoid_ratio = 0.0", "structure.void_ratio"),
            ("[structure]\nvoid_ratio = nan", "structure.void_ratio"),
            (
                "[structure]\nmean_radius_cells = -6.0",
                "structure.mean_radius_cells",
            ),
            ("[structure]\ngrid = [100, 0, 25]", "structure.grid"),
            (
                "[structure]\nsemi_axes_mm = [10.0, -1.0, 2.0]",
                "structure.semi_axes_mm",
            ),
            (
                "[structure]\ngrid = [100000, 100000, 100000]",
                "structure.grid",
            ),
            (
                "[crystal]\nsphere_diameter_nm = -250.0",
                "crystal.sphere_diameter_nm",
            ),
            ("[crystal]\nn_sphere = 0.9", "crystal.n_sphere"),
            ("[render]\nwidth = 0", "render.width"),
            ("[render]\nbody_tone = 12", "render.body_tone"),
            ("[light]\nangle_deg = 120.0", "light.angle_deg"),
            ("[light]\ncutoff = 0.0", "light.cutoff"),
            ("[light]\ncutoff = 1e-7", "light.cutoff"),
            ("[light]\ncutoff = 0.8", "light.cutoff"),
            ("[light]\ncutoff = nan", "light.cutoff"),
            ("[render]\nwidth = 16384\nheight = 16384", "render.width"),
            (
                "[domains]\npattern = \"grains\"\ngrain_size_mm = 0.05",
                "domains.grain_size_mm",
            ),
            (
                "[domains]\nboundary_roughness = 1.5",
                "domains.boundary_roughness",
            ),
            ("[integrator]\nmethod = \"path\"\nspp = 0", "integrator.spp"),
            (
                "[integrator]\nmethod = \"stored\"\ncell_mm = 5.0",
                "integrator.cell_mm",
            ),
            (
                "[domains]\nsphere_diameter_spread = 0.5",
                "domains.sphere_diameter_spread",
            ),
            (
                "[domains]\ndiameter_correlation_mm = 0.05",
                "domains.diameter_correlation_mm",
            ),
            (
                "[domains]\ndiameter_correlation_mm = -1.0",
                "domains.diameter_correlation_mm",
            ),
            (
                "[domains]\ndiameter_correlation_mm = nan",
                "domains.diameter_correlation_mm",
            ),
            (
                "[domains]\ntilt_correlation_mm = 0.05",
                "domains.tilt_correlation_mm",
            ),
            (
                "[domains]\ntilt_jitter_deg = -1.0",
                "domains.tilt_jitter_deg",
            ),
            (
                "[domains]\ntilt_correlation_mm = 3.0\norientation_spread_deg = 4.0",
                "domains.tilt_jitter_deg",
            ),
        ] {
            let err = Scene::from_toml_str(text, "t").unwrap_err().to_string();
            assert!(err.contains(field), "{text}: {err}");
        }
    }
}

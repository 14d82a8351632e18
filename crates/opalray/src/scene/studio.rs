//! The sections of the crystal-and-studio model: the domains as geometry (`[domains]`) and
//! the environment light (`[environment]`), each a parameter table with defaults and a
//! `validate`.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::check_range;
use crate::error::{Error, Result};

/// How the domains are laid out.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Pattern {
    /// The paper's growth (`[structure]`), its balls kept as geometry.
    #[default]
    Paper,
    /// Grains of a power diagram (`grain_size_mm`, `stretch`, …).
    Grains,
}

/// How grain orientations are drawn.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum OrientationLaw {
    /// Every grain uniformly random.
    #[default]
    Independent,
    /// Grains inherit the orientation of a coarser parent grain (`correlation_mm`), turned by
    /// a random angle of RMS `orientation_spread_deg`: neighbouring grains flash together.
    Correlated,
    /// Sedimentary opal: the spheres settled in layers, so each grain's layers (one {111}
    /// family) lie near the bedding plane (the stone's broad face, xy); their normal is
    /// tilted from the face's normal by an angle of RMS `orientation_spread_deg`, in a
    /// uniform direction, and the lattice turned about it at random.
    Settled,
}

/// Which plane families reflect.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum FamilyChoice {
    /// {111} × 4, {220} × 6, {200} × 3.
    #[default]
    All,
    /// The four {111} families only.
    #[serde(rename = "111")]
    Only111,
    /// Randomly stacked close-packed layers: only the reflections that stacking faults leave
    /// sharp, `h + k + l ≡ 0 (mod 3)` about the stacking axis [111] — the stacking (111), the
    /// three in-layer {220} and six of the twelve {311}
    /// ([`crate::optics::FamilyKind::sharp_when_stacked`]); the oblique families are streaks.
    Stacked,
}

/// The domains: where each ordered region of the stone is and how it is made (DESIGN §3–4).
///
/// | field                    | unit | default        | valid                     |
/// |--------------------------|------|----------------|---------------------------|
/// | `pattern`                | –    | "paper"        | "paper", "grains"         |
/// | `grain_size_mm`          | mm   | 2.0            | [0.05, 50]                |
/// | `grain_size_spread`      | –    | 0.3            | [0, 2]                    |
/// | `stretch`                | –    | [1, 1, 1]      | each in [0.1, 20]         |
/// | `orientation`            | –    | "independent"  | "independent", "correlated", "settled" |
/// | `correlation_mm`         | mm   | 6.0            | [0.1, 100]                |
/// | `orientation_spread_deg` | deg  | 20.0           | [0, 180]                  |
/// | `void_fraction`          | –    | 0.15           | [0, 1] (1: potch only)    |
/// | `sphere_diameter_spread` | –    | 0.03           | [0, 0.3]                  |
/// | `diameter_correlation_mm`| mm   | 0.0            | 0, or [0.1, 100]          |
/// | `tilt_correlation_mm`    | mm   | 0.0            | 0, or [0.1, 100]          |
/// | `tilt_jitter_deg`        | deg  | 5.0            | [0, 180]; with the fields, at most `orientation_spread_deg` |
/// | `mosaic_spread_deg`      | deg  | 0.5            | [0, 20]                   |
/// | `families`               | –    | "all"          | "all", "111", "stacked"   |
/// | `boundary_roughness`     | –    | 0.0            | [0, 1]                    |
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct DomainsConfig {
    /// The layout: the paper's growth or grains.
    pub pattern: Pattern,
    /// Grains: diameter of a ball of the mean grain volume, mm.
    pub grain_size_mm: f64,
    /// Grains: relative spread of the grain sizes (lognormal).
    pub grain_size_spread: f64,
    /// Grains: stretch factors along x, y, z (ribbon and straw patterns: one large).
    #[serde(deserialize_with = "super::shape::three")]
    pub stretch: [f64; 3],
    /// Grains: independent or correlated orientations.
    pub orientation: OrientationLaw,
    /// Correlated orientations: size of the parent grains, mm.
    pub correlation_mm: f64,
    /// Correlated orientations: RMS turn of a grain from its parent; settled: RMS tilt of a
    /// grain's layers from the face, degrees.
    pub orientation_spread_deg: f64,
    /// Grains: share of grains that are potch (no play of colour).
    pub void_fraction: f64,
    /// Relative standard deviation of the sphere diameter from domain to domain (the mean is
    /// `crystal.sphere_diameter_nm`).
    pub sphere_diameter_spread: f64,
    /// Grains: distance over which the sphere size stays alike, mm (a smooth field of
    /// correlation length this); 0: each grain draws its own. The paper's balls
    /// (`pattern = "paper"`) always draw their own.
    pub diameter_correlation_mm: f64,
    /// Settled grains: distance over which the layers' tilt and the lattice's turn stay
    /// alike, mm (smooth fields of correlation length this, so that neighbouring plates are
    /// parts of one crystal and flash together); 0: each grain draws its own.
    pub tilt_correlation_mm: f64,
    /// Settled grains with `tilt_correlation_mm` > 0: RMS tilt (and turn) of a grain from
    /// the fields' orientation at its place, degrees; the fields carry the rest of
    /// `orientation_spread_deg`, so the tilts' RMS stays that.
    pub tilt_jitter_deg: f64,
    /// Mosaic spread of a domain's planes, degrees (RMS tilt): the spread of its reflection
    /// over directions (0: a mirror).
    pub mosaic_spread_deg: f64,
    /// The plane families that reflect.
    pub families: FamilyChoice,
    /// Grains: how far the domains' outlines wander in the bedding plane (x, y), in half
    /// grain widths (RMS); 0: straight-edged convex grains.
    pub boundary_roughness: f64,
}

impl Default for DomainsConfig {
    fn default() -> Self {
        DomainsConfig {
            pattern: Pattern::Paper,
            grain_size_mm: 2.0,
            grain_size_spread: 0.3,
            stretch: [1.0, 1.0, 1.0],
            orientation: OrientationLaw::Independent,
            correlation_mm: 6.0,
            orientation_spread_deg: 20.0,
            void_fraction: 0.15,
            sphere_diameter_spread: 0.03,
            diameter_correlation_mm: 0.0,
            tilt_correlation_mm: 0.0,
            tilt_jitter_deg: 5.0,
            mosaic_spread_deg: 0.5,
            families: FamilyChoice::All,
            boundary_roughness: 0.0,
        }
    }
}

/// With ragged outlines (`boundary_roughness` > 0), how many times finer than the grains the
/// columns that draw them are along each axis of the bedding plane (`stone::rough`).
pub const OUTLINE_SUBDIVISION: f32 = 6.0;
/// With ragged outlines, those columns' height in grain thicknesses: tall, so that a ray along
/// the view crosses few (24 took 10 % less time, but parted more pairs of points in one patch).
pub const COLUMN_HEIGHT: f32 = 8.0;

impl DomainsConfig {
    /// About how many grains a stone of semi-axes `semi_axes_mm` holds (the seeds of its box,
    /// one grain size of margin each side: as `stone::grains` places them), with ragged
    /// outlines and the columns that draw them.
    pub fn grain_count(&self, semi_axes_mm: [f64; 3]) -> f64 {
        let stretch: f64 = self.stretch.iter().product();
        let volume = std::f64::consts::PI / 6.0 * self.grain_size_mm.powi(3) / stretch;
        let pad = 2.0 * volume.cbrt();
        let box_volume: f64 = semi_axes_mm
            .iter()
            .zip(self.stretch)
            .map(|(a, s)| 2.0 * a / s + pad)
            .product();
        // Ragged outlines add k²/h columns a grain (`stone::rough`).
        let columns = if self.boundary_roughness > 0.0 {
            f64::from(OUTLINE_SUBDIVISION).powi(2) / f64::from(COLUMN_HEIGHT)
        } else {
            0.0
        };
        box_volume / volume * (1.0 + columns)
    }

    /// Check ranges.
    pub fn validate(&self) -> Result<()> {
        self.validate_grains()?;
        self.validate_correlations()?;
        check_range(
            "domains.mosaic_spread_deg",
            self.mosaic_spread_deg,
            0.0,
            20.0,
            0.5,
        )?;
        check_range(
            "domains.boundary_roughness",
            self.boundary_roughness,
            0.0,
            1.0,
            0.4,
        )
    }

    /// The grains' size, shape, orientations, voids and sphere diameters.
    fn validate_grains(&self) -> Result<()> {
        check_range("domains.grain_size_mm", self.grain_size_mm, 0.05, 50.0, 2.0)?;
        check_range(
            "domains.grain_size_spread",
            self.grain_size_spread,
            0.0,
            2.0,
            0.3,
        )?;
        for s in self.stretch {
            check_range("domains.stretch", s, 0.1, 20.0, 1.0)?;
        }
        check_range(
            "domains.correlation_mm",
            self.correlation_mm,
            0.1,
            100.0,
            6.0,
        )?;
        check_range(
            "domains.orientation_spread_deg",
            self.orientation_spread_deg,
            0.0,
            180.0,
            20.0,
        )?;
        check_range("domains.void_fraction", self.void_fraction, 0.0, 1.0, 0.15)?;
        check_range(
            "domains.sphere_diameter_spread",
            self.sphere_diameter_spread,
            0.0,
            0.3,
            0.03,
        )
    }

    /// The correlation lengths of the sizes and tilts, and the grains' own part of the tilt.
    fn validate_correlations(&self) -> Result<()> {
        // A correlation length: 0 (each grain its own draw) or a length in [0.1, 100] mm.
        for (field, length, own, example) in [
            (
                "domains.diameter_correlation_mm",
                self.diameter_correlation_mm,
                "size",
                2,
            ),
            (
                "domains.tilt_correlation_mm",
                self.tilt_correlation_mm,
                "tilt",
                3,
            ),
        ] {
            if !(length == 0.0 || (0.1..=100.0).contains(&length)) {
                return Err(Error::field(
                    field,
                    format!(
                        "must be 0 (each grain its own {own}) or a number in [0.1, 100], got \
                         {length}; try {example}"
                    ),
                ));
            }
        }
        let jitter = self.tilt_jitter_deg;
        check_range("domains.tilt_jitter_deg", jitter, 0.0, 180.0, 5.0)?;
        if self.tilt_correlation_mm > 0.0 && jitter > self.orientation_spread_deg {
            return Err(Error::field(
                "domains.tilt_jitter_deg",
                format!(
                    "must be in [0, orientation_spread_deg = {spread}] (a grain's part of \
                     the tilt), got {jitter}; try {}, or raise orientation_spread_deg",
                    self.orientation_spread_deg / 4.0,
                    spread = self.orientation_spread_deg
                ),
            ));
        }
        Ok(())
    }
}

/// Built-in environments and files.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum EnvironmentKind {
    /// No environment: only the scene's light, over the backdrop (`render.background`).
    #[default]
    None,
    /// A gem studio: a large softbox overhead, two strip lights at the sides, a dark table.
    Studio,
    /// A window on one side of a dim room.
    Window,
    /// An overcast sky over dark ground.
    Overcast,
    /// A light tent: a white dome lit evenly from outside, the camera looking in through a
    /// port at its top, over black velvet.
    Tent,
    /// The same value from every direction (a furnace: tests and body-tone checks).
    Uniform,
    /// An equirectangular map read from `path` (Radiance `.hdr` or OpenEXR `.exr`).
    File,
}

/// Light from every direction (path integrator only).
///
/// | field          | unit | default | valid                                                     |
/// |----------------|------|---------|-----------------------------------------------------------|
/// | `kind`         | –    | "none"  | "none", "studio", "window", "overcast", "tent", "uniform", "file" |
/// | `path`         | –    | ""      | a `.hdr` or `.exr` file, 2:1; only with "file" |
/// | `intensity`    | –    | 1.0     | [0, 1000]                                      |
/// | `rotation_deg` | deg  | 0.0     | [−360, 360]                                    |
///
/// A relative `path` is taken from the scene file's folder when the scene is read from a
/// file ([`Scene::load`](super::Scene::load), the `opalray` command, `Scene.from_toml` in
/// Python), else from the working directory.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct EnvironmentConfig {
    /// Which environment.
    pub kind: EnvironmentKind,
    /// `kind = "file"`: the equirectangular map, Radiance `.hdr` (RGBE) or OpenEXR `.exr`
    /// (R, G, B half or float), twice as wide as high; its luminance is the value.
    pub path: String,
    /// Scale of its radiance (1: its brightest emitter has luminance about 1; a map's
    /// luminance as it is stored).
    pub intensity: f64,
    /// Turn of the environment about the zenith (z, towards the camera), degrees,
    /// counter-clockwise seen from above.
    pub rotation_deg: f64,
}

impl Default for EnvironmentConfig {
    fn default() -> Self {
        EnvironmentConfig {
            kind: EnvironmentKind::None,
            path: String::new(),
            intensity: 1.0,
            rotation_deg: 0.0,
        }
    }
}

impl EnvironmentConfig {
    /// Check ranges, and that a map is given exactly when `kind = "file"` (its contents are
    /// checked when it is read).
    pub fn validate(&self) -> Result<()> {
        check_range("environment.intensity", self.intensity, 0.0, 1000.0, 1.0)?;
        match (self.kind, self.path.is_empty()) {
            (EnvironmentKind::File, true) => {
                return Err(Error::field(
                    "environment.path",
                    "kind = \"file\" needs a map; set environment.path = \"studio.hdr\" (a \
                     Radiance .hdr or OpenEXR .exr file)",
                ))
            }
            (EnvironmentKind::File, false) => {
                if map_format(Path::new(&self.path)).is_none() {
                    return Err(Error::field(
                        "environment.path",
                        format!(
                            "`{}` is not a .hdr or .exr file; give a Radiance .hdr or an \
                             OpenEXR .exr map",
                            self.path
                        ),
                    ));
                }
            }
            (_, false) => {
                return Err(Error::field(
                    "environment.path",
                    "a map is read only with environment.kind = \"file\"; set that kind or \
                     remove environment.path",
                ))
            }
            (_, true) => {}
        }
        check_range(
            "environment.rotation_deg",
            self.rotation_deg,
            -360.0,
            360.0,
            0.0,
        )
    }
}

/// The file formats of an environment map (`environment.path`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapFormat {
    /// Radiance RGBE (`.hdr`, `.pic`, `.rgbe`).
    Radiance,
    /// OpenEXR (`.exr`).
    OpenExr,
}

/// The format of `path` by its extension (case-insensitive), `None` if neither.
pub fn map_format(path: &Path) -> Option<MapFormat> {
    let ext = path.extension()?.to_str()?.to_ascii_lowercase();
    match ext.as_str() {
        "hdr" | "pic" | "rgbe" => Some(MapFormat::Radiance),
        "exr" => Some(MapFormat::OpenExr),
        _ => None,
    }
}

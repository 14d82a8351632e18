//! The scene: everything a render needs, as plain data with a default for every field.
//!
//! Input: TOML text (a file, a preset) → output: a validated [`Scene`]. Unknown fields are
//! errors naming their path; [`Scene::validate`] checks ranges, NaN and the memory a grid
//! would need before anything is allocated. Field tables: `docs/scene-format.md`.
//!
//! One file a section (`body`, `look`, `stone`, `studio`, `integrator`: the section that
//! chooses the method, each method's settings in its own folder, registered in
//! [`crate::integrator`]); `parse` reads text, values and files, `validate` checks what spans
//! sections, `presets` holds `scenes/*.toml`.

mod body;
mod integrator;
mod look;
mod parse;
mod presets;
mod shape;
mod stone;
mod studio;
mod validate;

pub use crate::integrator::configs::*;
pub use body::{Backing, BodyConfig, Cut};
pub(crate) use integrator::IntegratorFields;
pub use integrator::{check_spp, IntegratorConfig, Method, DEFAULT_SPP, MAX_SPP};
pub use look::{
    CameraConfig, ColorConfig, ColorSpaceChoice, GamutMapping, Illuminant, LightConfig, LightKind,
    RenderConfig, BODY_EXTINCTION_PER_MM,
};
pub use parse::{read_text_limited, MAX_SCENE_FILE_BYTES};
pub use presets::{preset, DEFAULT_RENDER_PRESET, PRESET_NAMES};
pub use stone::{CrystalConfig, Dispersion, StructureConfig, MAX_CELLS};
pub use studio::{
    map_format, DomainsConfig, EnvironmentConfig, EnvironmentKind, FamilyChoice, MapFormat,
    OrientationLaw, Pattern, COLUMN_HEIGHT, OUTLINE_SUBDIVISION,
};
pub(crate) use validate::{check_count, check_positive, check_range};
pub use validate::{MAX_GRAINS, MAX_SPECTRAL_IMAGE_BYTES};

use serde::{Deserialize, Serialize};

use crate::spectrum::WavelengthGrid;

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

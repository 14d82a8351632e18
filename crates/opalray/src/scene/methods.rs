//! Each method's own `[integrator]` settings, a parameter table with defaults apiece
//! (`integrator.rs` holds the section that chooses among them).

use serde::{Deserialize, Serialize};

/// Most samples per pixel of the path integrator (`integrator.spp`).
pub const MAX_SPP: u32 = 65_536;

/// Default samples (camera rays) per pixel (`integrator.spp`).
pub(super) const DEFAULT_SPP: u32 = 16;
/// Default wavelengths per contribution (`integrator.wavelengths`); the stored and lobe
/// methods' wavelength sampler is built with it (they draw no wavelengths).
pub const DEFAULT_WAVELENGTHS: u32 = 4;

/// `max_scatterings`' default: the weight's roulette ends a white body's paths long before.
pub const DEFAULT_MAX_SCATTERINGS: u32 = 1 << 14;

/// The path tracer's settings (`method = "path"`).
///
/// | field         | unit | default | valid          |
/// |---------------|------|---------|----------------|
/// | `spp`         | –    | 16      | 1 ..= 65536    |
/// | `max_depth`   | –    | 8       | 1 ..= 256      |
/// | `max_scatterings` | – | 16384 | 0 ..= 65536  |
/// | `wavelengths` | –    | 4       | 1 ..= 64       |
/// | `seed`        | –    | 0       | 0 ..= 2⁶³ − 1  |
/// | `denoise`     | –    | false   | true, false    |
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct PathConfig {
    /// Samples per pixel (camera rays, each uniform over the pixel: anti-aliasing); with a
    /// time limit, the most that are rendered.
    pub spp: u32,
    /// Most events (surface, domain reflection or crossing, backing) on one path, its
    /// scatterings in the body or a domain's haze not counted: those go on until the path's
    /// weight ends it by Russian roulette, so a light body reaches its tone at any depth.
    pub max_depth: u32,
    /// Most scatterings in the body or a domain's haze on one path (a bound on a path's work,
    /// far past what a white body needs); 0 counts them among `max_depth`'s events, as a
    /// path tracer cut at a depth does.
    pub max_scatterings: u32,
    /// Wavelengths drawn per contribution, stratified over its spectral proposal.
    pub wavelengths: u32,
    /// Seed of the sample streams, mixed with `structure.seed` (which grows the stone):
    /// another value renders the same stone with independent samples.
    pub seed: u64,
    /// Filter the image's noise after the last pass ([`crate::denoise`]): non-local means
    /// between its even and odd samples. Smoother at a small bias; the spectral image is left
    /// unfiltered.
    pub denoise: bool,
}

impl Default for PathConfig {
    fn default() -> Self {
        PathConfig {
            spp: DEFAULT_SPP,
            max_depth: 8,
            max_scatterings: DEFAULT_MAX_SCATTERINGS,
            wavelengths: DEFAULT_WAVELENGTHS,
            seed: 0,
            denoise: false,
        }
    }
}

/// The stored method's settings (`method = "stored"`).
///
/// | field     | unit | default | valid          |
/// |-----------|------|---------|----------------|
/// | `spp`     | –    | 16      | 1 ..= 65536    |
/// | `seed`    | –    | 0       | 0 ..= 2⁶³ − 1  |
/// | `cell_mm` | mm   | 0.15    | [0.02, 2]      |
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct StoredConfig {
    /// Camera rays per pixel, at stratified fixed positions.
    pub spp: u32,
    /// Seed of the sub-pixel positions.
    pub seed: u64,
    /// Edge of the grid cells the light is stored in, mm (finer: the light's direction and
    /// the notches of the domains it crossed follow the stone more closely, at the cube of
    /// the cost).
    pub cell_mm: f64,
}

impl Default for StoredConfig {
    fn default() -> Self {
        StoredConfig {
            spp: DEFAULT_SPP,
            seed: 0,
            cell_mm: 0.15,
        }
    }
}

/// The lobe integrator's settings (`method = "lobe"`).
///
/// | field  | unit | default | valid          |
/// |--------|------|---------|----------------|
/// | `spp`  | –    | 16      | 1 ..= 65536    |
/// | `seed` | –    | 0       | 0 ..= 2⁶³ − 1  |
/// | `trapped` | – | false   | true, false    |
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields, default)]
pub struct LobeConfig {
    /// Rays through each pixel at an edge (one through every pixel's centre, `spp − 1` more,
    /// stratified, where a pixel differs from a neighbour).
    pub spp: u32,
    /// Seed of the sub-pixel positions.
    pub seed: u64,
    /// Walk the strongest reflections that the dome traps by total internal reflection for
    /// their second Bragg reflections (most of the blue the lobe integrator misses against
    /// the path tracer), at 2 to 3 × the render's time; default false (and then not
    /// written out).
    #[serde(skip_serializing_if = "std::ops::Not::not")]
    pub trapped: bool,
}

impl Default for LobeConfig {
    fn default() -> Self {
        LobeConfig {
            spp: DEFAULT_SPP,
            seed: 0,
            trapped: false,
        }
    }
}

/// The paper's two passes take no `[integrator]` field but `method`: their settings are the
/// light's (`light.rays`, `light.cutoff`) and the render's (`render.phong_exponent`).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TwoPassConfig {}

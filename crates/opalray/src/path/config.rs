//! The path tracer's own `[integrator]` settings (`method = "path"`).

use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::film::DEFAULT_WAVELENGTHS;
use crate::integrator::{spp_and_seed_fields, Settings};
use crate::scene::DEFAULT_SPP;

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

impl Settings for PathConfig {
    const NAME: &'static str = "path";
    const FIELDS: &'static [&'static str] = &[
        "spp",
        "max_depth",
        "max_scatterings",
        "wavelengths",
        "seed",
        "denoise",
    ];

    fn validate(&self) -> Result<()> {
        for (field, v, hi, example) in [
            ("integrator.max_depth", self.max_depth, 256, 8),
            ("integrator.wavelengths", self.wavelengths, 64, 4),
        ] {
            if !(1..=hi).contains(&v) {
                return Err(Error::field(
                    field,
                    format!("must be in 1..={hi}, got {v}; try {example}"),
                ));
            }
        }
        if self.max_scatterings > 1 << 16 {
            return Err(Error::field(
                "integrator.max_scatterings",
                format!(
                    "must be in 0..=65536, got {}; try {DEFAULT_MAX_SCATTERINGS}",
                    self.max_scatterings
                ),
            ));
        }
        Ok(())
    }

    spp_and_seed_fields!();
}

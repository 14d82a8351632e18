//! The lobe integrator's own `[integrator]` settings (`method = "lobe"`).

use serde::{Deserialize, Serialize};

use crate::integrator::{spp_and_seed_fields, Settings};
use crate::scene::DEFAULT_SPP;

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

impl Settings for LobeConfig {
    const NAME: &'static str = "lobe";
    const FIELDS: &'static [&'static str] = &["spp", "seed", "trapped"];

    spp_and_seed_fields!();
}

//! The stored method's own `[integrator]` settings (`method = "stored"`).

use serde::{Deserialize, Serialize};

use crate::error::Result;
use crate::integrator::{spp_and_seed_fields, Settings};
use crate::scene::{check_range, DEFAULT_SPP};

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

impl Settings for StoredConfig {
    const NAME: &'static str = "stored";
    const FIELDS: &'static [&'static str] = &["spp", "seed", "cell_mm"];

    fn validate(&self) -> Result<()> {
        check_range("integrator.cell_mm", self.cell_mm, 0.02, 2.0, 0.15)
    }

    spp_and_seed_fields!();
}

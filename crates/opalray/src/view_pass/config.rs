//! The paper's two passes' `[integrator]` settings (`method = "two-pass"`): none.

use serde::{Deserialize, Serialize};

use crate::integrator::Settings;

/// The paper's two passes take no `[integrator]` field but `method`: their settings are the
/// light's (`light.rays`, `light.cutoff`) and the render's (`render.phong_exponent`). They
/// take no samples per pixel, and draw from `structure.seed` alone (their seed reads 0).
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TwoPassConfig {}

impl Settings for TwoPassConfig {
    const NAME: &'static str = "two-pass";
    const FIELDS: &'static [&'static str] = &[];
}

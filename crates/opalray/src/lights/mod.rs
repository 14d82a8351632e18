//! What lights the stone, shared by every integrator that reads the stone model.
//!
//! Input: the scene's `[environment]` and `[light]` sections → output: an [`Environment`]
//! (uniform, studio or a file, importance-sampled) and an [`AreaLight`] (sphere or rect),
//! each evaluated along a ray, sampled from a point and asked for its density, and a
//! [`Lamp`] (point or directional).
//!
//! - [`env`]: the environment around the stone and its sampling;
//! - [`env_map`]: the environment file reader (Radiance `.hdr`, OpenEXR) to luminance;
//! - [`emitters`]: the area lights and what a ray leaving the stone sees;
//! - [`lamp`]: the point or directional light ([`Lamp`]) and the disc the gloss shows of it;
//! - [`lobe_share`]: how much of a narrow lobe of directions an area light fills.
//!
//! Physics as built: `docs/model.md`.

pub mod emitters;
pub mod env;
pub mod env_map;
pub mod lamp;
pub mod lobe_share;

pub use emitters::{AreaLight, LightSample};
pub use env::{EnvSample, Environment};
pub use lamp::Lamp;

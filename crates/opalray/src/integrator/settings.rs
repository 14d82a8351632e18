//! What every method's own `[integrator]` settings answer: their name and fields, their
//! ranges, and the samples and seed where the method takes them. Each method's settings
//! struct lives in its folder (`config.rs`) and implements [`Settings`]; the registration
//! line in `integrator.rs` makes it a variant of `IntegratorConfig`. Settings that hold
//! their samples and seed as `spp` and `seed` fields answer for them with
//! [`spp_and_seed_fields!`].

use std::fmt::Debug;

use serde::de::DeserializeOwned;
use serde::Serialize;

use crate::error::Result;

/// A method's own `[integrator]` settings: a parameter table with a default for every field,
/// read with `#[serde(deny_unknown_fields, default)]`.
pub trait Settings:
    Clone + Debug + Default + PartialEq + Serialize + DeserializeOwned + Send + Sync + 'static
{
    /// Its name in a scene file (`method = "path"`), the kebab-case of its variant.
    const NAME: &'static str;

    /// The `[integrator]` fields it takes besides `method`.
    const FIELDS: &'static [&'static str];

    /// Check the fields' ranges: the first problem as one line naming the field and a fix.
    fn validate(&self) -> Result<()> {
        Ok(())
    }

    /// Samples (camera rays) per pixel, for a method that takes them.
    fn spp(&self) -> Option<u32> {
        None
    }

    /// Set the samples per pixel where the method takes them (`--spp`).
    fn set_spp(&mut self, _spp: u32) {}

    /// The seed of its sample streams (0 for a method that draws none of its own).
    fn seed(&self) -> u64 {
        0
    }

    /// Set the seed of its sample streams where it draws any.
    fn set_seed(&mut self, _seed: u64) {}
}

/// The four [`Settings`] accessors of settings whose samples per pixel and seed are their
/// `spp: u32` and `seed: u64` fields (`spp`, `set_spp`, `seed`, `set_seed`): invoked as
/// `spp_and_seed_fields!();` inside the `impl Settings`.
macro_rules! spp_and_seed_fields {
    () => {
        fn spp(&self) -> Option<u32> {
            Some(self.spp)
        }

        fn set_spp(&mut self, spp: u32) {
            self.spp = spp;
        }

        fn seed(&self) -> u64 {
            self.seed
        }

        fn set_seed(&mut self, seed: u64) {
            self.seed = seed;
        }
    };
}
pub(crate) use spp_and_seed_fields;

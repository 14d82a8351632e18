//! `[integrator]` as a scene file gives it: every field of every method, read before the
//! method's variant takes only its own; a field of another method is refused naming the
//! methods that take it.

use serde::{Deserialize, Serialize};

use super::super::methods::DEFAULT_SPP;
use super::{IntegratorConfig, LobeConfig, Method, PathConfig, StoredConfig, TwoPassConfig};

/// Every field of every method, as a scene file gives them: the form `[integrator]` is read
/// in, before the method's variant takes only its own.
#[derive(Clone, Debug, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub(super) struct IntegratorFields {
    #[serde(default)]
    pub(super) method: Method,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) spp: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) max_depth: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) max_scatterings: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) wavelengths: Option<u32>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) seed: Option<u64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) cell_mm: Option<f64>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) denoise: Option<bool>,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub(super) trapped: Option<bool>,
}

impl IntegratorFields {
    /// The names of the fields given.
    pub(super) fn given(&self) -> Vec<&'static str> {
        [
            ("spp", self.spp.is_some()),
            ("max_depth", self.max_depth.is_some()),
            ("max_scatterings", self.max_scatterings.is_some()),
            ("wavelengths", self.wavelengths.is_some()),
            ("seed", self.seed.is_some()),
            ("cell_mm", self.cell_mm.is_some()),
            ("denoise", self.denoise.is_some()),
            ("trapped", self.trapped.is_some()),
        ]
        .into_iter()
        .filter_map(|(name, given)| given.then_some(name))
        .collect()
    }
}

/// `"path"`, `"path" or "stored"`, … : the methods that take `field`, quoted.
fn owners_of(field: &str) -> String {
    let owners: Vec<String> = Method::ALL
        .iter()
        .filter(|m| m.fields().contains(&field))
        .map(|m| format!("\"{}\"", m.name()))
        .collect();
    owners.join(" or ")
}

/// The one-line refusal of `field` under `method`, naming the methods that take it.
fn foreign_field(field: &str, method: Method) -> String {
    format!(
        "`integrator.{field}` is a field of integrator.method = {owners}, not of \"{name}\"; \
         remove it or set integrator.method = {first}",
        owners = owners_of(field),
        name = method.name(),
        first = owners_of(field).split(" or ").next().unwrap_or_default(),
    )
}

impl TryFrom<IntegratorFields> for IntegratorConfig {
    type Error = String;

    fn try_from(f: IntegratorFields) -> std::result::Result<Self, String> {
        if let Some(field) = f
            .given()
            .into_iter()
            .find(|g| !f.method.fields().contains(g))
        {
            return Err(foreign_field(field, f.method));
        }
        let spp = f.spp.unwrap_or(DEFAULT_SPP);
        let seed = f.seed.unwrap_or(0);
        Ok(match f.method {
            Method::TwoPass => IntegratorConfig::TwoPass(TwoPassConfig {}),
            Method::Path => {
                let d = PathConfig::default();
                IntegratorConfig::Path(PathConfig {
                    spp,
                    max_depth: f.max_depth.unwrap_or(d.max_depth),
                    max_scatterings: f.max_scatterings.unwrap_or(d.max_scatterings),
                    wavelengths: f.wavelengths.unwrap_or(d.wavelengths),
                    seed,
                    denoise: f.denoise.unwrap_or(d.denoise),
                })
            }
            Method::Stored => IntegratorConfig::Stored(StoredConfig {
                spp,
                seed,
                cell_mm: f.cell_mm.unwrap_or(StoredConfig::default().cell_mm),
            }),
            Method::Lobe => IntegratorConfig::Lobe(LobeConfig {
                spp,
                seed,
                trapped: f.trapped.unwrap_or(false),
            }),
        })
    }
}

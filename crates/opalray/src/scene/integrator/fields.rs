//! `[integrator]` as a scene file gives it: `method` and the fields given, each read with the
//! type of a method that takes it (so a wrong type is named by its field and line), before
//! the method's variant takes only its own; a field of another method is refused naming the
//! methods that take it.

use std::fmt;
use std::sync::OnceLock;

use serde::de::{DeserializeSeed, Deserializer, Error as _, MapAccess, Visitor};
use serde::Deserialize;

use super::{IntegratorConfig, Method};

/// The section as a scene file gives it: the method (`"two-pass"` when not given) and the
/// fields given besides it, before the method's variant takes only its own.
#[derive(Clone, Debug, Default)]
pub struct IntegratorFields {
    /// `integrator.method`.
    method: Method,
    /// The other fields given, each of the type of a method that takes it.
    given: toml::Table,
}

/// Every method's fields, each once, in the order of [`Method::ALL`] and of each method's
/// [`Method::fields`].
fn every_field() -> &'static [&'static str] {
    static FIELDS: OnceLock<Vec<&'static str>> = OnceLock::new();
    FIELDS.get_or_init(|| {
        let mut fields = vec!["method"];
        for field in Method::ALL.iter().flat_map(|m| m.fields()) {
            if !fields.contains(field) {
                fields.push(field);
            }
        }
        fields
    })
}

/// One field's value, read as a TOML value and checked against the type its first owner
/// gives it; a field no method takes is refused at its value, so that the error names it.
struct FieldOf {
    owner: Option<Method>,
    name: String,
}

impl<'de> DeserializeSeed<'de> for FieldOf {
    type Value = toml::Value;

    fn deserialize<D: Deserializer<'de>>(self, d: D) -> Result<toml::Value, D::Error> {
        let Some(owner) = self.owner else {
            return Err(D::Error::unknown_field(&self.name, every_field()));
        };
        let value = toml::Value::deserialize(d)?;
        let alone = toml::Table::from_iter([(self.name, value.clone())]);
        IntegratorConfig::from_given(owner, alone).map_err(|e| D::Error::custom(e.message()))?;
        Ok(value)
    }
}

/// Reads the section's table into [`IntegratorFields`].
struct FieldsVisitor;

impl<'de> Visitor<'de> for FieldsVisitor {
    type Value = IntegratorFields;

    fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
        f.write_str("struct IntegratorFields")
    }

    fn visit_map<A: MapAccess<'de>>(self, mut map: A) -> Result<IntegratorFields, A::Error> {
        let mut fields = IntegratorFields::default();
        while let Some(name) = map.next_key::<String>()? {
            if name == "method" {
                fields.method = map.next_value()?;
                continue;
            }
            let owner = Method::ALL
                .into_iter()
                .find(|m| m.fields().iter().any(|f| *f == name));
            let value = map.next_value_seed(FieldOf {
                owner,
                name: name.clone(),
            })?;
            fields.given.insert(name, value);
        }
        Ok(fields)
    }
}

impl<'de> Deserialize<'de> for IntegratorFields {
    fn deserialize<D: Deserializer<'de>>(d: D) -> Result<Self, D::Error> {
        d.deserialize_map(FieldsVisitor)
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
        if let Some(field) = every_field()
            .iter()
            .find(|name| f.given.contains_key(**name) && !f.method.fields().contains(name))
        {
            return Err(foreign_field(field, f.method));
        }
        IntegratorConfig::from_given(f.method, f.given).map_err(|e| e.message().to_string())
    }
}

//! Shapes the typed parse alone would let through: a fixed array given too many values
//! (serde reads the first two or three and drops the rest), a TOML array where a section (table)
//! is expected (serde fills a struct by position), and errors without a field path (a
//! number too large for TOML itself).

use std::fmt;
use std::marker::PhantomData;

use serde::de::{self, Deserializer, SeqAccess, Visitor};
use serde::Deserialize;

/// Deserialize exactly three values; more or fewer is an error naming the count.
pub(crate) fn three<'de, D, T>(deserializer: D) -> Result<[T; 3], D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    exactly(deserializer, "(x, y, z)")
}

/// Deserialize exactly two values (a width and a height); more or fewer is an error naming
/// the count.
pub(crate) fn two<'de, D, T>(deserializer: D) -> Result<[T; 2], D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    exactly(deserializer, "(width, height)")
}

/// Deserialize exactly `N` values, described as `what` in errors; more or fewer is an error
/// naming the count (serde's own arrays read the first `N` and drop the rest).
fn exactly<'de, D, T, const N: usize>(
    deserializer: D,
    what: &'static str,
) -> Result<[T; N], D::Error>
where
    D: Deserializer<'de>,
    T: Deserialize<'de>,
{
    struct Exactly<T, const N: usize>(&'static str, PhantomData<T>);
    impl<'de, T: Deserialize<'de>, const N: usize> Visitor<'de> for Exactly<T, N> {
        type Value = [T; N];
        fn expecting(&self, f: &mut fmt::Formatter) -> fmt::Result {
            write!(f, "an array of exactly {N} values {}", self.0)
        }
        fn visit_seq<A: SeqAccess<'de>>(self, mut seq: A) -> Result<[T; N], A::Error> {
            let mut values = Vec::with_capacity(N);
            while let Some(v) = seq.next_element::<T>()? {
                values.push(v);
                if values.len() > N {
                    // Count the rest without keeping them.
                    let mut n = values.len();
                    while seq.next_element::<de::IgnoredAny>()?.is_some() {
                        n += 1;
                    }
                    return Err(de::Error::invalid_length(n, &self));
                }
            }
            let n = values.len();
            values
                .try_into()
                .map_err(|_| de::Error::invalid_length(n, &self))
        }
    }
    deserializer.deserialize_seq(Exactly::<T, N>(what, PhantomData))
}

/// The dotted path of the first value in `given` that is not a table where `template` (the
/// default scene as TOML) has one, with what was found.
pub(crate) fn misplaced_table(
    given: &toml::Table,
    template: &toml::Table,
    prefix: &str,
) -> Option<(String, &'static str)> {
    for (key, value) in given {
        let Some(toml::Value::Table(expected)) = template.get(key) else {
            continue;
        };
        let path = if prefix.is_empty() {
            key.clone()
        } else {
            format!("{prefix}.{key}")
        };
        match value {
            toml::Value::Table(inner) => {
                if let Some(found) = misplaced_table(inner, expected, &path) {
                    return Some(found);
                }
            }
            other => return Some((path, other.type_str())),
        }
    }
    None
}

/// The dotted path of the key assigned on the line holding byte `offset` of `text`: the
/// last `[section]` header above it and the key before its `=`.
pub(crate) fn key_at(text: &str, offset: usize) -> Option<String> {
    let offset = offset.min(text.len());
    let start = text[..offset].rfind('\n').map_or(0, |i| i + 1);
    let line = text[start..].lines().next()?;
    let key = line.split_once('=')?.0.trim();
    if key.is_empty() || key.starts_with('[') {
        return None;
    }
    let section = text[..start].lines().rev().find_map(|l| {
        let l = l.trim();
        l.strip_prefix('[')?.strip_suffix(']').map(str::trim)
    });
    Some(match section {
        Some(s) => format!("{s}.{key}"),
        None => key.to_string(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn key_at_names_section_and_key() {
        let text = "[render]\nwidth = 99999999999999999999\n";
        assert_eq!(key_at(text, 20).as_deref(), Some("render.width"));
        assert_eq!(key_at("a = 1", 2).as_deref(), Some("a"));
        assert_eq!(key_at("[render]", 2), None);
    }
}

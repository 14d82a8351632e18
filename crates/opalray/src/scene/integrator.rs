//! The `[integrator]` section: which renderer, and that renderer's own settings. Each method
//! is its own variant with its own fields, so a field of another method is refused by name
//! (`method = "..."` selects the variant; a missing `method` is `"two-pass"`). The methods,
//! their variants and their settings are registered in one list ([`crate::integrator`]);
//! this module knows none of them: it reads the section (`fields.rs`), switches methods and
//! checks what every method shares (`spp`, `seed`). What each method refuses of the rest of
//! the scene is its own check (`crate::integrator`).

pub use crate::integrator::{IntegratorConfig, Method};

use crate::error::{Error, Result};

mod fields;

pub use fields::IntegratorFields;

/// Most samples per pixel (`integrator.spp`).
pub const MAX_SPP: u32 = 65_536;

/// Default samples (camera rays) per pixel (`integrator.spp`), of every method that takes
/// them.
pub const DEFAULT_SPP: u32 = 16;

impl Default for IntegratorConfig {
    fn default() -> Self {
        IntegratorConfig::of(Method::default())
    }
}

impl IntegratorConfig {
    /// The same settings under `method` (`--method`, Python's `method=`): the fields `method`
    /// takes are kept, the others dropped; what is not given takes `method`'s defaults.
    pub fn switched(&self, method: Method) -> Self {
        let mut given = self.given();
        given.retain(|name, _| method.fields().contains(&name));
        IntegratorConfig::from_given(method, given).expect("only the method's own fields are kept")
    }

    /// The fields as the section writes them, less `method`.
    fn given(&self) -> toml::Table {
        let mut given = match toml::Value::try_from(self) {
            Ok(toml::Value::Table(table)) => table,
            _ => unreachable!("an integrator serialises to a TOML table"),
        };
        given.remove("method");
        given
    }

    /// The boolean field `name` (`"denoise"`, `"trapped"`) where the method takes it, else
    /// `None` (one the section does not write out is false).
    pub fn flag(&self, name: &str) -> Option<bool> {
        self.method().fields().contains(&name).then(|| {
            self.given()
                .get(name)
                .and_then(toml::Value::as_bool)
                .unwrap_or(false)
        })
    }

    /// Set the boolean field `name` (`--denoise`) where the method takes it; false, and
    /// nothing changed, where it takes no such boolean field.
    pub fn set_flag(&mut self, name: &str, on: bool) -> bool {
        if !self.method().fields().contains(&name) {
            return false;
        }
        let mut given = self.given();
        given.insert(name.to_string(), toml::Value::Boolean(on));
        match IntegratorConfig::from_given(self.method(), given) {
            Ok(switched) => {
                *self = switched;
                true
            }
            Err(_) => false,
        }
    }

    /// Check ranges: the samples per pixel and the seed where the method takes them, then
    /// the method's own fields.
    pub fn validate(&self) -> Result<()> {
        if let Some(spp) = self.spp() {
            check_spp(spp)?;
        }
        self.validate_settings()?;
        if i64::try_from(self.seed()).is_err() {
            return Err(Error::field(
                "integrator.seed",
                format!(
                    "must be at most {} (TOML integers are signed 64-bit), got {}; try 0",
                    i64::MAX,
                    self.seed()
                ),
            ));
        }
        Ok(())
    }
}

/// Check a samples-per-pixel count (`integrator.spp`, `--spp`): 1 ..= [`MAX_SPP`].
pub fn check_spp(spp: u32) -> Result<()> {
    if (1..=MAX_SPP).contains(&spp) {
        Ok(())
    } else {
        Err(Error::field(
            "integrator.spp",
            format!("must be in 1..={MAX_SPP}, got {spp}; try {DEFAULT_SPP}"),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::configs::{LobeConfig, PathConfig, StoredConfig};
    use crate::Scene;

    #[test]
    fn a_field_of_another_method_is_refused_naming_it_and_its_method() {
        for (text, field, owner) in [
            (
                "method = \"path\"\ncell_mm = 0.2",
                "integrator.cell_mm",
                "\"stored\"",
            ),
            (
                "method = \"lobe\"\nmax_depth = 8",
                "integrator.max_depth",
                "\"path\"",
            ),
            (
                "method = \"stored\"\ndenoise = true",
                "integrator.denoise",
                "\"path\"",
            ),
            ("spp = 4", "integrator.spp", "\"lobe\""),
            (
                "method = \"path\"\ntrapped = true",
                "integrator.trapped",
                "\"lobe\"",
            ),
            (
                "method = \"lobe\"\nwavelengths = 4",
                "integrator.wavelengths",
                "\"path\"",
            ),
        ] {
            let text = format!("[integrator]\n{text}\n");
            let err = Scene::from_toml_str(&text, "t").unwrap_err().to_string();
            assert!(err.contains(field), "{text}: {err}");
            assert!(err.contains(owner), "{text}: {err}");
            assert!(!err.contains('\n'), "one line: {err}");
        }
    }

    #[test]
    fn each_method_takes_its_own_fields_and_round_trips() {
        for method in Method::ALL {
            let fields: String = method
                .fields()
                .iter()
                .map(|f| match *f {
                    "denoise" | "trapped" => format!("{f} = true\n"),
                    "cell_mm" => "cell_mm = 0.25\n".to_string(),
                    other => format!("{other} = 3\n"),
                })
                .collect();
            let text = format!("[integrator]\nmethod = \"{}\"\n{fields}", method.name());
            let scene = Scene::from_toml_str(&text, "t").unwrap();
            assert_eq!(scene.integrator.method(), method);
            assert_eq!(Scene::from_toml_str(&scene.to_toml(), "t").unwrap(), scene);
        }
    }

    #[test]
    fn switching_method_keeps_the_fields_the_new_one_takes() {
        let path = IntegratorConfig::Path(PathConfig {
            spp: 5,
            max_depth: 3,
            max_scatterings: 100,
            wavelengths: 2,
            seed: 7,
            denoise: true,
        });
        assert_eq!(
            path.switched(Method::Lobe),
            IntegratorConfig::Lobe(LobeConfig {
                spp: 5,
                seed: 7,
                trapped: false
            })
        );
        assert_eq!(
            path.switched(Method::Stored),
            IntegratorConfig::Stored(StoredConfig {
                spp: 5,
                seed: 7,
                cell_mm: 0.15
            })
        );
        assert_eq!(path.switched(Method::TwoPass), IntegratorConfig::default());
        assert_eq!(
            IntegratorConfig::default().switched(Method::Path),
            IntegratorConfig::of(Method::Path)
        );
    }
}

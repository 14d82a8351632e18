//! The `[integrator]` section: which renderer, and that renderer's own settings. Each method
//! is its own variant with its own fields, so a field of another method is refused by name
//! (`method = "..."` selects the variant; a missing `method` is `"two-pass"`). What each
//! method refuses of the rest of the scene is its own check (`crate::integrator`).

use serde::{Deserialize, Serialize};

pub use super::methods::{
    LobeConfig, PathConfig, StoredConfig, TwoPassConfig, DEFAULT_WAVELENGTHS, MAX_SPP,
};

use super::check_range;
use super::methods::{DEFAULT_MAX_SCATTERINGS, DEFAULT_SPP};
use crate::error::{Error, Result};

mod fields;

use fields::IntegratorFields;

/// Which renderer.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize, Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum Method {
    /// The paper's two passes on the cell grid (light stored per cluster, eq. (2) from the eye).
    #[default]
    TwoPass,
    /// The spectral path tracer on the stone model: domains as geometry, every plane family,
    /// the rocking width, lines evaluated at exact wavelengths.
    Path,
    /// The paper's two passes on the stone model: light stored per grid cell of the stone,
    /// then gathered from the eye (eq. (2)), each domain's lines at their exact wavelengths.
    /// Single reflection only; deterministic, no noise (`integrator.spp`, `cell_mm`).
    Stored,
    /// The lobe integrator on the stone model: every Bragg lobe integrated against the
    /// environment and the light, the body as its Munsell value; deterministic, no noise,
    /// seconds a frame (`integrator.spp`: stratified sub-pixel positions).
    Lobe,
}

impl Method {
    /// Every method, in the order the docs list them.
    pub const ALL: [Method; 4] = [Method::TwoPass, Method::Path, Method::Stored, Method::Lobe];

    /// Its name in a scene file (`"two-pass"`, `"path"`, …).
    pub fn name(self) -> &'static str {
        match self {
            Method::TwoPass => "two-pass",
            Method::Path => "path",
            Method::Stored => "stored",
            Method::Lobe => "lobe",
        }
    }

    /// The `[integrator]` fields it takes besides `method`.
    pub fn fields(self) -> &'static [&'static str] {
        match self {
            Method::TwoPass => &[],
            Method::Path => &[
                "spp",
                "max_depth",
                "max_scatterings",
                "wavelengths",
                "seed",
                "denoise",
            ],
            Method::Stored => &["spp", "seed", "cell_mm"],
            Method::Lobe => &["spp", "seed", "trapped"],
        }
    }
}

/// The integrator: `method` and that method's own fields (docs/scene-format.md).
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
#[serde(
    tag = "method",
    rename_all = "kebab-case",
    try_from = "IntegratorFields"
)]
pub enum IntegratorConfig {
    /// The paper's two passes on the cell grid.
    TwoPass(TwoPassConfig),
    /// The spectral path tracer.
    Path(PathConfig),
    /// The paper's two passes on the stone model.
    Stored(StoredConfig),
    /// The lobe integrator.
    Lobe(LobeConfig),
}

impl Default for IntegratorConfig {
    fn default() -> Self {
        IntegratorConfig::of(Method::TwoPass)
    }
}

impl IntegratorConfig {
    /// The defaults of `method`.
    pub fn of(method: Method) -> Self {
        IntegratorConfig::try_from(IntegratorFields {
            method,
            ..IntegratorFields::default()
        })
        .expect("no field given: every method takes that")
    }

    /// The method.
    pub fn method(&self) -> Method {
        match self {
            IntegratorConfig::TwoPass(_) => Method::TwoPass,
            IntegratorConfig::Path(_) => Method::Path,
            IntegratorConfig::Stored(_) => Method::Stored,
            IntegratorConfig::Lobe(_) => Method::Lobe,
        }
    }

    /// Every field given, as the section reads.
    fn fields(&self) -> IntegratorFields {
        let value = toml::Value::try_from(self).expect("an integrator serialises to TOML");
        value
            .try_into()
            .expect("an integrator's TOML reads back as fields")
    }

    /// The same settings under `method` (`--method`, Python's `method=`): the fields `method`
    /// takes are kept, the others dropped; what is not given takes `method`'s defaults.
    pub fn switched(&self, method: Method) -> Self {
        let mut f = self.fields();
        f.method = method;
        let keep = method.fields();
        let given = f.given();
        let drop = |name: &str| !keep.contains(&name) && given.contains(&name);
        if drop("spp") {
            f.spp = None;
        }
        if drop("seed") {
            f.seed = None;
        }
        if drop("max_depth") {
            f.max_depth = None;
        }
        if drop("max_scatterings") {
            f.max_scatterings = None;
        }
        if drop("wavelengths") {
            f.wavelengths = None;
        }
        if drop("cell_mm") {
            f.cell_mm = None;
        }
        if drop("denoise") {
            f.denoise = None;
        }
        if drop("trapped") {
            f.trapped = None;
        }
        IntegratorConfig::try_from(f).expect("only the method's own fields are kept")
    }

    /// Samples (camera rays) per pixel, for a method that takes them.
    pub fn spp(&self) -> Option<u32> {
        match self {
            IntegratorConfig::TwoPass(_) => None,
            IntegratorConfig::Path(c) => Some(c.spp),
            IntegratorConfig::Stored(c) => Some(c.spp),
            IntegratorConfig::Lobe(c) => Some(c.spp),
        }
    }

    /// Set the samples per pixel where the method takes them (`--spp`); the paper's two
    /// passes take none, and are left as they are.
    pub fn set_spp(&mut self, spp: u32) {
        match self {
            IntegratorConfig::TwoPass(_) => {}
            IntegratorConfig::Path(c) => c.spp = spp,
            IntegratorConfig::Stored(c) => c.spp = spp,
            IntegratorConfig::Lobe(c) => c.spp = spp,
        }
    }

    /// Set the seed of the sample streams where the method draws any; the paper's two passes
    /// (which draw from `structure.seed`) are left as they are.
    pub fn set_seed(&mut self, seed: u64) {
        match self {
            IntegratorConfig::TwoPass(_) => {}
            IntegratorConfig::Path(c) => c.seed = seed,
            IntegratorConfig::Stored(c) => c.seed = seed,
            IntegratorConfig::Lobe(c) => c.seed = seed,
        }
    }

    /// The seed of the sample streams (0 for the two passes, which draw from
    /// `structure.seed` alone).
    pub fn seed(&self) -> u64 {
        match self {
            IntegratorConfig::TwoPass(_) => 0,
            IntegratorConfig::Path(c) => c.seed,
            IntegratorConfig::Stored(c) => c.seed,
            IntegratorConfig::Lobe(c) => c.seed,
        }
    }

    /// Check ranges.
    pub fn validate(&self) -> Result<()> {
        if let Some(spp) = self.spp() {
            check_spp(spp)?;
        }
        if let IntegratorConfig::Path(c) = self {
            for (field, v, hi, example) in [
                ("integrator.max_depth", c.max_depth, 256, 8),
                ("integrator.wavelengths", c.wavelengths, 64, 4),
            ] {
                if !(1..=hi).contains(&v) {
                    return Err(Error::field(
                        field,
                        format!("must be in 1..={hi}, got {v}; try {example}"),
                    ));
                }
            }
            if c.max_scatterings > 1 << 16 {
                return Err(Error::field(
                    "integrator.max_scatterings",
                    format!(
                        "must be in 0..=65536, got {}; try {DEFAULT_MAX_SCATTERINGS}",
                        c.max_scatterings
                    ),
                ));
            }
        }
        if let IntegratorConfig::Stored(c) = self {
            check_range("integrator.cell_mm", c.cell_mm, 0.02, 2.0, 0.15)?;
        }
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

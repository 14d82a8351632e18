//! The one list of methods, made into what the rest of the crate reads: `register_methods!`
//! turns `Variant(module::Config, integrator)` lines into the `Method` enum (its `ALL`, name
//! and fields), the `[integrator]` section's `IntegratorConfig` (a variant a method, its
//! settings dispatched to the method's [`Settings`](super::Settings)), the table
//! `INTEGRATORS` with `of(method)`, and the re-export of every method's settings struct
//! (`configs`). A new method is one line of the list in `integrator.rs`.

/// Generate the methods' enum, the `[integrator]` section's enum and the integrators' table
/// from one list: `/// docs` then `Variant(module::Config, integrator)` per method, the
/// first the default (a scene without `integrator.method`).
macro_rules! register_methods {
    ($(
        $(#[doc = $doc:literal])*
        $variant:ident($module:ident :: $config:ident, $integrator:path)
    ),+ $(,)?) => {
        /// Every method's own `[integrator]` settings, each from its method's folder.
        pub mod configs {
            $(pub use crate::$module::$config;)+
        }

        /// How many methods are registered.
        const COUNT: usize = [$(stringify!($variant)),+].len();

        /// Which renderer (`integrator.method`).
        #[derive(Clone, Copy, Debug, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
        #[serde(rename_all = "kebab-case")]
        pub enum Method {
            $($(#[doc = $doc])* $variant,)+
        }

        impl Default for Method {
            /// The first registered: a scene without `integrator.method`.
            fn default() -> Self {
                Method::ALL[0]
            }
        }

        impl Method {
            /// Every method, in the order the docs list them.
            pub const ALL: [Method; COUNT] = [$(Method::$variant),+];

            /// Its name in a scene file (`"two-pass"`, `"path"`, …).
            pub fn name(self) -> &'static str {
                match self {
                    $(Method::$variant => <configs::$config as Settings>::NAME,)+
                }
            }

            /// The `[integrator]` fields it takes besides `method`.
            pub fn fields(self) -> &'static [&'static str] {
                match self {
                    $(Method::$variant => <configs::$config as Settings>::FIELDS,)+
                }
            }
        }

        /// The integrator: `method` and that method's own fields (docs/scene-format.md).
        #[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
        #[serde(
            tag = "method",
            rename_all = "kebab-case",
            try_from = "crate::scene::IntegratorFields"
        )]
        pub enum IntegratorConfig {
            $($(#[doc = $doc])* $variant(configs::$config),)+
        }

        impl IntegratorConfig {
            /// The method.
            pub fn method(&self) -> Method {
                match self {
                    $(IntegratorConfig::$variant(_) => Method::$variant,)+
                }
            }

            /// The defaults of `method`.
            pub fn of(method: Method) -> Self {
                match method {
                    $(Method::$variant => IntegratorConfig::$variant(Default::default()),)+
                }
            }

            /// `method`'s settings from the fields `given` (each a field it takes), the
            /// others at their defaults.
            pub(crate) fn from_given(
                method: Method,
                given: toml::Table,
            ) -> std::result::Result<Self, toml::de::Error> {
                let given = toml::Value::Table(given);
                Ok(match method {
                    $(Method::$variant => IntegratorConfig::$variant(given.try_into()?),)+
                })
            }

            /// Samples (camera rays) per pixel, for a method that takes them.
            pub fn spp(&self) -> Option<u32> {
                match self {
                    $(IntegratorConfig::$variant(c) => Settings::spp(c),)+
                }
            }

            /// Set the samples per pixel where the method takes them (`--spp`); a method
            /// that takes none (the paper's two passes) is left as it is.
            pub fn set_spp(&mut self, spp: u32) {
                match self {
                    $(IntegratorConfig::$variant(c) => Settings::set_spp(c, spp),)+
                }
            }

            /// The seed of the sample streams (0 for the two passes, which draw from
            /// `structure.seed` alone).
            pub fn seed(&self) -> u64 {
                match self {
                    $(IntegratorConfig::$variant(c) => Settings::seed(c),)+
                }
            }

            /// Set the seed of the sample streams where the method draws any; a method
            /// that draws none of its own (the paper's two passes, which draw from
            /// `structure.seed`) is left as it is.
            pub fn set_seed(&mut self, seed: u64) {
                match self {
                    $(IntegratorConfig::$variant(c) => Settings::set_seed(c, seed),)+
                }
            }

            /// The method's own ranges ([`Settings::validate`]).
            pub(crate) fn validate_settings(&self) -> crate::error::Result<()> {
                match self {
                    $(IntegratorConfig::$variant(c) => Settings::validate(c),)+
                }
            }
        }

        /// Every integrator, one a method, in [`Method::ALL`]'s order.
        pub static INTEGRATORS: [&dyn Integrator; COUNT] = [$(&$integrator),+];

        /// The integrator of `method`.
        pub fn of(method: Method) -> &'static dyn Integrator {
            match method {
                $(Method::$variant => &$integrator,)+
            }
        }
    };
}

pub(crate) use register_methods;

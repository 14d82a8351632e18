//! The integrator seam: what every renderer answers, and the one table of them.
//!
//! Each method lives in its own folder with a `method.rs` that implements [`Integrator`]:
//! what it refuses of a scene (one line naming the field), the memory of its own data, the
//! inputs it builds once and its frame for one light angle. `render.rs` and the CLI ask the
//! table ([`of`]); nothing else matches on the method. A new integrator is its folder (its
//! `method.rs` and its settings, a [`Settings`] in `config.rs`) and one line in the list
//! below, which makes its [`Method`], its [`IntegratorConfig`] variant (the `[integrator]`
//! section) and its line in [`INTEGRATORS`]. The methods that render the stone model start
//! each frame from `Prepared::frame_setup`.

mod frame_setup;
mod passes;
mod registry;
mod settings;

pub(crate) use passes::RowCounter;
pub use passes::{PassReport, Passes, RowsReport};
pub(crate) use settings::spp_and_seed_fields;
pub use settings::Settings;

use crate::error::Result;
use crate::render::{Frame, Prepared};
use crate::scene::Scene;

registry::register_methods! {
    /// The paper's two passes on the cell grid (light stored per cluster, eq. (2) from the eye).
    TwoPass(view_pass::TwoPassConfig, crate::view_pass::TwoPass),
    /// The spectral path tracer on the stone model: domains as geometry, every plane family,
    /// the rocking width, lines evaluated at exact wavelengths.
    Path(path::PathConfig, crate::path::PathTracer),
    /// The paper's two passes on the stone model: light stored per grid cell of the stone,
    /// then gathered from the eye (eq. (2)), each domain's lines at their exact wavelengths.
    /// Single reflection only; deterministic, no noise (`integrator.spp`, `cell_mm`).
    Stored(stored::StoredConfig, crate::stored::StoredMethod),
    /// The lobe integrator on the stone model: every Bragg lobe integrated against the
    /// environment and the light, the body as its Munsell value; deterministic, no noise,
    /// seconds a frame (`integrator.spp`: stratified sub-pixel positions).
    Lobe(lobe::LobeConfig, crate::lobe::LobeMethod),
}

/// A renderer of the scene.
pub trait Integrator: Sync {
    /// The method it renders (`integrator.method`).
    fn method(&self) -> Method;

    /// What it refuses of `scene` (already range-checked by [`Scene::validate`]): the first
    /// problem as one line naming the field and a fix.
    fn check(&self, scene: &Scene) -> Result<()>;

    /// Peak bytes of its own data for `scene`, beyond the image, the structure, the optics
    /// and the light rays every render is budgeted for (the CLI's memory model).
    fn memory_bytes(&self, _scene: &Scene) -> f64 {
        0.0
    }

    /// Whether it renders in passes, so that a time limit and a report after each pass mean
    /// something (`--time-limit`, Python's `time_limit`).
    fn renders_in_passes(&self) -> bool {
        false
    }

    /// Whether it sees the environment light (`[environment]`).
    fn sees_environment(&self) -> bool {
        true
    }

    /// The key of its section of the statistics (`--stats`, the Python frame's stats), where
    /// its frames carry a [`Report`](crate::render::Report); every frame's statistics hold
    /// the key, null for a frame of another method.
    fn stats_key(&self) -> Option<&'static str> {
        None
    }

    /// Whether it renders the stone model (`Stone::new`: its grains grown, its map drawn by
    /// `opalray structure`) rather than the paper's cell grid.
    fn renders_stone(&self) -> bool {
        true
    }

    /// The work of rendering `scene` `frames` times, less the stone's grains (the CLI's time
    /// estimate, said up front when it is long): its rays and their processor seconds, as
    /// measured on the 2-core development machine (`BENCHMARKS.md`, "The work estimate's
    /// costs").
    fn work(&self, scene: &Scene, frames: f64) -> Work;

    /// Build, into `prepared`, the inputs it reads that do not depend on the light angle,
    /// timing them into `prepared.times`.
    fn prepare(&self, prepared: &mut Prepared) -> Result<()>;

    /// Its frame for light angle `light_angle_deg` (degrees, fig. 10), in passes as `passes`
    /// says where it renders in passes.
    fn render(&self, prepared: &Prepared, light_angle_deg: f64, passes: &Passes) -> Frame;
}

/// What rendering a scene's frames costs a method, by its terms ([`Integrator::work`]).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Work {
    /// Path-traced samples, pixels × samples per pixel × frames.
    pub samples: f64,
    /// Camera rays of the lobe integrator or the stored method, at most pixels × `spp` ×
    /// frames, or the pixels of the two passes.
    pub rays: f64,
    /// Light rays of the two passes, `light.rays` × frames.
    pub light_rays: f64,
    /// Processor seconds of the whole.
    pub cpu_s: f64,
}

/// The pixels of `scene`'s image rendered `frames` times.
pub fn pixels(scene: &Scene, frames: f64) -> f64 {
    f64::from(scene.render.width) * f64::from(scene.render.height) * frames
}

/// Check `scene`: its fields' ranges ([`Scene::validate`]), then what its method refuses.
pub fn check(scene: &Scene) -> Result<()> {
    scene.validate()?;
    of(scene.integrator.method()).check(scene)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_method_has_one_integrator() {
        for method in Method::ALL {
            let n = INTEGRATORS.iter().filter(|i| i.method() == method).count();
            assert_eq!(n, 1, "{method:?}");
        }
    }

    #[test]
    fn each_method_is_named_in_a_scene_as_its_settings_say() {
        // The list's variants are named by serde's kebab-case, the settings by `NAME`.
        for method in Method::ALL {
            let serde_name = serde_json::to_value(method).unwrap();
            assert_eq!(serde_name, method.name(), "{method:?}");
            let config = IntegratorConfig::of(method);
            assert_eq!(config.method(), method);
            let toml = toml::Value::try_from(&config).unwrap();
            assert_eq!(toml["method"].as_str(), Some(method.name()));
        }
    }

    #[test]
    fn a_flag_is_set_only_where_the_method_takes_it() {
        let mut path = IntegratorConfig::of(Method::Path);
        assert_eq!(path.flag("denoise"), Some(false));
        assert!(path.set_flag("denoise", true));
        assert_eq!(path.flag("denoise"), Some(true));
        assert_eq!(path.switched(Method::Path), path);
        let mut lobe = IntegratorConfig::of(Method::Lobe);
        assert!(!lobe.set_flag("denoise", true));
        assert_eq!(lobe, IntegratorConfig::of(Method::Lobe));
        assert_eq!(lobe.flag("denoise"), None);
        // A boolean field left at false is not written out, and reads false.
        assert_eq!(lobe.flag("trapped"), Some(false));
        assert!(lobe.set_flag("trapped", true));
        assert_eq!(lobe.flag("trapped"), Some(true));
        // A field that is no boolean is not set.
        assert!(!path.set_flag("spp", true));
    }

    /// `text` under `check`: refused, naming `field`, on one line.
    fn refused(text: &str, field: &str) {
        let scene = Scene::from_toml_str(text, "t").unwrap();
        let err = check(&scene).unwrap_err().to_string();
        assert!(err.contains(field), "{text}: {err}");
        assert!(!err.contains('\n'), "one line: {err}");
    }

    #[test]
    fn each_method_refuses_what_it_cannot_render() {
        for (text, field) in [
            ("[environment]\nkind = \"studio\"", "environment.kind"),
            ("[light]\nkind = \"none\"", "light.kind"),
            ("[light]\nkind = \"sphere\"", "light.kind"),
            ("[light]\nkind = \"rect\"", "light.kind"),
            (
                "[integrator]\nmethod = \"stored\"\n[environment]\nkind = \"studio\"",
                "environment.kind",
            ),
            (
                "[integrator]\nmethod = \"stored\"\n[light]\nkind = \"sphere\"",
                "light.kind",
            ),
            (
                "[integrator]\nmethod = \"stored\"\n[light]\nkind = \"none\"",
                "light.kind",
            ),
            (
                "[integrator]\nmethod = \"stored\"\n[body]\ncut = \"triplet\"",
                "body.cut",
            ),
            (
                "[integrator]\nmethod = \"stored\"\ncell_mm = 0.02",
                "integrator.cell_mm",
            ),
        ] {
            refused(text, field);
        }
        // What the path tracer and the lobe integrator take passes.
        for text in [
            "[light]\nkind = \"sphere\"\nradius_mm = 20.0\n[environment]\nkind = \"studio\"",
            "[light]\nkind = \"none\"\n[environment]\nkind = \"studio\"",
        ] {
            for method in ["path", "lobe"] {
                let text = format!("[integrator]\nmethod = \"{method}\"\n{text}");
                check(&Scene::from_toml_str(&text, "t").unwrap()).unwrap();
            }
        }
    }
}

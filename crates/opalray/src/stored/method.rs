//! The stored method as an integrator (`integrator.method = "stored"`): what it refuses, the
//! memory of its light grid, and its frame (the light stored, then gathered from the eye).

use std::time::Instant;

use crate::error::{Error, Result};
use crate::film::DEFAULT_WAVELENGTHS;
use crate::integrator::{pixels, Integrator, Passes, Work};
use crate::render::{seconds, Frame, Prepared, Report};
use crate::scene::{
    Cut, EnvironmentKind, IntegratorConfig, LightKind, Method, Scene, StoredConfig,
};

use super::{gather_view, store_light, StoredSetup, StoredStats};

/// Most grid points the stored method's light pass may store light at.
pub const MAX_STORED_CELLS: f64 = 16e6;

/// Per grid point of the stored light: its slot, the cell and its notches (measured 44 bytes
/// on the paper's stone, with room for deeper stones crossing more domains).
const STORED_POINT_BYTES: f64 = 100.0;

/// Processor seconds of the stored method's first camera ray of a pixel (the paper's stone
/// at 640 × 480, 3 µs) and of each further one (0.43 µs), 2026-12-06 (load about 10):
/// `BENCHMARKS.md`, "The work estimate's costs".
const STORED_PIXEL_CPU_S: f64 = 4e-6;
const STORED_RAY_CPU_S: f64 = 0.5e-6;

/// The paper's two passes on the stone model.
pub struct StoredMethod;

/// The stored method's settings of `scene` (its defaults under another method).
fn config(scene: &Scene) -> StoredConfig {
    match &scene.integrator {
        IntegratorConfig::Stored(c) => c.clone(),
        _ => StoredConfig::default(),
    }
}

/// Grid points of the light grid of `scene`'s stone at cells of `cell_mm`.
fn grid_points(scene: &Scene, cell_mm: f64) -> f64 {
    let axes = scene.body.box_semi_axes(scene.structure.semi_axes_mm);
    axes.iter()
        .map(|a| (2.0 * a / cell_mm).ceil() + 1.0)
        .product()
}

impl Integrator for StoredMethod {
    fn method(&self) -> Method {
        Method::Stored
    }

    /// The scene's directional or point light, no environment, no triplet's cap, and a
    /// light grid that fits.
    fn check(&self, scene: &Scene) -> Result<()> {
        let kind = scene.light.kind;
        if !matches!(kind, LightKind::Directional | LightKind::Point) {
            let name = match kind {
                LightKind::Sphere => "sphere",
                LightKind::Rect => "rect",
                _ => "none",
            };
            return Err(Error::field(
                "light.kind",
                format!(
                    "the stored method stores a directional or point light, not \"{name}\"; set \
                     light.kind = \"directional\" or \"point\", or integrator.method = \"path\""
                ),
            ));
        }
        if scene.environment.kind != EnvironmentKind::None {
            return Err(Error::field(
                "environment.kind",
                "the stored method has no environment light; set integrator.method = \"path\" \
                 or environment.kind = \"none\"",
            ));
        }
        if scene.body.cut == Cut::Triplet {
            return Err(Error::field(
                "body.cut",
                "the stored method has no light under a triplet's cap; set integrator.method = \
                 \"path\" or another body.cut",
            ));
        }
        let h = config(scene).cell_mm;
        let cells = grid_points(scene, h);
        if cells > MAX_STORED_CELLS {
            let axes = scene.body.box_semi_axes(scene.structure.semi_axes_mm);
            let volume: f64 = axes.iter().map(|a| 2.0 * a).product();
            let smallest = (volume / MAX_STORED_CELLS).cbrt() * 1.05;
            return Err(Error::field(
                "integrator.cell_mm",
                format!(
                    "{h} mm cells would make about {cells:.0} cells in this stone, more than the \
                     limit of {MAX_STORED_CELLS:.0}; use at least {:.3} mm",
                    (smallest * 1000.0).ceil() / 1000.0
                ),
            ));
        }
        Ok(())
    }

    /// The stored light's grid.
    fn memory_bytes(&self, scene: &Scene) -> f64 {
        grid_points(scene, config(scene).cell_mm) * STORED_POINT_BYTES
    }

    fn sees_environment(&self) -> bool {
        false
    }

    /// `"stored"`: its rays and its stored light ([`StoredStats`]).
    fn stats_key(&self) -> Option<&'static str> {
        Some("stored")
    }

    /// One camera ray through every pixel, `spp − 1` more.
    fn work(&self, scene: &Scene, frames: f64) -> Work {
        let spp = f64::from(scene.integrator.spp().unwrap_or(1));
        let pixels = pixels(scene, frames);
        Work {
            rays: pixels * spp,
            cpu_s: pixels * (STORED_PIXEL_CPU_S + (spp - 1.0) * STORED_RAY_CPU_S),
            ..Work::default()
        }
    }

    fn prepare(&self, prepared: &mut Prepared) -> Result<()> {
        prepared.build_stone()
    }

    /// The light pass timed as such, the view pass as such.
    fn render(&self, prepared: &Prepared, light_angle_deg: f64, _passes: &Passes) -> Frame {
        let s = &prepared.scene;
        let c = config(s);
        let mut times = prepared.times;
        let f = prepared.frame_setup(light_angle_deg, DEFAULT_WAVELENGTHS, c.seed);
        let setup = StoredSetup {
            camera: f.camera,
            width: f.width,
            height: f.height,
            spp: c.spp,
            light: f
                .light
                .expect("the stored method's check admits only a directional or point light"),
            environment: f.environment,
            gloss: f.gloss,
            seed: f.seed,
            cell_mm: c.cell_mm,
            spectral: &f.sampler,
        };
        let start = Instant::now();
        let light = store_light(f.stone, &setup);
        times.light_pass += seconds(start);
        let start = Instant::now();
        let image = gather_view(f.stone, &light, &setup);
        times.view_pass = seconds(start);
        let stats = StoredStats {
            spp: setup.spp,
            light: light.stats(),
        };
        prepared.deterministic_frame(
            times,
            image.spectral,
            &image.xyz,
            &f.sampler,
            Some(Box::new(stats)),
        )
    }
}

impl Report for StoredStats {
    fn to_json(&self) -> serde_json::Value {
        serde_json::to_value(self).expect("the stored method's statistics are JSON")
    }

    fn spp(&self) -> Option<u32> {
        Some(self.spp)
    }

    /// Its rays and its stored light's grid.
    fn notes(&self, _scene: &Scene) -> Vec<String> {
        let l = self.light;
        vec![format!(
            "{} rays per pixel | light stored in {} cells of {} mm ({} lit, {} lines, {:.1} MB)",
            self.spp,
            l.cells,
            l.cell_mm,
            l.lit_cells,
            l.notches,
            l.bytes as f64 / 1e6
        )]
    }

    fn clone_box(&self) -> Box<dyn Report> {
        Box::new(*self)
    }
}

impl Frame {
    /// The stored method's rays and stored light (`None` for a frame of another method).
    pub fn stored(&self) -> Option<&StoredStats> {
        self.report_as()
    }
}

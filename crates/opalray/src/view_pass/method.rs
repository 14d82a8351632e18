//! The paper's two passes as an integrator (`integrator.method = "two-pass"`): what they
//! refuse, and their frame — the light pass (`light_pass`), the view pass, colour — on the
//! structure's cell grid, laid out once per prepared scene.

use std::time::Instant;

use crate::color::to_rgb;
use crate::error::{Error, Result};
use crate::integrator::{pixels, Integrator, Passes, Work};
use crate::light_pass::{
    trace_light, ClusterOptics, LightField, LightSetup, LightSource, Termination, VoxelLayout,
};
use crate::render::{seconds, Frame, Prepared};
use crate::scene::{EnvironmentKind, LightKind, Method, Scene, BODY_EXTINCTION_PER_MM};

use super::{trace_view, Shading, TwoPassStats, ViewSetup};

/// Processor seconds of a pixel of the paper's two passes (0.36 µs) and of one of their light
/// rays (`light.rays`, 1.4 µs), the paper's scene, 2026-12-06 (load about 10):
/// `BENCHMARKS.md`, "The work estimate's costs".
const TWO_PASS_PIXEL_CPU_S: f64 = 0.5e-6;
const LIGHT_RAY_CPU_S: f64 = 2e-6;

/// The paper's two passes on the cell grid (paper §3.2–3.3).
pub struct TwoPass;

impl Integrator for TwoPass {
    fn method(&self) -> Method {
        Method::TwoPass
    }

    /// A directional or point light, no environment.
    fn check(&self, scene: &Scene) -> Result<()> {
        match scene.light.kind {
            LightKind::None => {
                return Err(Error::field(
                    "light.kind",
                    "the two-pass integrator needs a light; set light.kind = \"directional\" \
                     or \"point\", or integrator.method = \"path\"",
                ))
            }
            LightKind::Sphere | LightKind::Rect => {
                let name = if scene.light.kind == LightKind::Sphere {
                    "sphere"
                } else {
                    "rect"
                };
                return Err(Error::field(
                    "light.kind",
                    format!(
                        "a {name} light needs the path integrator; set integrator.method = \
                         \"path\" or light.kind = \"point\""
                    ),
                ));
            }
            LightKind::Directional | LightKind::Point => {}
        }
        if scene.environment.kind != EnvironmentKind::None {
            return Err(Error::field(
                "environment.kind",
                "an environment light needs the path integrator; set integrator.method = \"path\" \
                 or environment.kind = \"none\"",
            ));
        }
        Ok(())
    }

    fn sees_environment(&self) -> bool {
        false
    }

    /// The paper's cell grid, not the stone model.
    fn renders_stone(&self) -> bool {
        false
    }

    /// A view ray through every pixel and `light.rays` light rays a frame.
    fn work(&self, scene: &Scene, frames: f64) -> Work {
        let pixels = pixels(scene, frames);
        let light_rays = scene.light.rays as f64 * frames;
        Work {
            rays: pixels,
            light_rays,
            cpu_s: pixels * TWO_PASS_PIXEL_CPU_S + light_rays * LIGHT_RAY_CPU_S,
            ..Work::default()
        }
    }

    /// The structure grown, the optics built and the stone's cells laid out once for every
    /// frame (timed as the light pass): all the passes read.
    fn prepare(&self, prepared: &mut Prepared) -> Result<()> {
        prepared.grow()?;
        let start = Instant::now();
        let cells = VoxelLayout::new(prepared.structure()?);
        prepared.times.light_pass = seconds(start);
        prepared.cells = std::sync::OnceLock::from(cells);
        Ok(())
    }

    /// Light pass, view pass and colour.
    fn render(&self, prepared: &Prepared, light_angle_deg: f64, _passes: &Passes) -> Frame {
        let cells = prepared
            .cells
            .get_or_init(|| VoxelLayout::new(prepared.grown().0));
        prepared.render_in(cells, light_angle_deg)
    }
}

impl Prepared {
    /// The structure and optics, grown in `prepare` for the two passes (for another method,
    /// now). Panics only if `self.scene` was made invalid after `prepare` checked it.
    fn grown(&self) -> (&crate::structure::Structure, &crate::optics::OpticsTables) {
        let checked = "prepare checked the scene: its structure grows and its optics build";
        (
            self.structure().expect(checked),
            self.optics().expect(checked),
        )
    }

    /// The two passes' frame with the stone's cells laid out by the caller: `cells` must be
    /// [`VoxelLayout::new`] of this structure.
    pub fn render_in(&self, cells: &VoxelLayout, light_angle_deg: f64) -> Frame {
        let s = &self.scene;
        let (structure, optics) = self.grown();
        let mut times = self.times;
        let (camera, source) = self.placement(light_angle_deg);
        let spectrum = self.light_spectrum();
        let body_albedo = s.render.body_albedo();

        let start = Instant::now();
        let mut light = self.trace_light_in(cells, source, &spectrum);
        times.light_pass += seconds(start);

        let start = Instant::now();
        let phong_exponent = s.render.phong_exponent as f32;
        let shading = Shading::new(
            structure,
            cells,
            &ClusterOptics::new(optics),
            &light,
            phong_exponent,
            body_albedo,
        );
        // The shading holds what the view pass needs of the stored spectra; freeing them
        // before the image is allocated keeps the peak memory down.
        light.fluence = Vec::new();
        let spectral = trace_view(
            structure,
            optics,
            &light,
            &shading,
            &ViewSetup {
                camera,
                width: s.render.width as usize,
                height: s.render.height as usize,
                source,
                light_spectrum: &spectrum,
                phong_exponent,
                gloss: s.render.gloss as f32,
                background: s.render.background as f32,
                body_extinction_per_mm: BODY_EXTINCTION_PER_MM,
                reflection_block: s.render.reflection_block as usize,
            },
        );
        times.view_pass = seconds(start);

        let start = Instant::now();
        let rgb = to_rgb(&spectral, &s.color, s.light.illuminant);
        times.color = seconds(start);
        Frame {
            spectral,
            rgb,
            times,
            report: Some(Box::new(TwoPassStats {
                ledger: light.ledger,
                void_ratio: structure.stats.void_ratio,
            })),
        }
    }

    /// The light pass alone (paper §3.2) for light angle `light_angle_deg`: the light stored
    /// in every inside cell, as the view pass of [`Prepared::render_in`] would receive it.
    /// `cells` must be [`VoxelLayout::new`] of this structure. Defined for the two passes
    /// only: with another method there is no stored light, and the result is that of the
    /// same scene's two passes.
    pub fn light_pass_in(&self, cells: &VoxelLayout, light_angle_deg: f64) -> LightField {
        let (_, source) = self.placement(light_angle_deg);
        self.trace_light_in(cells, source, &self.light_spectrum())
    }

    /// [`trace_light`] with this scene's light settings, from `source` with `spectrum`.
    fn trace_light_in(
        &self,
        cells: &VoxelLayout,
        source: LightSource,
        spectrum: &[f32],
    ) -> LightField {
        let s = &self.scene;
        let (structure, optics) = self.grown();
        trace_light(
            structure,
            cells,
            optics,
            &LightSetup {
                source,
                spectrum,
                rays: s.light.rays,
                seed: s.structure.seed,
                body_albedo: s.render.body_albedo(),
                body_extinction_per_mm: BODY_EXTINCTION_PER_MM,
                termination: Termination::of(s.light.cutoff, s.light.roulette),
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn light_pass_in_is_the_light_the_render_stores() {
        let (prepared, cells) = VoxelLayout::of_default_scene([24, 18, 6]);
        let light = prepared.light_pass_in(&cells, -20.0);
        let frame = prepared.render_in(&cells, -20.0);
        assert_eq!(light.ledger, frame.ledger());
        assert_eq!(light.slot_of_cell, cells.slot_of_cell);
        let bins = prepared.optics().unwrap().grid.bins;
        assert_eq!(
            light.fluence.len(),
            cells.slots() * crate::light_pass::LOBES * (bins + 4)
        );
    }

    #[test]
    fn a_frame_through_the_seam_is_the_frame_of_the_laid_out_cells() {
        let (prepared, cells) = VoxelLayout::of_default_scene([24, 18, 6]);
        let seam = prepared.render(-20.0);
        let direct = prepared.render_in(&cells, -20.0);
        assert_eq!(seam.spectral.data, direct.spectral.data);
    }
}

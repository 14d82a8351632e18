//! opalray: a spectral renderer for structural colour, starting with the play of colour of
//! precious opal (Imura et al., "Rendering of 'Play of Color' using Stratified Model based on
//! Amorphous Structure of Opal"). Layers, each importing only from those above it
//! (`docs/architecture.md`; the physics as built: `docs/model.md`):
//!
//! ```text
//! error spectrum geometry sampling simd cancel   foundations: know no scene
//! scatter      what happens at a point: phase, mosaic lobe, backing (sample, density, eval)
//! scene        TOML | preset = scenes/*.toml; parse, validate; [integrator] read for any method
//! color optics structure     CIE and colour spaces; R, T, Bragg lines; the paper's growth
//! stone        the one stone model: layout, crystal, lobe widths, cut, potch; the walk along a
//!              ray; the path to a light; its voxel view (Stone::voxels) for the paper's passes
//! lights       environment (built-in kinds, .hdr / .exr readers), area lights, the point or
//!              directional lamp
//! film         sensor table, even/odd sums, noise, denoiser
//! integrators  light_pass + view_pass (the paper's, on the voxels) | path | stored | lobe,
//!              each with a method.rs (integrator::Integrator) and a config.rs (Settings)
//!              (the two passes' in view_pass/); a frame's own figures in its method's Report
//!              (Frame::path, Frame::stored, Frame::two_pass)
//! integrator   the seam: traits Integrator, Settings; one list line a method makes Method,
//!              IntegratorConfig, INTEGRATORS; check(scene); Passes (a render's time limit
//!              and its reports after each pass or row)
//! render       prepare(scene) -> Prepared (the method's prepare) -> render(angle) -> Frame
//! output       PNG | EXR | spectral EXR | sheets of color::to_rgb's image (CIE 1931 -> XYZ
//!              -> RGB, gamut-mapped), with the scene they record
//! ```
#![warn(missing_docs)]

pub mod cancel;
pub mod color;
pub mod error;
pub mod film;
pub mod geometry;
pub mod integrator;
pub mod light_pass;
pub mod lights;
pub mod lobe;
pub mod optics;
pub mod output;
pub mod path;
pub mod render;
pub mod sampling;
pub mod scatter;
pub mod scene;
pub mod simd;
pub mod spectrum;
pub mod stone;
pub mod stored;
pub mod structure;
pub mod view_pass;

/// The denoiser, in the film's room ([`film::denoise`]).
pub use film::denoise;

pub use color::{
    illuminant_spectrum, to_display_rgb8, to_rgb, wavelength_srgb, white_point_xyz, ColorMatcher,
    RgbImage,
};
pub use error::{Error, Result};
pub use optics::{build_optics, OpticsTables};
pub use render::{prepare, render, Frame, Prepared, StageTimes};
pub use scene::Scene;
pub use spectrum::{SpectralImage, WavelengthGrid};
pub use structure::{grow_structure, Cell, Structure};

//! opalray: a spectral renderer for structural colour, starting with the play of colour of
//! precious opal (Imura et al., "Rendering of 'Play of Color' using Stratified Model based on
//! Amorphous Structure of Opal"). Layers, each importing only from those above it
//! (`docs/architecture.md`; the physics as built: `docs/model.md`):
//!
//! ```text
//! spectrum geometry sampling scatter error   foundations, no scene
//! scene (TOML | preset = scenes/*.toml; parse, validate)  ->  color, optics (R, T, Bragg lines),
//!   structure (growth)
//!   -> stone (the stone model: layout, crystal, lobe widths, cut, potch; the walk along a
//!      ray; the path to a light)  +  lights (environment and its built-in kinds, the .hdr /
//!      .exr readers, area lights)
//!   -> film (the sensor table, the even/odd accumulation, the noise, the denoiser)
//!   -> an integrator: light_pass + view_pass (paper, on the stone's voxels; the light's
//!      walk in named steps, its energy booked in one place) | path (on the film) | stored
//!      | lobe, each with a method.rs implementing integrator::Integrator (one table)
//!   -> render.rs: prepare(scene) (integrator::check, then its prepare), render -> Frame
//!      (render/frame.rs; the light and camera placed: render/placement.rs)
//!   -> to_rgb (CIE 1931 -> XYZ -> RGB, gamut-mapped) -> output (PNG | EXR | spectral EXR)
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

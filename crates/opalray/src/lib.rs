//! opalray: a spectral renderer for structural colour, starting with the play of colour of
//! precious opal (Imura et al., "Rendering of 'Play of Color' using Stratified Model based on
//! Amorphous Structure of Opal").
//!
//! The pipeline, one module per stage, each a function of its inputs and the seed:
//!
//! ```text
//! Scene (TOML | preset)                      scene::Scene
//!   -> grow_structure   cells: outside | void | cluster(orientation)     structure
//!   -> build_optics     R, T, D tables over wavelength × angle           optics
//!   -> trace_light      light stored per cluster                          light_pass
//!   -> trace_view       spectral image H × W × bins                       view_pass
//!      (or the path tracer on the stone model, path, then denoise; or the two passes on
//!      it, stored)
//!   -> to_rgb           CIE 1931 → XYZ → RGB, gamut-mapped               color
//!   -> write_*          PNG | EXR | spectral EXR                          output
//! ```
#![warn(missing_docs)]

pub mod color;
pub mod denoise;
pub mod error;
pub mod geometry;
pub mod light_pass;
pub mod lights;
pub mod optics;
pub mod output;
pub mod path;
pub mod render;
pub mod sampling;
pub mod scene;
pub mod simd;
pub mod spectrum;
pub mod stone;
pub mod stored;
pub mod structure;
pub mod view_pass;

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

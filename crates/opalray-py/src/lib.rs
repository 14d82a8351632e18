//! Python bindings of opalray: the `opalray._opalray` extension module under the `opalray`
//! package (`python/opalray`). Thin: scene dicts go through the core's serde structs and
//! validation, renders run in the core with the GIL released, and results come back as numpy
//! arrays or as files written by the core's own writers. The Python API is in
//! `docs/python.md`.
//!
//! - [`scene`]: dict ↔ `Scene`, errors as `ValueError`.
//! - [`stages`]: `prepare`, renders of the prepared scene, the structure and optics as arrays.
//! - [`render`]: `render`, the whole chain in one call with progress callbacks.
//! - [`deadline`]: waiting for the core without the GIL, within `time_limit`.
//! - [`frame`]: a rendered frame's arrays and files.
//! - [`light`]: the light pass's stored light as arrays.
//! - [`stone`]: the stone model's domains as arrays.
//! - [`sweep`]: a sweep's frames, contact sheet and animation.
// PyO3's macros expand to `unsafe` calls into the CPython C API (module and class
// registration, argument extraction); this crate itself writes no `unsafe` block.
#![allow(unsafe_code)]

pub mod deadline;
pub mod frame;
pub mod light;
pub mod render;
pub mod scene;
pub mod stages;
pub mod stone;
pub mod sweep;

use pyo3::prelude::*;

/// The extension module `opalray._opalray`.
#[pymodule]
fn _opalray(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add("DEFAULT_PRESET", opalray::scene::DEFAULT_RENDER_PRESET)?;
    m.add("PRESETS", opalray::scene::PRESET_NAMES.to_vec())?;
    m.add("MAX_SPP", opalray::scene::MAX_SPP)?;
    m.add_class::<frame::Frame>()?;
    m.add_class::<stages::Stages>()?;
    m.add_class::<light::StoredLight>()?;
    m.add_class::<stone::StoneModel>()?;
    m.add_function(wrap_pyfunction!(scene::normalize, m)?)?;
    m.add_function(wrap_pyfunction!(scene::preset, m)?)?;
    m.add_function(wrap_pyfunction!(scene::parse_toml, m)?)?;
    m.add_function(wrap_pyfunction!(scene::integrator_fields, m)?)?;
    m.add_function(wrap_pyfunction!(scene::integrator_reads, m)?)?;
    m.add_function(wrap_pyfunction!(scene::to_toml_text, m)?)?;
    m.add_function(wrap_pyfunction!(scene::read_scene, m)?)?;
    m.add_function(wrap_pyfunction!(stages::prepare, m)?)?;
    m.add_function(wrap_pyfunction!(render::render, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::write_sheet, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::write_animation, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::write_png_rgb8, m)?)?;
    m.add_function(wrap_pyfunction!(sweep::read_png_rgb8, m)?)?;
    Ok(())
}

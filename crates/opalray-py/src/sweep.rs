//! The files of a sweep: frames as 8-bit PNG, the contact sheet and the animation, written by
//! the core's writers exactly as `opalray sweep` writes them.

use std::path::PathBuf;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::scene::to_py_err;

/// The frames' bytes, copied out of their Python objects (to be used without the GIL).
fn owned(frames: &[Bound<'_, PyBytes>]) -> Vec<Vec<u8>> {
    frames.iter().map(|f| f.as_bytes().to_vec()).collect()
}

/// Check that every frame holds `width × height × 3` bytes.
fn check_frames(frames: &[Vec<u8>], width: usize, height: usize) -> PyResult<()> {
    match frames.iter().position(|f| f.len() != width * height * 3) {
        Some(k) => Err(PyValueError::new_err(format!(
            "frame {k}: {} bytes, expected {width} × {height} × 3",
            frames[k].len()
        ))),
        None => Ok(()),
    }
}

/// `write_sheet(path, frames, angles_deg, width, height, columns)`: the contact sheet of
/// `frames` (display codes) with each angle under its frame, as `opalray sweep --sheet`.
#[pyfunction]
pub fn write_sheet(
    py: Python<'_>,
    path: PathBuf,
    frames: Vec<Bound<'_, PyBytes>>,
    angles_deg: Vec<f64>,
    width: usize,
    height: usize,
    columns: usize,
) -> PyResult<()> {
    let frames = owned(&frames);
    check_frames(&frames, width, height)?;
    if frames.len() != angles_deg.len() || frames.is_empty() || columns == 0 {
        return Err(PyValueError::new_err(
            "one angle per frame, at least one frame and one column",
        ));
    }
    py.detach(|| {
        let labelled: Vec<(Vec<u8>, String)> = frames
            .into_iter()
            .zip(&angles_deg)
            .map(|(f, a)| (f, opalray::output::sheet_label(*a)))
            .collect();
        let sheet = opalray::output::contact_sheet(&labelled, width, height, columns);
        opalray::output::write_png_rgb8(&path, sheet.width as u32, sheet.height as u32, &sheet.rgb)
    })
    .map_err(to_py_err)
}

/// `write_animation(path, frames, width, height, delay_ms)`: a GIF, or an APNG for `.png`,
/// as `opalray sweep --animation`.
#[pyfunction]
pub fn write_animation(
    py: Python<'_>,
    path: PathBuf,
    frames: Vec<Bound<'_, PyBytes>>,
    width: u32,
    height: u32,
    delay_ms: u32,
) -> PyResult<()> {
    let frames = owned(&frames);
    check_frames(&frames, width as usize, height as usize)?;
    let is_png = path
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("png"));
    py.detach(|| {
        if is_png {
            opalray::output::write_apng(&path, &frames, width, height, delay_ms)
        } else {
            opalray::output::write_gif(&path, &frames, width, height, delay_ms)
        }
    })
    .map_err(to_py_err)
}

/// `write_png_rgb8(path, width, height, codes)`: one 8-bit frame, written atomically.
#[pyfunction]
pub fn write_png_rgb8(
    py: Python<'_>,
    path: PathBuf,
    width: u32,
    height: u32,
    codes: &[u8],
) -> PyResult<()> {
    if codes.len() != width as usize * height as usize * 3 {
        return Err(PyValueError::new_err(format!(
            "{} bytes, expected {width} × {height} × 3",
            codes.len()
        )));
    }
    py.detach(|| opalray::output::write_png_rgb8(&path, width, height, codes))
        .map_err(to_py_err)
}

/// `read_png_rgb8(path) -> (width, height, codes)`: an 8-bit RGB PNG (a sweep's frame).
#[pyfunction]
pub fn read_png_rgb8(py: Python<'_>, path: PathBuf) -> PyResult<(u32, u32, Bound<'_, PyBytes>)> {
    let image = py
        .detach(|| image::open(&path))
        .map_err(|e| PyValueError::new_err(format!("{}: {e}", path.display())))?;
    let rgb = image.into_rgb8();
    Ok((rgb.width(), rgb.height(), PyBytes::new(py, rgb.as_raw())))
}

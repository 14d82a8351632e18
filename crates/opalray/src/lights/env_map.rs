//! Environment maps from files: Radiance `.hdr` (RGBE) and OpenEXR, read into a luminance
//! raster.
//!
//! Input: a file path → output: a [`LuminanceMap`], `width × height` values of CIE Y
//! (Rec. 709 / sRGB primaries: `Y = 0.2126 R + 0.7152 G + 0.0722 B`), row 0 the top of the
//! picture. Only the luminance is kept (4 bytes a pixel): the path tracer carries the light's
//! spectrum, and the map scales it.
//!
//! This file picks the reader by the extension and checks what every map must be (a regular
//! file, a size within the limits, some light); the readers are `env_map/hdr.rs` (Radiance's
//! RGBE, bounded throughout) and `env_map/openexr.rs` (the `exr` crate's, its size read from
//! the header first).

mod hdr;
mod openexr;

use std::io::BufReader;
use std::path::Path;

use crate::scene::{map_format, MapFormat};

use hdr::read_header;
pub use hdr::{read_hdr, rgbe_to_float};
use openexr::exr_size;
pub use openexr::read_exr;

/// Most pixels of an environment map (8192 × 4096; about 400 MB with its distribution).
pub const MAX_MAP_PIXELS: u64 = 8192 * 4096;

/// Rec. 709 / sRGB luminance weights of R, G, B (IEC 61966-2-1, the Y row of the RGB → XYZ
/// matrix).
pub const LUMINANCE_WEIGHTS: [f32; 3] = [0.2126, 0.7152, 0.0722];

/// A picture's luminance, row-major, row 0 at the top.
#[derive(Clone, Debug, PartialEq)]
pub struct LuminanceMap {
    /// Pixels per row.
    pub width: usize,
    /// Rows.
    pub height: usize,
    /// `width × height` values of Y, ≥ 0.
    pub luminance: Vec<f32>,
}

/// Luminance of linear Rec. 709 RGB; negative or non-finite results count as 0.
pub fn luminance(rgb: [f32; 3]) -> f32 {
    let y = LUMINANCE_WEIGHTS[0] * rgb[0]
        + LUMINANCE_WEIGHTS[1] * rgb[1]
        + LUMINANCE_WEIGHTS[2] * rgb[2];
    if y.is_finite() && y > 0.0 {
        y
    } else {
        0.0
    }
}

/// Most pixels along either side of an environment map.
pub const MAX_MAP_SIDE: usize = 8192;

/// Bytes a map's pixel holds while it is read and sampled: reading an OpenEXR map at the size
/// limit peaked at 782 MB, 23 bytes a pixel (a 457-byte file the `maps` fuzz target grew,
/// RELIABILITY.md); then the sampling weights and the distribution's function and cumulative
/// sums, 4 bytes each; rounded up.
pub const MAP_PIXEL_BYTES: u64 = 48;

/// Read `path` as `.hdr` / `.pic` (Radiance) or `.exr` (OpenEXR) by its extension. The error
/// is one line: what is wrong with the file and what to do.
pub fn read_map(path: &Path) -> Result<LuminanceMap, String> {
    check_regular_file(path)?;
    let map = match map_format(path) {
        Some(MapFormat::Radiance) => read_hdr(path),
        Some(MapFormat::OpenExr) => read_exr(path),
        None => Err("not a .hdr or .exr file; give a Radiance .hdr or an OpenEXR .exr map".into()),
    }?;
    if map.luminance.iter().all(|&y| y == 0.0) {
        return Err(
            "every pixel is black (or its EXPOSURE scales it to nothing); give a map with light"
                .into(),
        );
    }
    Ok(map)
}

/// The width and height of the map `path`, read from its header alone (nothing of the
/// picture is allocated): what the memory estimate counts before the map is read.
pub fn map_size(path: &Path) -> Result<(usize, usize), String> {
    check_regular_file(path)?;
    let (width, height) = match map_format(path) {
        Some(MapFormat::Radiance) => {
            let file = std::fs::File::open(path).map_err(|e| format!("cannot open: {e}"))?;
            let header = read_header(&mut BufReader::new(file))?;
            (header.width, header.height)
        }
        Some(MapFormat::OpenExr) => exr_size(path)?,
        None => {
            return Err(
                "not a .hdr or .exr file; give a Radiance .hdr or an OpenEXR .exr map".into(),
            )
        }
    };
    check_size(width, height)?;
    Ok((width, height))
}

/// Refuse what is not a regular file before opening it: a named pipe would block the open
/// for ever, a device or a folder has no picture.
fn check_regular_file(path: &Path) -> Result<(), String> {
    match std::fs::metadata(path) {
        Err(e) => Err(format!(
            "cannot open ({e}); give an existing map (a relative path is taken from the scene \
             file's folder)"
        )),
        Ok(meta) if meta.is_dir() => Err("is a folder; give a map file".into()),
        Ok(meta) if !meta.is_file() => {
            Err("is not a regular file (a pipe or a device); give a map file".into())
        }
        Ok(_) => Ok(()),
    }
}

/// Refuse an empty picture or one larger than [`MAX_MAP_SIDE`] on a side or
/// [`MAX_MAP_PIXELS`] in all, each side checked on its own before they are multiplied.
fn check_size(width: usize, height: usize) -> Result<(), String> {
    if width == 0 || height == 0 {
        return Err(format!("the picture is {width} × {height}: empty"));
    }
    let pixels = (width <= MAX_MAP_SIDE && height <= MAX_MAP_SIDE)
        .then(|| (width as u64).checked_mul(height as u64))
        .flatten();
    if !pixels.is_some_and(|p| p <= MAX_MAP_PIXELS) {
        return Err(format!(
            "{width} × {height} pixels, more than the limit of {MAX_MAP_SIDE} × \
             {}; give a smaller map",
            MAX_MAP_PIXELS / MAX_MAP_SIDE as u64
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pattern with runs (a constant band) and literals (a ramp), and a bright spot: the
    /// picture both readers' round trips write.
    pub(super) fn pattern(width: usize, height: usize) -> Vec<[f32; 3]> {
        (0..width * height)
            .map(|i| {
                let (x, y) = (i % width, i / width);
                if y == 1 {
                    [0.25, 0.5, 1.0]
                } else if (x, y) == (5, 3) {
                    [900.0, 300.0, 12.0]
                } else {
                    [x as f32 / width as f32, 0.01 * y as f32, 3.0]
                }
            })
            .collect()
    }

    #[test]
    fn a_named_pipe_is_refused_without_blocking() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("pipe.hdr");
        let made = std::process::Command::new("mkfifo").arg(&path).status();
        if !made.is_ok_and(|s| s.success()) {
            return; // No mkfifo here: nothing to test.
        }
        let (send, receive) = std::sync::mpsc::channel();
        let probe = path.clone();
        std::thread::spawn(move || {
            let _ = send.send((read_map(&probe), map_size(&probe)));
        });
        let (read, size) = receive
            .recv_timeout(std::time::Duration::from_secs(20))
            .expect("reading a named pipe blocked");
        assert!(read.unwrap_err().contains("not a regular file"));
        assert!(size.unwrap_err().contains("not a regular file"));
    }
}

//! Environment maps from files: Radiance `.hdr` (RGBE) and OpenEXR, read into a luminance
//! raster.
//!
//! Input: a file path → output: a [`LuminanceMap`], `width × height` values of CIE Y
//! (Rec. 709 / sRGB primaries: `Y = 0.2126 R + 0.7152 G + 0.0722 B`), row 0 the top of the
//! picture. Only the luminance is kept (4 bytes a pixel): the path tracer carries the light's
//! spectrum, and the map scales it.
//!
//! The `.hdr` reader follows Greg Ward's Radiance picture format (`#?RADIANCE` header,
//! `FORMAT=32-bit_rle_rgbe` or `_xyze`, cumulative `EXPOSURE=` divided out, the standard
//! `-Y H +X W` orientation): scanlines flat, in the old run-length form (`1 1 1 n` repeats the
//! last pixel) or the new one (`2 2 hi lo`, then each of the four components run-length coded
//! on its own). A component decodes as `(c + 0.5) · 2^(e − 136)`, Radiance's `colr_color`.
//!
//! Why not the `image` crate's `hdr` decoder (0.25.10): it multiplies the run length of
//! consecutive old-style repeats without a bound, so eight `1 1 1 0` pixels in a row (a
//! 76-byte file) overflow, a panic wherever overflow is checked (the tests and the fuzz
//! targets); it reads header lines of any length, refuses `_xyze`, parses the sizes as 32
//! bits (a larger one reads as "unparsable", not as "more than the limit") and decodes
//! `c · 2^(e − 136)`, without Radiance's half step. The reader below is bounded throughout
//! (`tests::many_zero_repeats_are_an_error_not_a_panic`).

use std::io::{BufRead, BufReader, Read};
use std::path::Path;

use crate::scene::{map_format, MapFormat};

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

/// Read a Radiance RGBE picture.
pub fn read_hdr(path: &Path) -> Result<LuminanceMap, String> {
    let file = std::fs::File::open(path).map_err(|e| format!("cannot open: {e}"))?;
    let mut r = BufReader::new(file);
    let header = read_header(&mut r)?;
    check_size(header.width, header.height)?;
    let mut values = Vec::with_capacity(header.width * header.height);
    let mut line = vec![[0u8; 4]; header.width];
    let scale = 1.0 / header.exposure;
    for row in 0..header.height {
        read_scanline(&mut r, &mut line).map_err(|e| format!("scanline {row}: {e}"))?;
        values.extend(line.iter().map(|&p| {
            let c = rgbe_to_float(p);
            let y = if header.xyz { c[1] } else { luminance(c) };
            y * scale
        }));
    }
    if values.iter().any(|v| !v.is_finite()) {
        return Err(format!(
            "pixels overflow once EXPOSURE={} is divided out; give a smaller EXPOSURE product",
            header.exposure
        ));
    }
    Ok(LuminanceMap {
        width: header.width,
        height: header.height,
        luminance: values,
    })
}

struct Header {
    width: usize,
    height: usize,
    xyz: bool,
    exposure: f32,
}

/// A header line of at most this many bytes (Radiance's own limit is 8 kB for the whole
/// header's lines).
const MAX_HEADER_LINE: usize = 4096;
/// Header lines at most.
const MAX_HEADER_LINES: usize = 1024;

fn read_line(r: &mut impl BufRead) -> Result<String, String> {
    let mut bytes = Vec::new();
    r.by_ref()
        .take(MAX_HEADER_LINE as u64)
        .read_until(b'\n', &mut bytes)
        .map_err(|e| format!("cannot read: {e}"))?;
    if bytes.last() != Some(&b'\n') {
        return Err(
            "the header ends early or has an over-long line; not a Radiance picture".into(),
        );
    }
    bytes.pop();
    Ok(String::from_utf8_lossy(&bytes)
        .trim_end_matches('\r')
        .to_string())
}

fn read_header(r: &mut impl BufRead) -> Result<Header, String> {
    let first = read_line(r)?;
    if !first.starts_with("#?") {
        return Err("no `#?RADIANCE` signature; not a Radiance .hdr picture".into());
    }
    let mut xyz = false;
    let mut exposure = 1.0f32;
    let mut lines = 0;
    loop {
        let line = read_line(r)?;
        lines += 1;
        if line.is_empty() {
            break;
        }
        if lines > MAX_HEADER_LINES {
            return Err("the header has no end; not a Radiance picture".into());
        }
        if let Some(format) = line.strip_prefix("FORMAT=") {
            match format.trim() {
                "32-bit_rle_rgbe" => xyz = false,
                "32-bit_rle_xyze" => xyz = true,
                other => return Err(format!("unknown FORMAT={other}; expected 32-bit_rle_rgbe")),
            }
        } else if let Some(value) = line.strip_prefix("EXPOSURE=") {
            let e: f32 = value
                .trim()
                .parse()
                .map_err(|_| format!("unreadable EXPOSURE={}", value.trim()))?;
            if !(e.is_finite() && e > 0.0) {
                return Err(format!("EXPOSURE={e} must be a positive number"));
            }
            exposure *= e;
            // The product is divided out: it and its inverse must stay ordinary numbers.
            if !(1e-30..=1e30).contains(&exposure) {
                return Err(format!(
                    "the EXPOSURE= lines multiply to {exposure:e}, beyond what a picture can \
                     be scaled by; give factors whose product is between 1e-30 and 1e30"
                ));
            }
        }
    }
    let resolution = read_line(r)?;
    let words: Vec<&str> = resolution.split_whitespace().collect();
    let (height, width) = match words.as_slice() {
        ["-Y", h, "+X", w] => (h.parse::<usize>(), w.parse::<usize>()),
        _ => {
            return Err(format!(
                "resolution line `{resolution}`: only the standard `-Y height +X width` \
                 orientation is read; save the map top-down, left to right"
            ))
        }
    };
    match (height, width) {
        (Ok(height), Ok(width)) => Ok(Header {
            width,
            height,
            xyz,
            exposure,
        }),
        _ => Err(format!("unreadable resolution line `{resolution}`")),
    }
}

fn read_byte(r: &mut impl Read) -> Result<u8, String> {
    let mut b = [0u8; 1];
    r.read_exact(&mut b)
        .map_err(|_| "the file ends early (truncated?)".to_string())?;
    Ok(b[0])
}

/// One scanline into `line` (flat, old or new run-length encoding).
fn read_scanline(r: &mut impl Read, line: &mut [[u8; 4]]) -> Result<(), String> {
    let width = line.len();
    let mut first = [0u8; 4];
    r.read_exact(&mut first)
        .map_err(|_| "the file ends early (truncated?)".to_string())?;
    let new_rle = (8..=0x7fff).contains(&width)
        && first[0] == 2
        && first[1] == 2
        && first[2] & 0x80 == 0
        && ((first[2] as usize) << 8 | first[3] as usize) == width;
    if new_rle {
        return read_new_rle(r, line);
    }
    if first[0] == 2 && first[1] == 2 && first[2] & 0x80 == 0 && (8..=0x7fff).contains(&width) {
        return Err(format!(
            "run-length scanline of width {} in a picture {width} wide; the file is damaged",
            (first[2] as usize) << 8 | first[3] as usize
        ));
    }
    read_flat(r, line, first)
}

/// Flat pixels, where `1 1 1 n` repeats the previous pixel `n << shift` times.
fn read_flat(r: &mut impl Read, line: &mut [[u8; 4]], first: [u8; 4]) -> Result<(), String> {
    let mut x = 0;
    let mut shift = 0u32;
    let mut pixel = first;
    loop {
        if pixel[0] == 1 && pixel[1] == 1 && pixel[2] == 1 {
            if x == 0 {
                return Err("a repeat before the first pixel of a scanline".into());
            }
            let count = (pixel[3] as usize) << shift;
            if x + count > line.len() {
                return Err("a repeat runs past the end of the scanline".into());
            }
            let last = line[x - 1];
            line[x..x + count].fill(last);
            x += count;
            shift += 8;
        } else {
            line[x] = pixel;
            x += 1;
            shift = 0;
        }
        if x == line.len() {
            return Ok(());
        }
        if shift > 24 {
            return Err("a repeat count too large".into());
        }
        r.read_exact(&mut pixel)
            .map_err(|_| "the file ends early (truncated?)".to_string())?;
    }
}

/// The new run-length form: each component of the scanline as runs (`n > 128`: one byte
/// repeated `n − 128` times) and literals (`n` bytes).
fn read_new_rle(r: &mut impl Read, line: &mut [[u8; 4]]) -> Result<(), String> {
    let width = line.len();
    for c in 0..4 {
        let mut x = 0;
        while x < width {
            let n = read_byte(r)? as usize;
            if n > 128 {
                let count = n - 128;
                if x + count > width {
                    return Err("a run runs past the end of the scanline".into());
                }
                let v = read_byte(r)?;
                for p in &mut line[x..x + count] {
                    p[c] = v;
                }
                x += count;
            } else {
                if n == 0 || x + n > width {
                    return Err("a literal runs past the end of the scanline".into());
                }
                for p in &mut line[x..x + n] {
                    p[c] = read_byte(r)?;
                }
                x += n;
            }
        }
    }
    Ok(())
}

/// An RGBE pixel as floats (Radiance's `colr_color`).
pub fn rgbe_to_float(p: [u8; 4]) -> [f32; 3] {
    if p[3] == 0 {
        return [0.0; 3];
    }
    let f = 2f32.powi(i32::from(p[3]) - 136);
    [
        (f32::from(p[0]) + 0.5) * f,
        (f32::from(p[1]) + 0.5) * f,
        (f32::from(p[2]) + 0.5) * f,
    ]
}

/// Read the R, G, B channels (half or float; alpha and other channels ignored) of an
/// OpenEXR file's first layer.
pub fn read_exr(path: &Path) -> Result<LuminanceMap, String> {
    use exr::prelude::{read, ReadChannels, ReadLayers};
    // The header first: the size is checked before the pixels are allocated.
    let (width, height) = exr_size(path)?;
    check_size(width, height)?;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |size, _| LuminanceMap {
                width: size.width(),
                height: size.height(),
                luminance: vec![0.0; size.width() * size.height()],
            },
            |map: &mut LuminanceMap, pos, (r, g, b): (f32, f32, f32)| {
                map.luminance[pos.y() * map.width + pos.x()] = luminance([r, g, b]);
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| {
            format!(
                "cannot read its R, G, B channels: {}; give an RGB or RGBA OpenEXR map",
                one_line(&e.to_string())
            )
        })?;
    Ok(image.layer_data.channel_data.pixels)
}

/// The size of a single-part OpenEXR file's layer, from its header. A multi-part file is
/// refused: its parts may differ in size, and the one read must be the one checked.
fn exr_size(path: &Path) -> Result<(usize, usize), String> {
    let meta = exr::meta::MetaData::read_from_file(path, false)
        .map_err(|e| format!("not a readable OpenEXR file: {}", one_line(&e.to_string())))?;
    match meta.headers.as_slice() {
        [] => Err("an OpenEXR file without a layer".into()),
        [header] if header.deep => {
            Err("a deep OpenEXR file; give a flat RGB or RGBA OpenEXR map".into())
        }
        [header] => Ok((header.layer_size.width(), header.layer_size.height())),
        parts => Err(format!(
            "a multi-part OpenEXR file ({} parts); save the map as a single-part RGB file",
            parts.len()
        )),
    }
}

fn one_line(message: &str) -> String {
    message.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An RGBE pixel of `rgb` (Ward's `setcolr`: the largest component's exponent, the
    /// mantissas truncated to 8 bits).
    fn float_to_rgbe(rgb: [f32; 3]) -> [u8; 4] {
        let v = rgb[0].max(rgb[1]).max(rgb[2]);
        if v < 1e-32 {
            return [0; 4];
        }
        let e = v.log2().floor() as i32 + 1;
        let m = 256.0 / 2f32.powi(e);
        [
            (rgb[0] * m) as u8,
            (rgb[1] * m) as u8,
            (rgb[2] * m) as u8,
            (e + 128) as u8,
        ]
    }

    /// Runs and literals of one component, as Radiance's `fwritecolrs` writes them (runs of
    /// at least 4).
    fn encode_component(values: &[u8], out: &mut Vec<u8>) {
        let mut x = 0;
        while x < values.len() {
            let mut run = 1;
            while x + run < values.len() && values[x + run] == values[x] && run < 127 {
                run += 1;
            }
            if run >= 4 {
                out.push(128 + run as u8);
                out.push(values[x]);
                x += run;
            } else {
                let start = x;
                let mut n = 0;
                while x < values.len() && n < 128 {
                    let mut ahead = 1;
                    while x + ahead < values.len() && values[x + ahead] == values[x] && ahead < 4 {
                        ahead += 1;
                    }
                    if ahead >= 4 {
                        break;
                    }
                    x += 1;
                    n += 1;
                }
                out.push(n as u8);
                out.extend_from_slice(&values[start..start + n]);
            }
        }
    }

    fn write_hdr(path: &Path, width: usize, height: usize, rgb: &[[f32; 3]], rle: bool) {
        let mut out = b"#?RADIANCE\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=2.0\n\n".to_vec();
        out.extend_from_slice(format!("-Y {height} +X {width}\n").as_bytes());
        for row in rgb.chunks(width) {
            let pixels: Vec<[u8; 4]> = row.iter().map(|&c| float_to_rgbe(c)).collect();
            if rle {
                out.extend_from_slice(&[2, 2, (width >> 8) as u8, (width & 0xff) as u8]);
                for c in 0..4 {
                    let comp: Vec<u8> = pixels.iter().map(|p| p[c]).collect();
                    encode_component(&comp, &mut out);
                }
            } else {
                for p in pixels {
                    out.extend_from_slice(&p);
                }
            }
        }
        std::fs::write(path, out).unwrap();
    }

    /// A pattern with runs (a constant band) and literals (a ramp), and a bright spot.
    fn pattern(width: usize, height: usize) -> Vec<[f32; 3]> {
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

    fn check_round_trip(rle: bool) {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("map.hdr");
        let (w, h) = (40, 20);
        let rgb = pattern(w, h);
        write_hdr(&path, w, h, &rgb, rle);
        let map = read_hdr(&path).unwrap();
        assert_eq!((map.width, map.height), (w, h));
        for (i, (&c, &y)) in rgb.iter().zip(&map.luminance).enumerate() {
            // Exposure 2 divided out; each component within one mantissa step (2^(e−8)) of
            // its value, so Y within one step of the largest component.
            let expected = luminance(c) / 2.0;
            let v = c[0].max(c[1]).max(c[2]);
            let step = 2f32.powi(v.log2().floor() as i32 + 1 - 8);
            assert!(
                (y - expected).abs() <= step,
                "pixel {i}: {y} vs {expected} (step {step})"
            );
        }
    }

    #[test]
    fn flat_rgbe_reads_back_within_its_precision() {
        check_round_trip(false);
    }

    #[test]
    fn run_length_rgbe_reads_back_within_its_precision() {
        check_round_trip(true);
    }

    #[test]
    fn old_style_repeats_fill_the_scanline() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("old.hdr");
        let mut out = b"#?RADIANCE\n\n-Y 1 +X 6\n".to_vec();
        // One pixel (128, 128, 128, 129) = 1.0 each, then "repeat 5 times".
        out.extend_from_slice(&[128, 128, 128, 129, 1, 1, 1, 5]);
        std::fs::write(&path, out).unwrap();
        let map = read_hdr(&path).unwrap();
        assert_eq!(map.luminance.len(), 6);
        for y in map.luminance {
            assert!((y - 128.5 / 128.0).abs() < 1e-6, "{y}");
        }
    }

    #[test]
    fn many_zero_repeats_are_an_error_not_a_panic() {
        // A pixel, then nine `1 1 1 0` repeats: the count's shift grows by 8 each time.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("repeats.hdr");
        let mut body = vec![128, 128, 128, 129];
        for _ in 0..9 {
            body.extend_from_slice(&[1, 1, 1, 0]);
        }
        body.extend_from_slice(&[1, 1, 1, 15]);
        write_raw(&path, "\n-Y 1 +X 16\n", &body);
        let err = read_map(&path).unwrap_err();
        assert!(err.contains("repeat count too large"), "{err}");
        assert!(!err.contains('\n'));
    }

    #[test]
    fn a_truncated_or_foreign_file_is_an_error() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("cut.hdr");
        let (w, h) = (16, 8);
        write_hdr(&path, w, h, &pattern(w, h), true);
        let bytes = std::fs::read(&path).unwrap();
        std::fs::write(&path, &bytes[..bytes.len() - 10]).unwrap();
        let err = read_hdr(&path).unwrap_err();
        assert!(err.contains("ends early"), "{err}");
        std::fs::write(&path, b"P6\n2 2\n255\n").unwrap();
        let err = read_hdr(&path).unwrap_err();
        assert!(err.contains("not a Radiance"), "{err}");
        assert!(!err.contains('\n'));
    }

    #[test]
    fn exr_round_trips_through_the_exr_writer() {
        let dir = tempfile::tempdir().unwrap();
        for (name, alpha) in [("rgb.exr", false), ("rgba.exr", true)] {
            let path = dir.path().join(name);
            let (w, h) = (24, 12);
            let rgb = pattern(w, h);
            if alpha {
                // Half floats: 11 bits of mantissa.
                exr::prelude::write_rgba_file(&path, w, h, |x, y| {
                    let c = rgb[y * w + x];
                    (
                        exr::prelude::f16::from_f32(c[0]),
                        exr::prelude::f16::from_f32(c[1]),
                        exr::prelude::f16::from_f32(c[2]),
                        exr::prelude::f16::from_f32(1.0),
                    )
                })
                .unwrap();
            } else {
                exr::prelude::write_rgb_file(&path, w, h, |x, y| {
                    let c = rgb[y * w + x];
                    (c[0], c[1], c[2])
                })
                .unwrap();
            }
            let map = read_map(&path).unwrap();
            assert_eq!((map.width, map.height), (w, h));
            let tolerance = if alpha { 1e-3 } else { 1e-6 };
            for (&c, &y) in rgb.iter().zip(&map.luminance) {
                let expected = luminance(c);
                assert!(
                    (y - expected).abs() <= tolerance * expected.max(1e-3),
                    "{name}: {y} vs {expected}"
                );
            }
        }
    }

    /// A picture of `header` (the lines after the signature) followed by `body`.
    fn write_raw(path: &Path, header: &str, body: &[u8]) {
        let mut out = format!("#?RADIANCE\n{header}").into_bytes();
        out.extend_from_slice(body);
        std::fs::write(path, out).unwrap();
    }

    #[test]
    fn sizes_past_the_limit_are_refused_before_allocating() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("big.hdr");
        // 2^32 × 2^32 wraps to 0 in 64 bits, 3 × 6148914691236517206 to 2; 16384 × 2 fits
        // the pixel count but not a side.
        for resolution in [
            "-Y 4294967296 +X 4294967296",
            "-Y 3 +X 6148914691236517206",
            "-Y 18446744073709551615 +X 2",
            "-Y 2 +X 16384",
        ] {
            write_raw(&path, &format!("\n{resolution}\n"), &[128, 128, 128, 129]);
            let err = read_map(&path).unwrap_err();
            assert!(err.contains("more than the limit"), "{resolution}: {err}");
            let err = map_size(&path).unwrap_err();
            assert!(err.contains("more than the limit"), "{resolution}: {err}");
        }
    }

    #[test]
    fn an_exposure_product_out_of_range_is_refused() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("dim.hdr");
        // Each factor is a positive number; their product underflows to 0 or overflows to
        // infinity in 32 bits.
        for factors in [
            "EXPOSURE=1e-30\nEXPOSURE=1e-30\n",
            "EXPOSURE=1e30\nEXPOSURE=1e30\n",
        ] {
            write_raw(&path, &format!("{factors}\n-Y 1 +X 2\n"), &[128; 8]);
            let err = read_map(&path).unwrap_err();
            assert!(err.contains("EXPOSURE"), "{factors}: {err}");
        }
        // A product within range is divided out.
        write_raw(
            &path,
            "EXPOSURE=4\nEXPOSURE=0.5\n\n-Y 1 +X 2\n",
            &[128, 128, 128, 129, 128, 128, 128, 129],
        );
        let map = read_map(&path).unwrap();
        assert!(
            (map.luminance[0] - 128.5 / 128.0 / 2.0).abs() < 1e-6,
            "{:?}",
            map.luminance
        );
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

    #[test]
    fn a_multi_part_exr_is_refused() {
        use exr::prelude::*;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("parts.exr");
        // A small first part without colour, then a larger RGB part: the part read would not
        // be the part checked.
        let depth = AnyChannels::sort(SmallVec::from_vec(vec![AnyChannel::new(
            "Z",
            FlatSamples::F32(vec![0.0; 8]),
        )]));
        let small = Layer::new(
            (4, 2),
            LayerAttributes::named("depth"),
            Encoding::UNCOMPRESSED,
            depth,
        );
        let big = Layer::new(
            (32, 16),
            LayerAttributes::named("colour"),
            Encoding::UNCOMPRESSED,
            SpecificChannels::rgb(|_pos: Vec2<usize>| (1.0f32, 1.0f32, 1.0f32)),
        );
        Image::empty(ImageAttributes::new(IntegerBounds::from_dimensions((
            32, 16,
        ))))
        .with_layer(small)
        .with_layer(big)
        .write()
        .to_file(&path)
        .unwrap();
        let err = read_map(&path).unwrap_err();
        assert!(err.contains("multi-part"), "{err}");
        assert!(map_size(&path).unwrap_err().contains("multi-part"));
    }
}

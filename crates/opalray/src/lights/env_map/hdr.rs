//! The Radiance picture reader, after Greg Ward's format (`#?RADIANCE` header,
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

use super::{check_size, luminance, LuminanceMap};

#[cfg(test)]
mod tests;

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

/// What a Radiance header says of its picture.
pub(super) struct Header {
    /// Pixels per row.
    pub(super) width: usize,
    /// Rows.
    pub(super) height: usize,
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

pub(super) fn read_header(r: &mut impl BufRead) -> Result<Header, String> {
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

//! The Radiance reader against pictures written here as Radiance writes them: round trips
//! of flat and run-length scanlines, old-style repeats, and damaged or oversized files.

use std::path::Path;

use super::super::tests::pattern;
use super::super::{luminance, map_size, read_map};
use super::read_hdr;

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

//! Display images: linear RGB → gamut-mapped, sRGB-encoded PNG, 8 or 16 bits per channel.

use std::path::Path;

use crate::color::{to_display_rgb16, to_display_rgb8, RgbImage};
use crate::error::{Error, Result};
use crate::scene::ColorConfig;

use super::encode_png;
use super::provenance::Provenance;

/// Write a linear RGB image as an sRGB-encoded PNG (with an `sRGB` chunk), atomically:
/// gamut mapping per `color.gamut`, then the sRGB transfer curve, at `color.bit_depth`
/// (8 or 16) bits per channel. Exposure is not applied here (it is part of
/// [`to_rgb`](crate::color::to_rgb)).
pub fn write_png(
    path: &Path,
    rgb: &RgbImage,
    color: &ColorConfig,
    provenance: &Provenance,
) -> Result<()> {
    let (width, height) = dimensions(path, rgb)?;
    match color.bit_depth {
        8 => encode_png(
            path,
            width,
            height,
            png::ColorType::Rgb,
            png::BitDepth::Eight,
            &to_display_rgb8(rgb, color),
            provenance,
        ),
        16 => {
            let codes = to_display_rgb16(rgb, color);
            let bytes: Vec<u8> = codes.iter().flat_map(|c| c.to_be_bytes()).collect();
            encode_png(
                path,
                width,
                height,
                png::ColorType::Rgb,
                png::BitDepth::Sixteen,
                &bytes,
                provenance,
            )
        }
        other => Err(Error::field(
            "color.bit_depth",
            format!("must be 8 or 16, got {other}; try 8"),
        )),
    }
}

/// Check that the image is non-empty, consistent and small enough for the file formats.
pub(crate) fn dimensions(path: &Path, rgb: &RgbImage) -> Result<(u32, u32)> {
    let fits = |v: usize| u32::try_from(v).ok().filter(|&v| v > 0 && v < (1 << 24));
    match (fits(rgb.width), fits(rgb.height)) {
        (Some(w), Some(h)) if rgb.data.len() == rgb.width * rgb.height => Ok((w, h)),
        _ => Err(Error::Encode {
            path: path.to_path_buf(),
            message: format!(
                "image is {} × {} pixels with {} values; need 1 ..= 16777215 pixels a side and \
                 width × height values",
                rgb.width,
                rgb.height,
                rgb.data.len()
            ),
        }),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp() -> RgbImage {
        RgbImage {
            width: 4,
            height: 2,
            data: (0..8)
                .map(|i| [i as f32 / 7.0, 0.5, 1.0 - i as f32 / 7.0])
                .collect(),
        }
    }

    #[test]
    fn png_8_bit_round_trips_through_the_image_crate() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.png");
        let rgb = ramp();
        write_png(&path, &rgb, &ColorConfig::default(), &Provenance::default()).unwrap();
        let read = image::open(&path).unwrap();
        assert_eq!(read.color(), image::ColorType::Rgb8);
        let expected = to_display_rgb8(&rgb, &ColorConfig::default());
        assert_eq!(read.to_rgb8().as_raw(), &expected);
    }

    #[test]
    fn png_16_bit_round_trips_through_the_image_crate() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a16.png");
        let color = ColorConfig {
            bit_depth: 16,
            ..ColorConfig::default()
        };
        let rgb = ramp();
        write_png(&path, &rgb, &color, &Provenance::default()).unwrap();
        let read = image::open(&path).unwrap();
        assert_eq!(read.color(), image::ColorType::Rgb16);
        let codes = read.to_rgb16().into_raw();
        assert_eq!(codes, to_display_rgb16(&rgb, &color));
        // Decoding the codes gives back the linear values to 16-bit precision.
        for (code, px) in codes.chunks(3).zip(&rgb.data) {
            for (c, v) in code.iter().zip(px) {
                let back = crate::color::decode_srgb(*c as f32 / 65535.0);
                assert!((back - v).abs() < 2e-5, "{back} vs {v}");
            }
        }
    }

    #[test]
    fn empty_or_inconsistent_image_is_refused_and_nothing_written() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("e.png");
        let bad = RgbImage {
            width: 3,
            height: 1,
            data: vec![[0.0; 3]; 2],
        };
        assert!(write_png(&path, &bad, &ColorConfig::default(), &Provenance::default()).is_err());
        let empty = RgbImage {
            width: 0,
            height: 0,
            data: vec![],
        };
        assert!(write_png(
            &path,
            &empty,
            &ColorConfig::default(),
            &Provenance::default()
        )
        .is_err());
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
    }
}

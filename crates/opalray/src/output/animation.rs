//! Animations of rendered frames: GIF (every viewer) and APNG (full colour).

use std::path::Path;

use crate::error::{Error, Result};
use crate::output::write_atomic;

/// Write RGB8 frames (each `width × height`) as a looping animated GIF, `delay_ms` per frame.
/// Colours are quantised per frame (NeuQuant, as the GIF format allows 256 colours).
pub fn write_gif(
    path: &Path,
    frames: &[Vec<u8>],
    width: u32,
    height: u32,
    delay_ms: u32,
) -> Result<()> {
    use image::codecs::gif::{GifEncoder, Repeat};
    use image::{Delay, Frame, RgbaImage};
    let encode = |w: &mut dyn std::io::Write| -> std::io::Result<()> {
        let mut encoder = GifEncoder::new_with_speed(w, 10);
        encoder
            .set_repeat(Repeat::Infinite)
            .map_err(std::io::Error::other)?;
        for rgb in frames {
            let rgba: Vec<u8> = rgb
                .chunks_exact(3)
                .flat_map(|p| [p[0], p[1], p[2], 255])
                .collect();
            let image = RgbaImage::from_raw(width, height, rgba)
                .ok_or_else(|| std::io::Error::other("frame size does not match"))?;
            let frame = Frame::from_parts(image, 0, 0, Delay::from_numer_denom_ms(delay_ms, 1));
            encoder.encode_frame(frame).map_err(std::io::Error::other)?;
        }
        Ok(())
    };
    write_atomic(path, |w| encode(w)).map_err(|e| match e {
        Error::Io { path, source } => Error::Encode {
            path,
            message: source.to_string(),
        },
        other => other,
    })
}

/// Write RGB8 frames as a looping animated PNG (APNG), `delay_ms` per frame, sRGB tagged.
pub fn write_apng(
    path: &Path,
    frames: &[Vec<u8>],
    width: u32,
    height: u32,
    delay_ms: u32,
) -> Result<()> {
    let encode_error = |e: png::EncodingError| std::io::Error::other(e.to_string());
    write_atomic(path, |w| {
        let mut encoder = png::Encoder::new(w, width, height);
        encoder.set_color(png::ColorType::Rgb);
        encoder.set_depth(png::BitDepth::Eight);
        encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
        encoder
            .set_animated(frames.len() as u32, 0)
            .map_err(encode_error)?;
        encoder
            .set_frame_delay(delay_ms.min(u32::from(u16::MAX)) as u16, 1000)
            .map_err(encode_error)?;
        let mut writer = encoder.write_header().map_err(encode_error)?;
        for rgb in frames {
            writer.write_image_data(rgb).map_err(encode_error)?;
        }
        writer.finish().map_err(encode_error)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn frames() -> Vec<Vec<u8>> {
        (0..3u8).map(|k| vec![k * 80; 4 * 2 * 3]).collect()
    }

    #[test]
    fn gif_has_every_frame() {
        use image::AnimationDecoder;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.gif");
        write_gif(&path, &frames(), 4, 2, 100).unwrap();
        let file = std::io::BufReader::new(std::fs::File::open(&path).unwrap());
        let decoded = image::codecs::gif::GifDecoder::new(file).unwrap();
        assert_eq!(decoded.into_frames().count(), 3);
    }

    #[test]
    fn apng_declares_every_frame() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.png");
        write_apng(&path, &frames(), 4, 2, 100).unwrap();
        let decoder =
            png::Decoder::new(std::io::BufReader::new(std::fs::File::open(&path).unwrap()));
        let reader = decoder.read_info().unwrap();
        assert_eq!(reader.info().animation_control().unwrap().num_frames, 3);
    }
}

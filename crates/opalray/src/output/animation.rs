//! Animations of rendered frames: GIF (every viewer) and APNG (full colour).

use std::path::Path;

use crate::error::{Error, Result};
use crate::output::write_atomic;

/// Write RGB8 frames (each `width × height`) as a looping animated GIF, `delay_ms` per frame.
/// Colours are quantised per frame (NeuQuant, as the GIF format allows 256 colours), the
/// frames in parallel: each frame's palette depends on that frame alone, so the file is the
/// same at any thread count.
pub fn write_gif(
    path: &Path,
    frames: &[Vec<u8>],
    width: u32,
    height: u32,
    delay_ms: u32,
) -> Result<()> {
    use rayon::prelude::*;
    let too_large = || Error::Encode {
        path: path.to_path_buf(),
        message: format!("a GIF is at most 65535 pixels on a side, not {width} × {height}"),
    };
    let w = u16::try_from(width).map_err(|_| too_large())?;
    let h = u16::try_from(height).map_err(|_| too_large())?;
    let pixels = width as usize * height as usize;
    if let Some(bad) = frames.iter().find(|f| f.len() != 3 * pixels) {
        return Err(Error::Encode {
            path: path.to_path_buf(),
            message: format!(
                "a frame holds {} bytes, not the {} of {width} × {height} RGB",
                bad.len(),
                3 * pixels
            ),
        });
    }
    // GIF delays are in hundredths of a second.
    let delay = u16::try_from(delay_ms.div_ceil(10)).unwrap_or(u16::MAX);
    let quantised: Vec<gif::Frame<'static>> = frames
        .par_iter()
        .map(|rgb| {
            let mut rgba: Vec<u8> = rgb
                .chunks_exact(3)
                .flat_map(|p| [p[0], p[1], p[2], 255])
                .collect();
            let mut frame = gif::Frame::from_rgba_speed(w, h, &mut rgba, 10);
            frame.delay = delay;
            frame
        })
        .collect();
    let encode = |out: &mut dyn std::io::Write| -> std::io::Result<()> {
        let mut encoder = gif::Encoder::new(out, w, h, &[]).map_err(std::io::Error::other)?;
        encoder
            .set_repeat(gif::Repeat::Infinite)
            .map_err(std::io::Error::other)?;
        for frame in &quantised {
            encoder.write_frame(frame).map_err(std::io::Error::other)?;
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
        encoder.set_compression(super::COMPRESSION);
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
        let frames: Vec<image::Frame> = decoded.into_frames().map(|f| f.unwrap()).collect();
        assert_eq!(frames.len(), 3);
        // 100 ms a frame; the second frame's grey (80) survives the palette.
        assert_eq!(frames[1].delay().numer_denom_ms(), (100, 1));
        assert_eq!(frames[1].buffer().get_pixel(2, 1).0, [80, 80, 80, 255]);
    }

    #[test]
    fn gif_refuses_a_frame_of_the_wrong_size_and_writes_nothing() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.gif");
        let mut bad = frames();
        bad[1].pop();
        let err = write_gif(&path, &bad, 4, 2, 100).unwrap_err().to_string();
        assert!(err.contains("23 bytes, not the 24"), "{err}");
        assert!(!path.exists());
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

//! Animations of rendered frames: GIF (every viewer) and APNG (full colour).

use std::fs::File;
use std::io::BufWriter;
use std::path::{Path, PathBuf};

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

/// An animation written one frame at a time, so that a sweep need not keep its frames: the
/// same bytes as [`write_gif`] / [`write_apng`] given the same frames. It writes `path`
/// directly, not atomically: give it a temporary path that the caller renames once
/// everything is written (the command's staged outputs do).
pub struct AnimationWriter {
    path: PathBuf,
    width: u32,
    height: u32,
    encoder: Encoder,
}

enum Encoder {
    Gif(gif::Encoder<BufWriter<File>>, u16),
    // Unbuffered: the encoder writes whole chunks, and a failed write is seen at once.
    Apng(png::Writer<File>),
}

impl AnimationWriter {
    /// Start an animation of `frames` frames of `width × height` at `path`: an APNG if
    /// `apng`, else a GIF (at most 65535 pixels on a side).
    pub fn create(
        path: &Path,
        apng: bool,
        frames: u32,
        width: u32,
        height: u32,
        delay_ms: u32,
    ) -> Result<Self> {
        let fail = |message: String| Error::Encode {
            path: path.to_path_buf(),
            message,
        };
        let file = File::create(path).map_err(|e| Error::io(path, e))?;
        let encoder = if apng {
            let mut encoder = png::Encoder::new(file, width, height);
            encoder.set_color(png::ColorType::Rgb);
            encoder.set_depth(png::BitDepth::Eight);
            encoder.set_source_srgb(png::SrgbRenderingIntent::Perceptual);
            encoder.set_compression(super::COMPRESSION);
            encoder
                .set_animated(frames, 0)
                .map_err(|e| fail(e.to_string()))?;
            encoder
                .set_frame_delay(delay_ms.min(u32::from(u16::MAX)) as u16, 1000)
                .map_err(|e| fail(e.to_string()))?;
            Encoder::Apng(encoder.write_header().map_err(|e| fail(e.to_string()))?)
        } else {
            let too_large = || {
                fail(format!(
                    "a GIF is at most 65535 pixels on a side, not {width} × {height}"
                ))
            };
            let w = u16::try_from(width).map_err(|_| too_large())?;
            let h = u16::try_from(height).map_err(|_| too_large())?;
            let mut encoder = gif::Encoder::new(BufWriter::new(file), w, h, &[])
                .map_err(|e| fail(e.to_string()))?;
            encoder
                .set_repeat(gif::Repeat::Infinite)
                .map_err(|e| fail(e.to_string()))?;
            // GIF delays are in hundredths of a second.
            let delay = u16::try_from(delay_ms.div_ceil(10)).unwrap_or(u16::MAX);
            Encoder::Gif(encoder, delay)
        };
        Ok(AnimationWriter {
            path: path.to_path_buf(),
            width,
            height,
            encoder,
        })
    }

    /// Append one RGB8 frame (`width × height`, rows top to bottom).
    pub fn push(&mut self, rgb: &[u8]) -> Result<()> {
        let fail = |message: String| Error::Encode {
            path: self.path.clone(),
            message,
        };
        let pixels = self.width as usize * self.height as usize;
        if rgb.len() != 3 * pixels {
            return Err(fail(format!(
                "a frame holds {} bytes, not the {} of {} × {} RGB",
                rgb.len(),
                3 * pixels,
                self.width,
                self.height
            )));
        }
        match &mut self.encoder {
            Encoder::Gif(encoder, delay) => {
                let mut rgba: Vec<u8> = rgb
                    .chunks_exact(3)
                    .flat_map(|p| [p[0], p[1], p[2], 255])
                    .collect();
                let mut frame = gif::Frame::from_rgba_speed(
                    self.width as u16,
                    self.height as u16,
                    &mut rgba,
                    10,
                );
                frame.delay = *delay;
                encoder.write_frame(&frame).map_err(|e| fail(e.to_string()))
            }
            Encoder::Apng(writer) => writer
                .write_image_data(rgb)
                .map_err(|e| fail(e.to_string())),
        }
    }

    /// Write the end of the file and flush it to disk.
    pub fn finish(self) -> Result<()> {
        let path = self.path;
        let fail = |message: String| Error::Encode {
            path: path.clone(),
            message,
        };
        let file = match self.encoder {
            Encoder::Gif(encoder, _) => encoder.into_inner().map_err(|e| fail(e.to_string()))?,
            Encoder::Apng(writer) => {
                writer.finish().map_err(|e| fail(e.to_string()))?;
                return Ok(());
            }
        };
        let file = file.into_inner().map_err(|e| fail(e.to_string()))?;
        file.sync_all().map_err(|e| Error::io(&path, e))
    }
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
    fn streamed_animations_are_the_same_bytes() {
        let dir = tempfile::tempdir().unwrap();
        for apng in [false, true] {
            let whole = dir.path().join("whole");
            let streamed = dir.path().join("streamed");
            if apng {
                write_apng(&whole, &frames(), 4, 2, 100).unwrap();
            } else {
                write_gif(&whole, &frames(), 4, 2, 100).unwrap();
            }
            let mut writer = AnimationWriter::create(&streamed, apng, 3, 4, 2, 100).unwrap();
            for frame in frames() {
                writer.push(&frame).unwrap();
            }
            writer.finish().unwrap();
            assert!(std::fs::read(&whole).unwrap() == std::fs::read(&streamed).unwrap());
        }
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

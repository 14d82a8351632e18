//! The spectrum plot's text: DejaVu Sans (`data/fonts`, a subset of printable ASCII and
//! `° µ × θ λ – −`, under its licence beside it), rasterised by `ab_glyph` and blended by
//! coverage over an RGB8 image, across or turned a quarter to read upwards (an axis title).

use std::sync::LazyLock;

use ab_glyph::{point, Font, FontRef, PxScale, ScaleFont};

/// DejaVu Sans, subset (see `data/fonts/README.md`).
static FONT_DATA: &[u8] = include_bytes!("../../../../../data/fonts/DejaVuSans-subset.ttf");

/// The font, parsed once.
static FONT: LazyLock<FontRef<'static>> =
    LazyLock::new(|| FontRef::try_from_slice(FONT_DATA).expect("the embedded font parses"));

fn font() -> &'static FontRef<'static> {
    &FONT
}

/// A line of text as coverage (0..1), `width × height`, row-major, row 0 at the top of
/// the font's ascent.
struct Coverage {
    width: usize,
    height: usize,
    alpha: Vec<f32>,
}

/// Rasterise `text` at `size_px` (the font's em): glyphs placed by their advances and
/// kerning on one baseline.
fn rasterise(text: &str, size_px: f32) -> Coverage {
    let font = font();
    let scaled = font.as_scaled(PxScale::from(size_px));
    let height = (scaled.ascent() - scaled.descent()).ceil() as usize;
    let width = text_width(text, size_px);
    let mut alpha = vec![0.0f32; width * height];
    let mut x = 0.0f32;
    let mut last = None;
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(prev) = last {
            x += scaled.kern(prev, id);
        }
        let glyph = id.with_scale_and_position(size_px, point(x, scaled.ascent()));
        x += scaled.h_advance(id);
        last = Some(id);
        let Some(outline) = font.outline_glyph(glyph) else {
            continue; // a space
        };
        let bounds = outline.px_bounds();
        outline.draw(|gx, gy, c| {
            let px = bounds.min.x as i64 + i64::from(gx);
            let py = bounds.min.y as i64 + i64::from(gy);
            if (0..width as i64).contains(&px) && (0..height as i64).contains(&py) {
                let at = py as usize * width + px as usize;
                alpha[at] = alpha[at].max(c);
            }
        });
    }
    Coverage {
        width,
        height,
        alpha,
    }
}

/// Width of `text` at `size_px`, px (rounded up).
pub fn text_width(text: &str, size_px: f32) -> usize {
    let font = font();
    let scaled = font.as_scaled(PxScale::from(size_px));
    let mut x = 0.0f32;
    let mut last = None;
    for c in text.chars() {
        let id = scaled.glyph_id(c);
        if let Some(prev) = last {
            x += scaled.kern(prev, id);
        }
        x += scaled.h_advance(id);
        last = Some(id);
    }
    x.ceil() as usize
}

/// Height of a line at `size_px`, px: ascent to descent.
pub fn text_height(size_px: f32) -> usize {
    let font = font();
    let scaled = font.as_scaled(PxScale::from(size_px));
    (scaled.ascent() - scaled.descent()).ceil() as usize
}

/// An RGB8 image to write text into: `width` pixels a row.
pub struct Canvas<'a> {
    /// The pixels, `width × height × 3`.
    pub rgb: &'a mut [u8],
    /// Pixels a row.
    pub width: usize,
}

impl Canvas<'_> {
    /// Blend `colour` at `(x, y)` by coverage `a`; outside the image nothing is drawn.
    fn blend(&mut self, x: usize, y: usize, a: f32, colour: [u8; 3]) {
        let height = self.rgb.len() / (3 * self.width);
        if a <= 0.0 || x >= self.width || y >= height {
            return;
        }
        let at = 3 * (y * self.width + x);
        for (code, &c) in self.rgb[at..at + 3].iter_mut().zip(&colour) {
            *code = (f32::from(*code) * (1.0 - a) + f32::from(c) * a).round() as u8;
        }
    }

    /// Write `text` across with its top-left corner at `(x, y)`.
    pub fn text(&mut self, x: usize, y: usize, text: &str, size_px: f32, colour: [u8; 3]) {
        let line = rasterise(text, size_px);
        for row in 0..line.height {
            for col in 0..line.width {
                self.blend(x + col, y + row, line.alpha[row * line.width + col], colour);
            }
        }
    }

    /// Write `text` turned a quarter counter-clockwise (reading upwards), the top-left
    /// corner of its box at `(x, y)`: [`text_height`] wide, [`text_width`] high.
    pub fn text_upwards(&mut self, x: usize, y: usize, text: &str, size_px: f32, colour: [u8; 3]) {
        let line = rasterise(text, size_px);
        for row in 0..line.height {
            for col in 0..line.width {
                let a = line.alpha[row * line.width + col];
                self.blend(x + row, y + line.width - 1 - col, a, colour);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_label_character_is_in_the_subset() {
        let font = font();
        for c in "0123456789.° nm wavelength (nm) angle in air θ inside the stone λ".chars() {
            assert!(font.glyph_id(c).0 != 0, "{c:?} missing from the font");
        }
    }

    #[test]
    fn text_covers_its_box_and_turns_upwards() {
        let (w, h) = (text_width("450", 14.0), text_height(14.0));
        assert!((20..40).contains(&w) && (12..20).contains(&h), "{w} × {h}");
        let mut rgb = vec![0u8; 3 * 64 * 64];
        let mut canvas = Canvas {
            rgb: &mut rgb,
            width: 64,
        };
        canvas.text(2, 2, "450", 14.0, [255, 255, 255]);
        let lit = |rgb: &[u8], x0: usize, x1: usize, y0: usize, y1: usize| {
            (y0..y1).any(|y| (x0..x1).any(|x| rgb[3 * (y * 64 + x)] > 128))
        };
        assert!(lit(&rgb, 2, 2 + w, 2, 2 + h));
        assert!(!lit(&rgb, 2 + w, 64, 0, 64) && !lit(&rgb, 0, 64, 2 + h, 64));
        let mut up = vec![0u8; 3 * 64 * 64];
        Canvas {
            rgb: &mut up,
            width: 64,
        }
        .text_upwards(2, 2, "450", 14.0, [255, 255, 255]);
        // The box turned: h wide, w high; the first digit at the bottom.
        assert!(lit(&up, 2, 2 + h, 2, 2 + w));
        assert!(!lit(&up, 2 + h, 64, 0, 64) && !lit(&up, 0, 64, 2 + w, 64));
        assert!(lit(&up, 2, 2 + h, 2 + w - w / 3, 2 + w));
    }
}

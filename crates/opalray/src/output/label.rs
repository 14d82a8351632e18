//! A tiny built-in bitmap font (5 × 7 pixels) for labelling contact sheets without a font
//! file: digits, sign, degree, decimal point and a few letters.

/// Glyph rows, top to bottom, 5 bits each (bit 4 = leftmost pixel).
fn glyph(c: char) -> Option<[u8; 7]> {
    Some(match c {
        '0' => [0x0E, 0x11, 0x13, 0x15, 0x19, 0x11, 0x0E],
        '1' => [0x04, 0x0C, 0x04, 0x04, 0x04, 0x04, 0x0E],
        '2' => [0x0E, 0x11, 0x01, 0x02, 0x04, 0x08, 0x1F],
        '3' => [0x1F, 0x02, 0x04, 0x02, 0x01, 0x11, 0x0E],
        '4' => [0x02, 0x06, 0x0A, 0x12, 0x1F, 0x02, 0x02],
        '5' => [0x1F, 0x10, 0x1E, 0x01, 0x01, 0x11, 0x0E],
        '6' => [0x06, 0x08, 0x10, 0x1E, 0x11, 0x11, 0x0E],
        '7' => [0x1F, 0x01, 0x02, 0x04, 0x08, 0x08, 0x08],
        '8' => [0x0E, 0x11, 0x11, 0x0E, 0x11, 0x11, 0x0E],
        '9' => [0x0E, 0x11, 0x11, 0x0F, 0x01, 0x02, 0x0C],
        '-' => [0x00, 0x00, 0x00, 0x1F, 0x00, 0x00, 0x00],
        '+' => [0x00, 0x04, 0x04, 0x1F, 0x04, 0x04, 0x00],
        '.' => [0x00, 0x00, 0x00, 0x00, 0x00, 0x0C, 0x0C],
        '°' => [0x0C, 0x12, 0x12, 0x0C, 0x00, 0x00, 0x00],
        ' ' => [0; 7],
        _ => return None,
    })
}

/// Width in pixels of `text` drawn at `scale`.
pub fn text_width(text: &str, scale: usize) -> usize {
    let n = text.chars().count();
    if n == 0 {
        0
    } else {
        (n * 6 - 1) * scale
    }
}

/// Draw `text` into an RGB8 image (`width` pixels wide) with its top-left corner at
/// `(x, y)`, each font pixel a `scale × scale` block. Characters without a glyph are skipped;
/// pixels outside the image are clipped.
pub fn draw_text(
    rgb: &mut [u8],
    width: usize,
    x: usize,
    y: usize,
    text: &str,
    scale: usize,
    colour: [u8; 3],
) {
    let height = rgb.len() / (3 * width);
    for (i, c) in text.chars().enumerate() {
        let Some(rows) = glyph(c) else { continue };
        let x0 = x + i * 6 * scale;
        for (row, bits) in rows.iter().enumerate() {
            for col in 0..5 {
                if bits & (0x10 >> col) == 0 {
                    continue;
                }
                for dy in 0..scale {
                    for dx in 0..scale {
                        let (px, py) = (x0 + col * scale + dx, y + row * scale + dy);
                        if px < width && py < height {
                            let at = 3 * (py * width + px);
                            rgb[at..at + 3].copy_from_slice(&colour);
                        }
                    }
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn digits_draw_distinct_pixels_and_clip() {
        let (w, h) = (40, 10);
        let mut a = vec![0u8; w * h * 3];
        let mut b = vec![0u8; w * h * 3];
        draw_text(&mut a, w, 0, 0, "-60°", 1, [255; 3]);
        draw_text(&mut b, w, 0, 0, "+60°", 1, [255; 3]);
        assert_ne!(a, b);
        assert!(a.contains(&255));
        // Drawing far outside the image changes nothing and does not panic.
        let mut c = vec![0u8; w * h * 3];
        draw_text(&mut c, w, 100, 100, "12", 2, [255; 3]);
        assert!(c.iter().all(|&v| v == 0));
        assert_eq!(text_width("-60°", 2), 46);
    }
}

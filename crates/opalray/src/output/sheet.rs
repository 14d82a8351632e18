//! Contact sheets: frames side by side with a label under each (the paper's fig. 11).

use super::label::{draw_text, text_width};

/// Height of the label strip under each frame, pixels, and the font scale used in it.
const LABEL_SCALE: usize = 2;
const LABEL_HEIGHT: usize = 7 * LABEL_SCALE + 10;
/// Gap between frames, pixels.
const GAP: usize = 4;
/// Sheet background (dark grey, sRGB).
const PAPER: [u8; 3] = [24, 24, 24];

/// An RGB8 contact sheet.
#[derive(Clone, Debug, PartialEq)]
pub struct ContactSheet {
    /// Width, pixels.
    pub width: usize,
    /// Height, pixels.
    pub height: usize,
    /// RGB8 pixels, rows top to bottom.
    pub rgb: Vec<u8>,
}

/// The label under a sweep's frame at `value_deg` degrees, the value as swept: a whole
/// degree without a decimal ("-30°", "2°"), any other with one, rounded half away from zero
/// ("2.5°", "-7.5°"; "3.3°" for 10/3).
pub fn sheet_label(value_deg: f64) -> String {
    let tenths = (value_deg * 10.0).round();
    // `+ 0.0` makes a negative zero (a value just below 0) plain "0".
    if tenths % 10.0 == 0.0 {
        format!("{}°", tenths / 10.0 + 0.0)
    } else {
        format!("{:.1}°", tenths / 10.0)
    }
}

/// Lay out RGB8 frames (each `width × height`) in rows of `columns`, each with its label
/// (e.g. "-60°") centred under it.
pub fn contact_sheet(
    frames: &[(Vec<u8>, String)],
    width: usize,
    height: usize,
    columns: usize,
) -> ContactSheet {
    let mut sheet = ContactSheet::blank(frames.len(), width, height, columns);
    for (k, (frame, label)) in frames.iter().enumerate() {
        sheet.place(k, frame, width, height, label);
    }
    sheet
}

impl ContactSheet {
    /// An empty sheet for `count` frames of `width × height` in rows of `columns`, to be
    /// filled one frame at a time with [`ContactSheet::place`] (the frames need not all be
    /// held at once). The same bytes as [`contact_sheet`] once every frame is placed.
    pub fn blank(count: usize, width: usize, height: usize, columns: usize) -> ContactSheet {
        let (sheet_w, sheet_h) = Self::size(count, width, height, columns);
        let rgb: Vec<u8> = PAPER
            .iter()
            .copied()
            .cycle()
            .take(sheet_w * sheet_h * 3)
            .collect();
        ContactSheet {
            width: sheet_w,
            height: sheet_h,
            rgb,
        }
    }

    /// Width and height in pixels of the sheet of `count` frames (as [`ContactSheet::blank`]).
    pub fn size(count: usize, width: usize, height: usize, columns: usize) -> (usize, usize) {
        let columns = columns.clamp(1, count.max(1));
        let rows = count.div_ceil(columns);
        (
            columns * (width + GAP) + GAP,
            rows * (height + LABEL_HEIGHT) + GAP,
        )
    }

    /// Copy frame `k` (RGB8, `width × height`) into its cell with `label` under it.
    pub fn place(&mut self, k: usize, frame: &[u8], width: usize, height: usize, label: &str) {
        let cell_w = width + GAP;
        let cell_h = height + LABEL_HEIGHT;
        let columns = (self.width - GAP) / cell_w;
        let sheet_w = self.width;
        let x0 = GAP + (k % columns) * cell_w;
        let y0 = GAP + (k / columns) * cell_h;
        for y in 0..height {
            let src = &frame[y * width * 3..(y + 1) * width * 3];
            let at = ((y0 + y) * sheet_w + x0) * 3;
            self.rgb[at..at + width * 3].copy_from_slice(src);
        }
        let tw = text_width(label, LABEL_SCALE);
        let tx = x0 + width.saturating_sub(tw) / 2;
        draw_text(
            &mut self.rgb,
            sheet_w,
            tx,
            y0 + height + 5,
            label,
            LABEL_SCALE,
            [230, 230, 230],
        );
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sheet_labels_are_the_values_as_swept() {
        // The nine tilts of `opalray sweep --tilt-from 0 --tilt-to 20`: 2.5° apart.
        for (value, label) in [
            (-30.0, "-30°"),
            (0.0, "0°"),
            (-0.01, "0°"),
            (2.5, "2.5°"),
            (-7.5, "-7.5°"),
            (2.25, "2.3°"),
            (10.0 / 3.0, "3.3°"),
            (60.0, "60°"),
        ] {
            assert_eq!(sheet_label(value), label, "{value}");
        }
    }

    #[test]
    fn frames_land_in_their_cells() {
        let frames: Vec<(Vec<u8>, String)> = (0..5u8)
            .map(|k| (vec![50 + k * 40; 8 * 6 * 3], format!("{k}")))
            .collect();
        let sheet = contact_sheet(&frames, 8, 6, 3);
        assert_eq!(sheet.width, 3 * (8 + GAP) + GAP);
        assert_eq!(sheet.height, 2 * (6 + LABEL_HEIGHT) + GAP);
        // The top-left pixel of frame 4 (row 1, column 1).
        let (x, y) = (GAP + (8 + GAP), GAP + (6 + LABEL_HEIGHT));
        assert_eq!(sheet.rgb[(y * sheet.width + x) * 3], 50 + 4 * 40);
    }
}

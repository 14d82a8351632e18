//! The `--plot` image of `opalray spectrum`: reflectance over wavelength × angle, each
//! wavelength in its own colour, so the Bragg–Snell band (paper §2.3, §3.1) is seen bending
//! to blue as the angle grows.
//!
//! Input: the cluster's layer model, the wavelength range and the largest angle → output: an
//! sRGB PNG of [`WIDTH_PX`] × [`HEIGHT_PX`] pixels. Its data area holds [`DATA_COLUMNS`]
//! columns from `--from-nm` (left) to `--to-nm` (right) and [`DATA_ROWS`] rows from 0° (bottom)
//! to the largest requested angle (top); its top-left pixel is at ([`LEFT_PX`], [`TOP_PX`]).
//! A pixel is the colour of a monochromatic line at its wavelength (linear sRGB, brightest
//! level of its hue) times the mean unpolarised reflectance R over the pixel, sRGB-encoded:
//! the encoding follows lightness, so a side lobe of R = 1 % still shows faintly.

use std::path::Path;

use opalray::color::{encode_srgb8, wavelength_linear_srgb};
use opalray::optics::{ClusterOptics, ClusterStack};
use opalray::output::write_png_rgb8;
use rayon::prelude::*;

use super::label::{text_height, text_width, Canvas};

/// Columns of the data area, evenly spaced over `--from-nm`..`--to-nm`.
pub const DATA_COLUMNS: usize = 800;
/// Rows of the data area, evenly spaced from the largest angle (top) down to 0° (bottom).
pub const DATA_ROWS: usize = 360;
/// Margin left of the data area (the angle axis's title and labels), px.
pub const LEFT_PX: usize = 80;
/// Margin above the data area, px.
pub const TOP_PX: usize = 12;
/// Margin right of the data area (marks of the requested angles), px.
const RIGHT_PX: usize = 24;
/// Margin below the data area (the wavelength labels and the axis's title), px.
const BOTTOM_PX: usize = 60;
/// Width of the PNG, px.
pub const WIDTH_PX: usize = LEFT_PX + DATA_COLUMNS + RIGHT_PX;
/// Height of the PNG, px.
pub const HEIGHT_PX: usize = TOP_PX + DATA_ROWS + BOTTOM_PX;

/// Finest wavelength step averaged into one pixel, nm: well under the spacing of the side
/// lobes of the default crystal, λ²/(2 n_eff d N) ≈ 1.5 nm at 589 nm.
const SUB_STEP_NM: f64 = 0.1;
/// Most wavelengths averaged into one pixel (a 1600 nm wide plot still gets 0.1 nm).
const MAX_SUB_SAMPLES: usize = 64;
/// Size of the tick labels (the font's em), px.
const LABEL_PX: f32 = 14.0;
/// Size of the axis titles, px.
const TITLE_PX: f32 = 15.0;
/// Gap between the titles and the image's edge, px.
const EDGE_PX: usize = 4;
/// Length of a tick mark, px.
const TICK_PX: usize = 6;
/// Gap between a tick and its label, px.
const LABEL_GAP_PX: usize = 4;
/// Closest spacing of wavelength ticks, px (a 3-digit label is 27 px wide).
const WAVELENGTH_TICK_MIN_PX: f64 = 70.0;
/// Closest spacing of angle ticks, px.
const ANGLE_TICK_MIN_PX: f64 = 40.0;
const AXIS_COLOUR: [u8; 3] = [150, 150, 150];
const LABEL_COLOUR: [u8; 3] = [230, 230, 230];
const MARK_COLOUR: [u8; 3] = [255, 255, 255];

/// What the plot spans.
pub struct PlotAxes {
    /// Wavelength at the left edge, nm.
    pub from_nm: f64,
    /// Wavelength at the right edge, nm (> `from_nm`).
    pub to_nm: f64,
    /// Angle of the top row, degrees in [0, 90); the bottom row is 0°.
    pub top_deg: f64,
    /// Angle (degrees) → cos θ inside the stone (in air or inside, as the command's angles).
    pub cos_inside: fn(&ClusterStack, f64) -> f64,
    /// Angles marked on the right edge (the rows of the printed table), degrees.
    pub marked_deg: Vec<f64>,
    /// The angle axis's title: where the angle is measured.
    pub angle_title: &'static str,
}

impl PlotAxes {
    fn column_width_nm(&self) -> f64 {
        (self.to_nm - self.from_nm) / DATA_COLUMNS as f64
    }

    /// Angle of data row `row` (0 = top), degrees.
    fn row_angle_deg(&self, row: usize) -> f64 {
        self.top_deg * (DATA_ROWS - 1 - row) as f64 / (DATA_ROWS - 1) as f64
    }

    /// Data row (0 = top) nearest to `angle_deg`.
    fn row_of(&self, angle_deg: f64) -> usize {
        if self.top_deg <= 0.0 {
            return DATA_ROWS - 1;
        }
        let from_bottom = (angle_deg / self.top_deg * (DATA_ROWS - 1) as f64).round() as usize;
        DATA_ROWS - 1 - from_bottom.min(DATA_ROWS - 1)
    }

    /// Data column whose centre is nearest to `wavelength_nm`.
    fn column_of(&self, wavelength_nm: f64) -> usize {
        let at = ((wavelength_nm - self.from_nm) / self.column_width_nm() - 0.5).round();
        at.clamp(0.0, (DATA_COLUMNS - 1) as f64) as usize
    }
}

/// Draw the plot of `optics` over `axes` and write it to `path` (a `.png`), atomically.
pub fn write_plot(path: &Path, optics: &ClusterOptics, axes: &PlotAxes) -> opalray::Result<()> {
    let data = data_pixels(optics, axes);
    let mut rgb = vec![0u8; WIDTH_PX * HEIGHT_PX * 3];
    for (row, line) in data.chunks_exact(DATA_COLUMNS * 3).enumerate() {
        let at = 3 * ((TOP_PX + row) * WIDTH_PX + LEFT_PX);
        rgb[at..at + line.len()].copy_from_slice(line);
    }
    draw_axes(&mut rgb, axes);
    write_png_rgb8(path, WIDTH_PX as u32, HEIGHT_PX as u32, &rgb)
}

/// RGB8 codes of the data area, rows top to bottom: each wavelength's colour times the mean
/// R over the pixel's wavelength span.
fn data_pixels(optics: &ClusterOptics, axes: &PlotAxes) -> Vec<u8> {
    let width_nm = axes.column_width_nm();
    let subs = ((width_nm / SUB_STEP_NM).ceil() as usize).clamp(1, MAX_SUB_SAMPLES);
    let hues: Vec<[f32; 3]> = (0..DATA_COLUMNS)
        .map(|col| wavelength_linear_srgb(axes.from_nm + (col as f64 + 0.5) * width_nm))
        .collect();
    let mut data = vec![0u8; DATA_COLUMNS * DATA_ROWS * 3];
    data.par_chunks_mut(DATA_COLUMNS * 3)
        .enumerate()
        .for_each(|(row, line)| {
            let at = optics.at((axes.cos_inside)(&optics.stack, axes.row_angle_deg(row)));
            for (col, (pixel, hue)) in line.chunks_exact_mut(3).zip(&hues).enumerate() {
                let left_nm = axes.from_nm + col as f64 * width_nm;
                let sum: f64 = (0..subs)
                    .map(|s| {
                        let wl = left_nm + (s as f64 + 0.5) / subs as f64 * width_nm;
                        at.rt_unpolarized(wl).0
                    })
                    .sum();
                let r = (sum / subs as f64) as f32;
                for (code, &h) in pixel.iter_mut().zip(hue) {
                    *code = encode_srgb8(h * r);
                }
            }
        });
    data
}

/// Frame, ticks, labels and titles: wavelengths along the bottom, angles along the left,
/// marks of the requested angles on the right.
fn draw_axes(rgb: &mut [u8], axes: &PlotAxes) {
    let bottom = TOP_PX + DATA_ROWS;
    let right = LEFT_PX + DATA_COLUMNS;
    fill(rgb, LEFT_PX - 1, TOP_PX, 1, DATA_ROWS + 1, AXIS_COLOUR);
    fill(rgb, LEFT_PX - 1, bottom, DATA_COLUMNS + 1, 1, AXIS_COLOUR);

    // Wavelength ticks, labelled in nm under the tick.
    let span_nm = axes.to_nm - axes.from_nm;
    let step_nm = tick_step(span_nm, DATA_COLUMNS, WAVELENGTH_TICK_MIN_PX);
    for value in ticks(axes.from_nm, axes.to_nm, step_nm) {
        let x = LEFT_PX + axes.column_of(value);
        fill(rgb, x, bottom + 1, 1, TICK_PX, AXIS_COLOUR);
        let label = format!("{value:.*}", decimals(step_nm));
        let left = x.saturating_sub(text_width(&label, LABEL_PX) / 2);
        let y = bottom + 1 + TICK_PX + LABEL_GAP_PX;
        text(rgb, left, y, &label);
    }

    // Angle ticks, labelled in degrees left of the tick.
    let step_deg = if axes.top_deg > 0.0 {
        tick_step(axes.top_deg, DATA_ROWS, ANGLE_TICK_MIN_PX)
    } else {
        1.0
    };
    for value in ticks(0.0, axes.top_deg, step_deg) {
        let y = TOP_PX + axes.row_of(value);
        fill(rgb, LEFT_PX - 1 - TICK_PX, y, TICK_PX, 1, AXIS_COLOUR);
        let label = format!("{value:.*}°", decimals(step_deg));
        let x = LEFT_PX - 1 - TICK_PX - LABEL_GAP_PX - text_width(&label, LABEL_PX);
        let top = y.saturating_sub(text_height(LABEL_PX) / 2);
        text(rgb, x, top, &label);
    }
    draw_titles(rgb, axes);

    // The rows of the printed table.
    for &angle in &axes.marked_deg {
        let y = TOP_PX + axes.row_of(angle);
        fill(rgb, right + 1, y, TICK_PX, 1, MARK_COLOUR);
    }
}

/// The axes' titles: the wavelength's under its labels, the angle's reading upwards along
/// the left edge, each centred on the data area.
fn draw_titles(rgb: &mut [u8], axes: &PlotAxes) {
    let mut canvas = Canvas {
        rgb,
        width: WIDTH_PX,
    };
    let title = "wavelength (nm)";
    let x = (LEFT_PX + DATA_COLUMNS / 2).saturating_sub(text_width(title, TITLE_PX) / 2);
    let y = HEIGHT_PX - EDGE_PX - text_height(TITLE_PX);
    canvas.text(x, y, title, TITLE_PX, LABEL_COLOUR);
    let title = axes.angle_title;
    let y = (TOP_PX + DATA_ROWS / 2).saturating_sub(text_width(title, TITLE_PX) / 2);
    canvas.text_upwards(EDGE_PX, y, title, TITLE_PX, LABEL_COLOUR);
}

/// Write a tick label with its top-left corner at `(x, y)`.
fn text(rgb: &mut [u8], x: usize, y: usize, label: &str) {
    Canvas {
        rgb,
        width: WIDTH_PX,
    }
    .text(x, y, label, LABEL_PX, LABEL_COLOUR);
}

/// The smallest step of 1, 2 or 5 × 10ᵏ that puts ticks at least `min_px` apart when `span`
/// covers `px` pixels (`span` > 0).
fn tick_step(span: f64, px: usize, min_px: f64) -> f64 {
    let least = span * min_px / px as f64;
    let decade = 10f64.powf(least.log10().floor());
    [1.0, 2.0, 5.0, 10.0]
        .into_iter()
        .map(|m| m * decade)
        .find(|&s| s >= least * (1.0 - 1e-9))
        .unwrap_or(10.0 * decade)
}

/// The multiples of `step` in `[from, to]`.
fn ticks(from: f64, to: f64, step: f64) -> Vec<f64> {
    let first = (from / step - 1e-9).ceil() as i64;
    let last = (to / step + 1e-9).floor() as i64;
    (first..=last).map(|k| k as f64 * step).collect()
}

/// Decimals that print every multiple of a 1, 2, 5 × 10ᵏ `step` exactly.
fn decimals(step: f64) -> usize {
    (-step.log10().floor()).max(0.0) as usize
}

/// Paint a `w × h` rectangle with top-left corner `(x, y)`, clipped to the image.
fn fill(rgb: &mut [u8], x: usize, y: usize, w: usize, h: usize, colour: [u8; 3]) {
    for py in y..(y + h).min(HEIGHT_PX) {
        for px in x..(x + w).min(WIDTH_PX) {
            let at = 3 * (py * WIDTH_PX + px);
            rgb[at..at + 3].copy_from_slice(&colour);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn tick_step_is_the_smallest_round_step_far_enough_apart() {
        // 400 nm over 800 px: 70 px is 35 nm, so 50 nm; 60° over 360 rows: 40 px is 6.7°.
        assert_eq!(tick_step(400.0, 800, 70.0), 50.0);
        assert_eq!(tick_step(60.0, 360, 40.0), 10.0);
        assert_eq!(tick_step(2.0, 800, 70.0), 0.2);
        assert_eq!(tick_step(1.0, 360, 40.0), 0.2);
    }

    #[test]
    fn ticks_are_the_multiples_inside_the_range() {
        assert_eq!(
            ticks(380.0, 780.0, 50.0),
            [400.0, 450.0, 500.0, 550.0, 600.0, 650.0, 700.0, 750.0]
        );
        assert_eq!(ticks(0.0, 60.0, 10.0).len(), 7);
        assert_eq!(ticks(0.0, 0.0, 1.0), [0.0]);
        assert_eq!(decimals(50.0), 0);
        assert_eq!(decimals(0.2), 1);
    }

    #[test]
    fn rows_and_columns_map_back_to_their_angles_and_wavelengths() {
        let axes = PlotAxes {
            from_nm: 380.0,
            to_nm: 780.0,
            top_deg: 60.0,
            cos_inside: |_, deg| deg.to_radians().cos(),
            marked_deg: vec![],
            angle_title: "angle",
        };
        assert_eq!(axes.row_of(0.0), DATA_ROWS - 1);
        assert_eq!(axes.row_of(60.0), 0);
        for row in [0, 17, DATA_ROWS - 1] {
            assert_eq!(axes.row_of(axes.row_angle_deg(row)), row);
        }
        // Column i spans 380 + 0.5 i … 380 + 0.5 (i + 1) nm.
        assert_eq!(axes.column_of(589.2), 418);
        assert_eq!(axes.column_of(300.0), 0);
    }
}

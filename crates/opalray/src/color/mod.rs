//! scratch colour for render development (replaced by the real stage).
#![allow(missing_docs)]
use crate::scene::{ColorConfig, Illuminant};
use crate::spectrum::{SpectralImage, WavelengthGrid};
use std::path::Path;
fn g(x: f64, mu: f64, s1: f64, s2: f64) -> f64 {
    let t = (x - mu) / if x < mu { s1 } else { s2 };
    (-0.5 * t * t).exp()
}
fn cmf(l: f64) -> [f64; 3] {
    [
        1.056 * g(l, 599.8, 37.9, 31.0) + 0.362 * g(l, 442.0, 16.0, 26.7)
            - 0.065 * g(l, 501.1, 20.4, 26.2),
        0.821 * g(l, 568.8, 46.9, 40.5) + 0.286 * g(l, 530.9, 16.3, 31.1),
        1.217 * g(l, 437.0, 11.8, 36.0) + 0.681 * g(l, 459.0, 26.0, 13.8),
    ]
}
pub struct ColorMatcher {
    w: Vec<[f32; 3]>,
}
impl ColorMatcher {
    pub fn new(grid: &WavelengthGrid) -> Self {
        Self {
            w: (0..grid.bins)
                .map(|b| {
                    let c = cmf(grid.center_nm(b));
                    [0, 1, 2].map(|k| (c[k] * grid.bin_width_nm()) as f32)
                })
                .collect(),
        }
    }
    pub fn to_xyz(&self, s: &[f32]) -> [f32; 3] {
        let mut o = [0.0; 3];
        for (v, w) in s.iter().zip(&self.w) {
            for k in 0..3 {
                o[k] += v * w[k];
            }
        }
        o
    }
}
pub fn illuminant_spectrum(_i: Illuminant, grid: &WavelengthGrid) -> Vec<f32> {
    let m = ColorMatcher::new(grid);
    let s = vec![1.0f32; grid.bins];
    let y = m.to_xyz(&s)[1];
    s.iter().map(|v| v / y).collect()
}
#[derive(Clone, Debug, PartialEq)]
pub struct RgbImage {
    pub width: usize,
    pub height: usize,
    pub data: Vec<[f32; 3]>,
}
pub fn to_rgb(image: &SpectralImage, color: &ColorConfig, _w: Illuminant) -> RgbImage {
    let m = ColorMatcher::new(&image.grid);
    let k = 2f32.powf(color.exposure_ev as f32);
    let data = (0..image.width * image.height)
        .map(|p| {
            let [x, y, z] = m.to_xyz(&image.data[p * image.grid.bins..(p + 1) * image.grid.bins]);
            [
                k * (3.2406 * x - 1.5372 * y - 0.4986 * z),
                k * (-0.9689 * x + 1.8758 * y + 0.0415 * z),
                k * (0.0557 * x - 0.2040 * y + 1.0570 * z),
            ]
        })
        .collect();
    RgbImage {
        width: image.width,
        height: image.height,
        data,
    }
}
pub fn to_display_rgb8(rgb: &RgbImage, _c: &ColorConfig) -> Vec<u8> {
    rgb.data
        .iter()
        .flat_map(|p| {
            let y = (0.2126 * p[0] + 0.7152 * p[1] + 0.0722 * p[2]).max(0.0);
            let m = p.iter().cloned().fold(0.0f32, f32::min);
            let s = if m < 0.0 { y / (y - m) } else { 1.0 };
            p.map(|c| {
                let c = (y + (c - y) * s).clamp(0.0, 1.0);
                ((if c <= 0.0031308 {
                    12.92 * c
                } else {
                    1.055 * c.powf(1.0 / 2.4) - 0.055
                }) * 255.0
                    + 0.5) as u8
            })
        })
        .collect()
}
pub fn write_png(path: &Path, rgb: &RgbImage, c: &ColorConfig) -> crate::Result<()> {
    crate::output::write_png_rgb8(
        path,
        rgb.width as u32,
        rgb.height as u32,
        &to_display_rgb8(rgb, c),
    )
}

//! Criterion benchmarks of the colour stage (paper §3.4) at the default image size:
//! a 640 × 480 spectral image of 40 bins → linear sRGB → 8-bit display codes.
//!
//! `cargo bench -p opalray --bench color`

use criterion::{black_box, Criterion};
use opalray::scene::{ColorConfig, Illuminant};
use opalray::spectrum::WavelengthGrid;
use opalray::{illuminant_spectrum, to_display_rgb8, to_rgb, SpectralImage};

const WIDTH: usize = 640;
const HEIGHT: usize = 480;

/// A spectral image of the default grid with varied, saturated and out-of-gamut spectra:
/// D65 times a narrow band whose peak moves across the image.
fn test_image() -> SpectralImage {
    let grid = WavelengthGrid::default();
    let light = illuminant_spectrum(Illuminant::D65, &grid);
    let mut image = SpectralImage::new(WIDTH, HEIGHT, grid);
    for (p, px) in image.data.chunks_exact_mut(grid.bins).enumerate() {
        let peak = (p % WIDTH) as f64 / WIDTH as f64 * 400.0 + 380.0;
        let gain = 0.5 + 2.0 * (p / WIDTH) as f64 / HEIGHT as f64;
        for (b, v) in px.iter_mut().enumerate() {
            let d = (grid.center_nm(b) - peak) / 15.0;
            *v = light[b] * (gain * (-d * d).exp() + 0.02) as f32;
        }
    }
    image
}

fn color(c: &mut Criterion) {
    let image = test_image();
    let config = ColorConfig::default();
    let rgb = to_rgb(&image, &config, Illuminant::D65);
    let mut group = c.benchmark_group("color");
    group.bench_function("to_rgb_640x480x40", |b| {
        b.iter(|| to_rgb(black_box(&image), &config, Illuminant::D65))
    });
    group.bench_function("to_display_rgb8_640x480", |b| {
        b.iter(|| to_display_rgb8(black_box(&rgb), &config))
    });
    group.bench_function("spectral_to_srgb8_640x480x40", |b| {
        b.iter(|| {
            to_display_rgb8(
                &to_rgb(black_box(&image), &config, Illuminant::D65),
                &config,
            )
        })
    });
    group.finish();
}

fn main() {
    let mut criterion = Criterion::default().configure_from_args();
    color(&mut criterion);
    criterion.final_summary();
}

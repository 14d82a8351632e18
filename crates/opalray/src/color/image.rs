//! Spectral image → linear RGB image → display codes (paper §3.4).

use rayon::prelude::*;

use super::cmf::{cmf_at, dot3};
use super::gamut::{encode_srgb, encode_srgb16, gamut_map, srgb8_tables};
use super::illuminant::illuminant_spectrum;
use super::space::{xyz_to_rgb_adapted, RgbSpace, SRGB};
use super::ColorMatcher;
use crate::scene::{ColorConfig, GamutMapping, Illuminant};
use crate::spectrum::{SpectralImage, WavelengthGrid};

/// A linear RGB image: `width × height` pixels `[r, g, b]`, rows top to bottom. Values are
/// scene-referred: 1 is the luminance of a perfect white reflector under the scene's light,
/// and they may be negative (out of gamut) or above 1 (brighter than white) until
/// [`to_display_rgb8`] maps them.
#[derive(Clone, Debug, PartialEq)]
pub struct RgbImage {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// `width × height` pixels, row-major, rows top to bottom.
    pub data: Vec<[f32; 3]>,
}

/// The spectrum → linear RGB operator of one grid, light and colour configuration: three rows
/// of per-bin weights, `rgb = Σ_b s_b · w_b`, the product of the bin-averaged CMFs, the
/// Bradford adaptation, the space's matrix and the exposure.
#[derive(Clone, Debug, PartialEq)]
pub struct SpectrumToRgb {
    rows: [Vec<f32>; 3],
}

impl SpectrumToRgb {
    /// The operator for spectra on `grid` lit by `light_white`, rendered in `color.space`
    /// with `color.exposure_ev`. The adaptation starts from the white of the light *as
    /// binned on this grid*, so a perfect white reflector gives exactly `(1, 1, 1)·2^ev` on
    /// any grid, however coarse.
    pub fn new(grid: &WavelengthGrid, color: &ColorConfig, light_white: Illuminant) -> Self {
        let matcher = ColorMatcher::new(grid);
        let light = illuminant_spectrum(light_white, grid);
        let binned_white = matcher.to_xyz(&light).map(f64::from);
        let space = RgbSpace::of(color.space);
        let m = xyz_to_rgb_adapted(space, binned_white) * 2f64.powf(color.exposure_ev);
        let [wx, wy, wz] = matcher.weights();
        let rows = [0, 1, 2].map(|r| {
            let row = m.row(r);
            (0..grid.bins)
                .map(|b| {
                    (row.x * wx[b] as f64 + row.y * wy[b] as f64 + row.z * wz[b] as f64) as f32
                })
                .collect()
        });
        SpectrumToRgb { rows }
    }

    /// Linear RGB of one bin-averaged spectrum.
    #[inline(always)]
    pub fn apply(&self, spectrum: &[f32]) -> [f32; 3] {
        let [r, g, b] = &self.rows;
        dot3(spectrum, r, g, b)
    }
}

/// Convert a spectral image to linear RGB: spectrum → XYZ (bin-averaged CIE 1931 2° CMFs) →
/// Bradford from the light's white to the space's white → linear RGB of `color.space`
/// (sRGB: IEC 61966-2-1, D65; paper: eq. 3, NTSC 1953, white C) → × 2^`exposure_ev`.
/// Rows are converted in parallel into one pre-sized buffer; the result does not depend on
/// the number of threads.
pub fn to_rgb(image: &SpectralImage, color: &ColorConfig, light_white: Illuminant) -> RgbImage {
    let op = SpectrumToRgb::new(&image.grid, color, light_white);
    let (width, bins) = (image.width, image.grid.bins);
    let mut data = vec![[0.0f32; 3]; image.width * image.height];
    if width > 0 && bins > 0 {
        data.par_chunks_mut(width)
            .zip(image.data.par_chunks(width * bins))
            .for_each(|(out, spectra)| {
                // In the copy compiled for the processor's vector level (`simd`): the same
                // sums, in eight lanes at once.
                crate::simd::widest(
                    #[inline(always)]
                    || {
                        for (px, s) in out.iter_mut().zip(spectra.chunks_exact(bins)) {
                            *px = op.apply(s);
                        }
                    },
                )
            });
    }
    RgbImage {
        width: image.width,
        height: image.height,
        data,
    }
}

/// Luminance weights of the configured space, as f32.
fn luminance(color: &ColorConfig) -> [f32; 3] {
    RgbSpace::of(color.space)
        .luminance_weights()
        .map(|w| w as f32)
}

/// Gamut-map (`color.gamut`) and sRGB-encode a linear RGB image into 8-bit RGB codes, 3 bytes
/// per pixel, rows top to bottom. Both spaces use the sRGB transfer curve (the paper's RGB
/// values are shown as a display shows them).
pub fn to_display_rgb8(rgb: &RgbImage, color: &ColorConfig) -> Vec<u8> {
    let tables = srgb8_tables();
    to_display(rgb, color, move |v| tables.encode(v))
}

/// As [`to_display_rgb8`], with 16-bit codes.
pub fn to_display_rgb16(rgb: &RgbImage, color: &ColorConfig) -> Vec<u16> {
    to_display(rgb, color, encode_srgb16)
}

fn to_display<T: Copy + Default + Send>(
    rgb: &RgbImage,
    color: &ColorConfig,
    encode: impl Fn(f32) -> T + Sync + Copy,
) -> Vec<T> {
    let (lum, mode) = (luminance(color), color.gamut);
    let mut out = vec![T::default(); rgb.data.len() * 3];
    if rgb.width > 0 {
        out.par_chunks_mut(rgb.width * 3)
            .zip(rgb.data.par_chunks(rgb.width))
            .for_each(|(codes, pixels)| {
                for (code, &px) in codes.chunks_exact_mut(3).zip(pixels) {
                    let [r, g, b] = gamut_map(px, lum, mode);
                    code.copy_from_slice(&[encode(r), encode(g), encode(b)]);
                }
            });
    }
    out
}

/// The linear sRGB colour of a monochromatic line at `wavelength_nm`, at the brightest level
/// that keeps its hue: hue-preserving gamut mapping, then scaled so that the largest component
/// is 1. Black outside 360–830 nm (where the CMF table ends). For plots: multiply by an
/// intensity in linear light, then encode with [`encode_srgb`].
pub fn wavelength_linear_srgb(wavelength_nm: f64) -> [f32; 3] {
    let xyz = glam::DVec3::from_array(cmf_at(wavelength_nm));
    if xyz.y <= 0.0 {
        return [0.0; 3];
    }
    let rgb = (SRGB.xyz_to_rgb() * (xyz / xyz.y))
        .to_array()
        .map(|v| v as f32);
    let lum = SRGB.luminance_weights().map(|w| w as f32);
    let mapped = gamut_map(rgb, lum, GamutMapping::HuePreserving);
    let max = mapped[0].max(mapped[1]).max(mapped[2]);
    if max > 0.0 {
        mapped.map(|v| v / max)
    } else {
        [0.0; 3]
    }
}

/// The display colour (sRGB-encoded, each in `[0, 1]`) of a monochromatic line at
/// `wavelength_nm`: [`wavelength_linear_srgb`] encoded. E.g. 470 nm is blue, 530 nm green,
/// 580 nm yellow, 650 nm red; black outside 360–830 nm.
pub fn wavelength_srgb(wavelength_nm: f64) -> [f32; 3] {
    wavelength_linear_srgb(wavelength_nm).map(encode_srgb)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::ColorSpaceChoice;

    fn white_image(light: Illuminant, grid: WavelengthGrid) -> SpectralImage {
        let spectrum = illuminant_spectrum(light, &grid);
        let mut image = SpectralImage::new(3, 2, grid);
        for px in image.data.chunks_exact_mut(grid.bins) {
            px.copy_from_slice(&spectrum);
        }
        image
    }

    #[test]
    fn white_reflector_is_rgb_one_for_every_light_space_and_grid() {
        for grid in [
            WavelengthGrid::default(),
            WavelengthGrid::new(400.0, 700.0, 6).unwrap(),
        ] {
            for light in [Illuminant::D65, Illuminant::A, Illuminant::C, Illuminant::E] {
                for space in [ColorSpaceChoice::Srgb, ColorSpaceChoice::Paper] {
                    let color = ColorConfig {
                        space,
                        ..ColorConfig::default()
                    };
                    let rgb = to_rgb(&white_image(light, grid), &color, light);
                    for px in &rgb.data {
                        for v in px {
                            assert!((v - 1.0).abs() < 1e-5, "{light:?} {space:?}: {px:?}");
                        }
                    }
                }
            }
        }
    }

    #[test]
    fn exposure_doubles_per_stop() {
        let grid = WavelengthGrid::default();
        let color = ColorConfig {
            exposure_ev: -1.0,
            ..ColorConfig::default()
        };
        let rgb = to_rgb(&white_image(Illuminant::D65, grid), &color, Illuminant::D65);
        assert!((rgb.data[0][1] - 0.5).abs() < 1e-5);
    }

    #[test]
    fn display_codes_of_white_black_and_grey() {
        let rgb = RgbImage {
            width: 3,
            height: 1,
            data: vec![[1.0; 3], [0.0; 3], [0.18; 3]],
        };
        let codes = to_display_rgb8(&rgb, &ColorConfig::default());
        // 0.18 linear encodes to 0.4614 (IEC 61966-2-1), code 118.
        assert_eq!(codes, [255, 255, 255, 0, 0, 0, 118, 118, 118]);
        let codes16 = to_display_rgb16(&rgb, &ColorConfig::default());
        assert_eq!(&codes16[..6], &[65535, 65535, 65535, 0, 0, 0]);
    }

    #[test]
    fn wavelength_colours_follow_the_spectrum() {
        let dominant = |w: f64| {
            let c = wavelength_linear_srgb(w);
            (0..3).max_by(|&a, &b| c[a].total_cmp(&c[b])).unwrap()
        };
        assert_eq!(dominant(450.0), 2);
        assert_eq!(dominant(530.0), 1);
        assert_eq!(dominant(650.0), 0);
        assert_eq!(wavelength_srgb(900.0), [0.0; 3]);
        // 578 nm is the unique yellow: red and green both high once encoded, no blue.
        let yellow = wavelength_srgb(578.0);
        assert!(
            yellow[0] > 0.7 && yellow[1] > 0.7 && yellow[2] < 0.05,
            "{yellow:?}"
        );
    }
}

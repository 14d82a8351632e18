//! Display encoding: gamut mapping of linear RGB into the unit cube, and the sRGB transfer
//! function (IEC 61966-2-1).
//!
//! Opal's flashes are near-spectral colours, outside every RGB gamut (a negative component),
//! and often brighter than the display (a component above 1). Clipping each channel turns them
//! towards white or shifts their hue. The hue-preserving mapping instead
//! 1. desaturates towards the colour's own luminance `Y` along the straight line to the grey
//!    `(Y, Y, Y)`, just far enough that the smallest component reaches 0 — luminance and
//!    dominant wavelength (the line through the white point in the chromaticity diagram) stay;
//! 2. scales all three components by the same factor when the largest exceeds 1 — the
//!    chromaticity stays, so a too-bright flash stays saturated rather than going white.
//!
//! The kept "hue" is the colorimetric one, the dominant wavelength. The perceived (OKLab) hue
//! of a mapped spectral line stays within 5° of the line's own from 500 to 700 nm, and moves
//! up to 25° towards blue near 470 nm. A 700 nm line becomes a deep red with a touch of blue
//! and 530 nm a full green with some blue: the lines from the white to those points leave
//! sRGB on its red–blue and green–blue edges.

use std::sync::OnceLock;

use crate::scene::GamutMapping;

/// Bring linear RGB into `[0, 1]³`. `luminance` are the space's weights (the Y row of its
/// RGB → XYZ matrix, see [`super::RgbSpace::luminance_weights`]). Non-finite components
/// count as 0; a colour with no positive luminance becomes black in the hue-preserving mode.
#[inline]
pub fn gamut_map(rgb: [f32; 3], luminance: [f32; 3], mode: GamutMapping) -> [f32; 3] {
    let c = rgb.map(|v| if v.is_finite() { v } else { 0.0 });
    match mode {
        GamutMapping::Clip => c.map(|v| v.clamp(0.0, 1.0)),
        GamutMapping::HuePreserving => {
            let y = c[0] * luminance[0] + c[1] * luminance[1] + c[2] * luminance[2];
            if y <= 0.0 {
                return [0.0; 3];
            }
            // (Plain comparisons: the components are finite, so no NaN-aware min/max.)
            let min = smaller(smaller(c[0], c[1]), c[2]);
            // 1. Desaturate towards (Y, Y, Y) until the smallest component is 0.
            let c = if min < 0.0 {
                let t = y / (y - min);
                c.map(|v| y + t * (v - y))
            } else {
                c
            };
            // 2. Scale down so the largest component is 1.
            let max = larger(larger(c[0], c[1]), c[2]);
            let c = if max > 1.0 {
                let k = 1.0 / max;
                c.map(|v| v * k)
            } else {
                c
            };
            c.map(|v| larger(smaller(v, 1.0), 0.0))
        }
    }
}

#[inline]
fn smaller(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}

#[inline]
fn larger(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

/// The sRGB transfer function (IEC 61966-2-1:1999 eq. 5): linear `[0, 1]` → encoded `[0, 1]`,
/// `12.92·v` below 0.0031308, `1.055·v^(1/2.4) − 0.055` above. Values outside `[0, 1]` are
/// clamped first.
#[inline]
pub fn encode_srgb(linear: f32) -> f32 {
    let v = linear.clamp(0.0, 1.0);
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// The inverse of [`encode_srgb`] (IEC 61966-2-1:1999 eq. 4): encoded `[0, 1]` → linear.
#[inline]
pub fn decode_srgb(encoded: f32) -> f32 {
    let v = encoded.clamp(0.0, 1.0);
    if v <= 0.040_45 {
        v / 12.92
    } else {
        ((v + 0.055) / 1.055).powf(2.4)
    }
}

/// Entries of the coarse table of [`encode_srgb8`]: in one step of 1/4096 in linear value the
/// encoded value moves by at most 12.92/4096 × 255 = 0.8 of a code (12.92 is the steepest
/// slope of the curve), so a step holds at most one code boundary and a single comparison
/// after the table look-up lands on the exact code.
const COARSE: usize = 4096;

/// Tables for exact, fast 8-bit sRGB encoding.
pub(crate) struct Srgb8 {
    /// `thresholds[k]`: the smallest linear value whose rounded 8-bit code is `k + 1`;
    /// `thresholds[255]` is +∞.
    thresholds: [f32; 256],
    /// The code of the start of each coarse step.
    coarse: [u8; COARSE],
}

pub(crate) fn srgb8_tables() -> &'static Srgb8 {
    static TABLES: OnceLock<Srgb8> = OnceLock::new();
    TABLES.get_or_init(|| {
        // thresholds[k]: step from a first guess to the first f32 whose exact code is k + 1.
        let thresholds = std::array::from_fn(|k| {
            if k == 255 {
                return f32::INFINITY;
            }
            let k = k as u8;
            let mut t = decode_srgb((k as f32 + 0.5) / 255.0);
            while exact_srgb8(t) > k {
                t = f32::from_bits(t.to_bits() - 1);
            }
            while exact_srgb8(t) <= k {
                t = f32::from_bits(t.to_bits() + 1);
            }
            t
        });
        let coarse = std::array::from_fn(|i| {
            let v = i as f32 / COARSE as f32;
            thresholds.partition_point(|&t| t <= v) as u8
        });
        Srgb8 { thresholds, coarse }
    })
}

/// The 8-bit code of a linear value, `round(255 · encode(v))` in f64: the reference that
/// [`encode_srgb8`] reproduces.
fn exact_srgb8(linear: f32) -> u8 {
    let v = linear.clamp(0.0, 1.0) as f64;
    let e = if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    };
    (e * 255.0 + 0.5).floor() as u8
}

/// Encode a linear value as an 8-bit sRGB code: `round(255 · encode(v))` evaluated in f64,
/// exactly, by a table look-up and one branch-free comparison (no `powf`). Clamps to
/// `[0, 1]`; NaN gives 0.
#[inline]
pub fn encode_srgb8(linear: f32) -> u8 {
    srgb8_tables().encode(linear)
}

impl Srgb8 {
    /// See [`encode_srgb8`].
    #[inline]
    pub(crate) fn encode(&self, linear: f32) -> u8 {
        let v = if linear.is_nan() {
            0.0
        } else {
            linear.clamp(0.0, 1.0)
        };
        let code = self.coarse[((v * COARSE as f32) as usize).min(COARSE - 1)];
        code + u8::from(v >= self.thresholds[code as usize])
    }
}

/// Encode a linear value as a 16-bit sRGB code, `round(65535 · encode(v))`. Clamps to `[0, 1]`.
#[inline]
pub fn encode_srgb16(linear: f32) -> u16 {
    (encode_srgb(linear) * 65535.0 + 0.5) as u16
}

#[cfg(test)]
mod tests {
    use super::*;

    const SRGB_Y: [f32; 3] = [0.2126, 0.7152, 0.0722];

    #[test]
    fn srgb_transfer_matches_iec_reference_points() {
        // IEC 61966-2-1: the linear segment ends at 0.0031308 ↦ 0.040449936 (12.92 × it);
        // middle grey 0.18 ↦ 1.055 · 0.18^(1/2.4) − 0.055 = 0.4613561 (by hand); 1 ↦ 1.
        assert!((encode_srgb(0.003_130_8) - 0.040_449_936).abs() < 1e-7);
        assert!((encode_srgb(0.18) - 0.461_356_13).abs() < 1e-6);
        assert!((encode_srgb(1.0) - 1.0).abs() < 1e-6);
        assert_eq!(encode_srgb(-1.0), 0.0);
        for i in 0..=100 {
            let v = i as f32 / 100.0;
            assert!((decode_srgb(encode_srgb(v)) - v).abs() < 1e-6);
        }
    }

    #[test]
    fn srgb8_equals_rounded_f64_encoding_everywhere() {
        let exact = exact_srgb8;
        for i in 0..=200_000 {
            let v = i as f32 / 200_000.0;
            assert_eq!(encode_srgb8(v), exact(v), "at {v}");
        }
        for &t in &srgb8_tables().thresholds[..255] {
            for v in [f32::from_bits(t.to_bits() - 1), t] {
                assert_eq!(encode_srgb8(v), exact(v), "at threshold {v}");
            }
        }
        assert_eq!(encode_srgb8(f32::NAN), 0);
        assert_eq!(encode_srgb8(7.0), 255);
    }

    #[test]
    fn hue_preserving_keeps_in_gamut_colours() {
        for c in [
            [0.2, 0.5, 0.9],
            [0.0, 0.0, 0.0],
            [1.0, 1.0, 1.0],
            [0.3, 0.0, 1.0],
        ] {
            assert_eq!(gamut_map(c, SRGB_Y, GamutMapping::HuePreserving), c);
        }
    }

    #[test]
    fn hue_preserving_keeps_luminance_when_desaturating() {
        let c = [-0.3, 0.6, 0.1];
        let y = |c: [f32; 3]| c[0] * SRGB_Y[0] + c[1] * SRGB_Y[1] + c[2] * SRGB_Y[2];
        let m = gamut_map(c, SRGB_Y, GamutMapping::HuePreserving);
        assert!((y(m) - y(c)).abs() < 1e-6);
        assert_eq!(m[0], 0.0);
    }

    #[test]
    fn hue_preserving_keeps_bright_flashes_saturated_where_clip_bleaches() {
        // A bright orange-red flash: clipping each channel yields (1, 1, 0.3), a pale yellow;
        // the hue-preserving map keeps the 4 : 2 : 0.3 ratios (saturation (max − min)/max).
        let flash = [4.0, 2.0, 0.3];
        let sat = |c: [f32; 3]| (c[0].max(c[1]).max(c[2]) - c[0].min(c[1]).min(c[2])) / c[0];
        let kept = gamut_map(flash, SRGB_Y, GamutMapping::HuePreserving);
        let clipped = gamut_map(flash, SRGB_Y, GamutMapping::Clip);
        assert_eq!(kept, [1.0, 0.5, 0.075]);
        assert_eq!(clipped, [1.0, 1.0, 0.3]);
        assert!(sat(kept) > 0.9 && sat(clipped) < 0.75);
    }

    #[test]
    fn non_finite_and_dark_colours_map_to_black() {
        let hp = GamutMapping::HuePreserving;
        assert_eq!(gamut_map([f32::NAN; 3], SRGB_Y, hp), [0.0; 3]);
        assert_eq!(gamut_map([-1.0, 0.1, 0.1], SRGB_Y, hp), [0.0; 3]);
    }
}

//! The colour of one sampled spectrum, every way it is usually quoted: XYZ, xy, linear and
//! encoded sRGB, 8-bit codes and hex (for `opalray color` and the per-angle colours of
//! `opalray spectrum`).

use glam::DVec3;

use super::exact::{emission_xyz, reflectance_xyz};
use super::gamut::{encode_srgb, encode_srgb8, gamut_map};
use super::illuminant::{chromaticity, white_point_xyz};
use super::space::{xyz_to_rgb_adapted, SRGB};
use crate::scene::{GamutMapping, Illuminant};

/// Slack of [`SpectrumColor::in_gamut`]: a white reflector sampled only over 380–780 nm
/// misses the CMF tails and lands 1e-5 from (1, 1, 1), which is still white.
pub const IN_GAMUT_TOLERANCE: f64 = 1e-4;

/// The colour of a spectrum in sRGB.
#[derive(Clone, Debug, PartialEq)]
pub struct SpectrumColor {
    /// Tristimulus values: for an emission `∫ S x̄ dλ` etc. in the input's units × nm; for a
    /// reflectance the luminance-factor scale (a perfect white reflector has Y = 1).
    pub xyz: [f64; 3],
    /// Chromaticity; `None` for black (X + Y + Z = 0).
    pub xy: Option<[f64; 2]>,
    /// Linear sRGB before gamut mapping (may be negative or above 1). An emission is taken
    /// at unit luminance (Y = 1); a reflectance is Bradford-adapted from its illuminant's white
    /// to D65.
    pub srgb_linear: [f64; 3],
    /// Whether `srgb_linear` lies in `[0, 1]³` (to [`IN_GAMUT_TOLERANCE`]).
    pub in_gamut: bool,
    /// sRGB-encoded values in `[0, 1]` after hue-preserving gamut mapping.
    pub srgb: [f64; 3],
    /// 8-bit codes of `srgb`.
    pub srgb8: [u8; 3],
}

impl SpectrumColor {
    /// The colour of light emitted with spectrum `samples` (`(wavelength_nm, value)`, sorted),
    /// shown at the brightest display level that keeps its chromaticity.
    pub fn of_emission(samples: &[(f64, f64)]) -> Self {
        let xyz = emission_xyz(samples);
        let unit = if xyz[1] > 0.0 {
            xyz.map(|v| v / xyz[1])
        } else {
            [0.0; 3]
        };
        Self::build(xyz, unit, white_point_xyz(Illuminant::D65))
    }

    /// The colour of a surface of reflectance `samples` (0–1, sorted by wavelength) lit by
    /// `illuminant`, white-balanced to D65: a perfect white reflector is `#ffffff`.
    pub fn of_reflectance(samples: &[(f64, f64)], illuminant: Illuminant) -> Self {
        let xyz = reflectance_xyz(samples, illuminant);
        Self::build(xyz, xyz, white_point_xyz(illuminant))
    }

    fn build(xyz: [f64; 3], shown_xyz: [f64; 3], light_white: [f64; 3]) -> Self {
        let srgb_linear =
            (xyz_to_rgb_adapted(&SRGB, light_white) * DVec3::from_array(shown_xyz)).to_array();
        let in_gamut = srgb_linear
            .iter()
            .all(|v| (-IN_GAMUT_TOLERANCE..=1.0 + IN_GAMUT_TOLERANCE).contains(v));
        let luminance = SRGB.luminance_weights().map(|w| w as f32);
        let mapped = gamut_map(
            srgb_linear.map(|v| v as f32),
            luminance,
            GamutMapping::HuePreserving,
        );
        SpectrumColor {
            xyz,
            xy: chromaticity(xyz),
            srgb_linear,
            in_gamut,
            srgb: mapped.map(|v| encode_srgb(v) as f64),
            srgb8: mapped.map(encode_srgb8),
        }
    }

    /// The 8-bit colour as `#rrggbb`.
    pub fn hex(&self) -> String {
        let [r, g, b] = self.srgb8;
        format!("#{r:02x}{g:02x}{b:02x}")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn white_reflector_is_ffffff_under_every_illuminant() {
        let white = [(300.0, 1.0), (900.0, 1.0)];
        for ill in [Illuminant::D65, Illuminant::A, Illuminant::C, Illuminant::E] {
            let c = SpectrumColor::of_reflectance(&white, ill);
            assert_eq!(c.hex(), "#ffffff", "{ill:?}: {c:?}");
        }
    }

    #[test]
    fn half_grey_reflector_is_middle_grey() {
        // Linear 0.5 encodes to 0.7354 (IEC 61966-2-1 curve), code 188 = #bc.
        let grey = [(300.0, 0.5), (900.0, 0.5)];
        assert_eq!(
            SpectrumColor::of_reflectance(&grey, Illuminant::D65).hex(),
            "#bcbcbc"
        );
    }

    #[test]
    fn green_line_is_out_of_gamut_and_keeps_its_dominant_wavelength() {
        // 530 nm lies at xy (0.1547, 0.8059) (CIE 1931 spectral locus), outside sRGB; the line
        // from D65 towards it leaves the gamut on the green–blue edge, so the mapped colour is
        // full green with some blue and no red.
        let line = [(529.9, 0.0), (530.0, 1.0), (530.1, 0.0)];
        let c = SpectrumColor::of_emission(&line);
        let xy = c.xy.unwrap();
        assert!((xy[0] - 0.1547).abs() < 2e-4 && (xy[1] - 0.8059).abs() < 2e-4);
        assert!(!c.in_gamut);
        assert_eq!(c.srgb8[..2], [0, 255]);
        assert!(c.srgb8[2] > 100 && c.srgb8[2] < 200, "{c:?}");
    }
}

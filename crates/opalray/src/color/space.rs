//! RGB colour spaces and chromatic adaptation: XYZ ↔ RGB matrices derived from the primaries
//! and the white (paper eq. 3 for the NTSC 1953 space; IEC 61966-2-1 for sRGB), and the
//! Bradford transform between two whites.

use glam::{DMat3, DVec3};

use super::illuminant::white_point_xyz;
use crate::scene::{ColorSpaceChoice, Illuminant};

/// An additive RGB space: three primaries and a white, in CIE 1931 xy chromaticities.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RgbSpace {
    /// Short name used in messages and file metadata.
    pub name: &'static str,
    /// Chromaticities `[x, y]` of the red, green and blue primaries.
    pub primaries_xy: [[f64; 2]; 3],
    /// The illuminant whose white RGB (1, 1, 1) is; its XYZ comes from the shipped tables.
    pub white: Illuminant,
}

/// sRGB (IEC 61966-2-1:1999 §5.1): primaries R (0.64, 0.33), G (0.30, 0.60), B (0.15, 0.06),
/// white D65. The default for files.
pub const SRGB: RgbSpace = RgbSpace {
    name: "sRGB",
    primaries_xy: [[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]],
    white: Illuminant::D65,
};

/// The paper's space (eq. 3): the NTSC 1953 primaries R (0.67, 0.33), G (0.21, 0.71),
/// B (0.14, 0.08) (FCC 1953 colour television standard), white C.
pub const PAPER_NTSC_1953: RgbSpace = RgbSpace {
    name: "NTSC 1953 (paper eq. 3)",
    primaries_xy: [[0.67, 0.33], [0.21, 0.71], [0.14, 0.08]],
    white: Illuminant::C,
};

/// The cone-like response matrix of the Bradford transform (Lam 1985; the linearised form
/// used by CIECAM97s and ICC v4, e.g. Hunt, *Measuring Colour*, 4th ed., §12.4).
const BRADFORD: [[f64; 3]; 3] = [
    [0.8951, 0.2664, -0.1614],
    [-0.7502, 1.7135, 0.0367],
    [0.0389, -0.0685, 1.0296],
];

/// A matrix from rows, for readability of the constants above.
fn from_rows(rows: [[f64; 3]; 3]) -> DMat3 {
    DMat3::from_cols_array_2d(&rows).transpose()
}

/// XYZ of a chromaticity at unit luminance.
fn xyz_of_xy([x, y]: [f64; 2]) -> DVec3 {
    DVec3::new(x / y, 1.0, (1.0 - x - y) / y)
}

impl RgbSpace {
    /// The space chosen in a scene's `color.space`.
    pub fn of(choice: ColorSpaceChoice) -> &'static RgbSpace {
        match choice {
            ColorSpaceChoice::Srgb => &SRGB,
            ColorSpaceChoice::Paper => &PAPER_NTSC_1953,
        }
    }

    /// The linear RGB → XYZ matrix: columns are the primaries' XYZ, each scaled so that
    /// RGB (1, 1, 1) is the white's XYZ with Y = 1 (SMPTE RP 177-1993 §3.3).
    pub fn rgb_to_xyz(&self) -> DMat3 {
        let primaries = DMat3::from_cols(
            xyz_of_xy(self.primaries_xy[0]),
            xyz_of_xy(self.primaries_xy[1]),
            xyz_of_xy(self.primaries_xy[2]),
        );
        let white = DVec3::from_array(white_point_xyz(self.white));
        let scale = primaries.inverse() * white;
        DMat3::from_cols(
            primaries.x_axis * scale.x,
            primaries.y_axis * scale.y,
            primaries.z_axis * scale.z,
        )
    }

    /// The XYZ → linear RGB matrix, the inverse of [`Self::rgb_to_xyz`].
    pub fn xyz_to_rgb(&self) -> DMat3 {
        self.rgb_to_xyz().inverse()
    }

    /// The luminance Y of linear RGB (1, 0, 0), (0, 1, 0), (0, 0, 1): the second row of
    /// [`Self::rgb_to_xyz`]. They sum to 1.
    pub fn luminance_weights(&self) -> [f64; 3] {
        self.rgb_to_xyz().row(1).to_array()
    }
}

/// The Bradford chromatic adaptation from a source white to a destination white (both XYZ,
/// any positive Y): `M⁻¹ · diag(ρ_dst / ρ_src) · M` in the Bradford cone space `M`. Maps the
/// source white to the destination white; the identity when the whites are equal.
pub fn bradford(source_white_xyz: [f64; 3], destination_white_xyz: [f64; 3]) -> DMat3 {
    let m = from_rows(BRADFORD);
    let src = m * DVec3::from_array(source_white_xyz);
    let dst = m * DVec3::from_array(destination_white_xyz);
    m.inverse() * DMat3::from_diagonal(dst / src) * m
}

/// The whole XYZ → RGB transform for light whose white is `light_white_xyz`: Bradford to the
/// space's white, then the space's matrix. A surface that reflects the light unchanged
/// (a white) comes out as RGB (Y, Y, Y).
pub fn xyz_to_rgb_adapted(space: &RgbSpace, light_white_xyz: [f64; 3]) -> DMat3 {
    space.xyz_to_rgb() * bradford(light_white_xyz, white_point_xyz(space.white))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: DMat3, b: [[f64; 3]; 3], tol: f64) -> bool {
        let b = from_rows(b);
        (0..3).all(|c| (a.col(c) - b.col(c)).abs().max_element() <= tol)
    }

    #[test]
    fn paper_matrix_matches_eq_3() {
        // Paper eq. (3), printed to 3 decimals.
        let eq3 = [
            [1.910, -0.532, -0.288],
            [-0.985, 1.999, -0.028],
            [0.058, -0.118, 0.898],
        ];
        let m = PAPER_NTSC_1953.xyz_to_rgb();
        assert!(close(m, eq3, 1.5e-3), "{m}");
    }

    #[test]
    fn srgb_matrix_matches_iec_61966_2_1() {
        // IEC 61966-2-1:1999 eq. (F.7)/(8): the XYZ → sRGB matrix, printed to 4 decimals.
        // Ours uses the white integrated from the D65 table (0.31273, 0.32902) rather than
        // the rounded (0.3127, 0.3290), which moves the entries by less than 3e-4.
        let iec = [
            [3.2406, -1.5372, -0.4986],
            [-0.9689, 1.8758, 0.0415],
            [0.0557, -0.2040, 1.0570],
        ];
        let m = SRGB.xyz_to_rgb();
        assert!(close(m, iec, 6e-4), "{m}");
    }

    #[test]
    fn luminance_weights_match_rec_709_and_sum_to_one() {
        // ITU-R BT.709 luma weights for the same primaries and D65: 0.2126, 0.7152, 0.0722.
        let w = SRGB.luminance_weights();
        for (a, b) in w.iter().zip([0.2126, 0.7152, 0.0722]) {
            assert!((a - b).abs() < 2e-4, "{w:?}");
        }
        assert!((w.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    }

    #[test]
    fn bradford_maps_one_white_to_the_other() {
        let whites = [Illuminant::D65, Illuminant::A, Illuminant::C, Illuminant::E];
        for src in whites {
            for dst in whites {
                let (s, d) = (white_point_xyz(src), white_point_xyz(dst));
                let mapped = bradford(s, d) * DVec3::from_array(s);
                assert!((mapped - DVec3::from_array(d)).abs().max_element() < 1e-12);
            }
        }
        let d65 = white_point_xyz(Illuminant::D65);
        assert!(close(
            bradford(d65, d65),
            [[1., 0., 0.], [0., 1., 0.], [0., 0., 1.]],
            1e-12
        ));
    }

    #[test]
    fn bradford_d65_to_d50_matches_lindbloom() {
        // Bradford D65 → D50 with the ASTM E308 whites, as tabulated by B. Lindbloom
        // (brucelindbloom.com, "Chromatic Adaptation"): 1.0478112 0.0228866 −0.0501270 /
        // 0.0295424 0.9904844 −0.0170491 / −0.0092345 0.0150436 0.7521316.
        let m = bradford([0.95047, 1.0, 1.08883], [0.96422, 1.0, 0.82521]);
        let expected = [
            [1.0478112, 0.0228866, -0.0501270],
            [0.0295424, 0.9904844, -0.0170491],
            [-0.0092345, 0.0150436, 0.7521316],
        ];
        assert!(close(m, expected, 2e-7), "{m}");
    }
}

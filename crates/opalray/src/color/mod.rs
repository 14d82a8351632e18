//! Colour stage (paper §3.4): spectral image → XYZ → linear RGB → display codes.
//!
//! Input: a [`SpectralImage`](crate::spectrum::SpectralImage) of bin-averaged radiance and the
//! scene's `color` section; output: an [`RgbImage`] of linear RGB, and from it 8/16-bit
//! sRGB-encoded codes for PNG (the writers are in [`crate::output`]).
//!
//! - XYZ with the CIE 1931 2° colour-matching functions (paper fig. 8), the official 1 nm
//!   table averaged exactly over each wavelength bin ([`ColorMatcher`]).
//! - Lights are CIE illuminants D65, A, C, E from the official tables, normalised to unit
//!   luminance ([`illuminant_spectrum`]).
//! - XYZ → RGB matrices derived from primaries and white ([`RgbSpace`]): sRGB
//!   (IEC 61966-2-1, D65) or the paper's eq. (3) (NTSC 1953 primaries, white C), with the
//!   Bradford adaptation from the light's white to the space's white.
//! - Hue-preserving gamut mapping and the sRGB transfer curve ([`gamut_map`], [`encode_srgb`]).

mod cmf;
mod csv;
mod exact;
mod gamut;
mod illuminant;
mod image;
mod report;
mod space;

pub use cmf::{cmf_at, ColorMatcher};
pub use csv::{parse_spectrum_csv, read_spectrum_csv};
pub use exact::{emission_xyz, reflectance_xyz};
pub use gamut::{decode_srgb, encode_srgb, encode_srgb16, encode_srgb8, gamut_map};
pub use illuminant::{chromaticity, illuminant_samples, illuminant_spectrum, white_point_xyz};
pub use image::{
    to_display_rgb16, to_display_rgb8, to_rgb, wavelength_linear_srgb, wavelength_srgb, RgbImage,
    SpectrumToRgb,
};
pub use report::{SpectrumColor, IN_GAMUT_TOLERANCE};
pub use space::{bradford, xyz_to_rgb_adapted, RgbSpace, PAPER_NTSC_1953, SRGB};

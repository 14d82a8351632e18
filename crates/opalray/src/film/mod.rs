//! The film: where a render's light becomes an image. Input what each camera sample adds to
//! its pixel → output the developed image, its noise and, on request, its denoised version.
//!
//! - [`sensor`]: the light × colour-matching table ([`SpectralSampler`]) through which every
//!   method turns a wavelength, or the light's white, into a pixel's XYZ and spectral bins,
//!   and the wavelength draws of a path's first reflection.
//! - `sums`: a sampled render's accumulation, each pixel's even and odd samples summed apart
//!   (and their squares), developed into means, half differences and variances.
//! - [`noise`]: the noise estimated from the even and odd halves.
//! - [`denoise`]: dual-buffer non-local means over the two halves of a [`FilmImage`].
//!
//! The path tracer accumulates on a `Film`; the stored method and the lobe integrator deposit
//! through the [`SpectralSampler`]; the denoiser reads a [`FilmImage`].

pub mod denoise;
pub mod noise;
pub mod sensor;
mod sums;

pub use noise::Noise;
pub(crate) use sensor::NO_BIN;
pub use sensor::{SpectralSampler, DEFAULT_WAVELENGTHS};
pub(crate) use sums::{Film, PixelSums};

/// A sampled image as its film developed it, borrowed: what the denoiser reads.
#[derive(Clone, Copy, Debug)]
pub struct FilmImage<'a> {
    /// CIE XYZ per pixel, row-major: the mean of its samples.
    pub xyz: &'a [[f32; 3]],
    /// Per pixel, the XYZ mean of its even samples minus that of its odd ones (empty below
    /// two samples per pixel).
    pub half_difference: &'a [[f32; 3]],
    /// Per pixel, the variance of its XYZ mean (infinite with one sample).
    pub variance: &'a [[f32; 3]],
    /// Samples per pixel.
    pub spp: u32,
}

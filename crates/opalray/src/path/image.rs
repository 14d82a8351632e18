//! The path integrator's image: what its film developed (`crate::film`), with the pixels that
//! see the stone and the light by class of path; the film's noise estimate and denoiser read it.

use glam::Mat3;

use super::orders::BraggOrders;
use crate::film::noise::{noise_of, Noise};
use crate::film::FilmImage;
use crate::spectrum::SpectralImage;

/// The path integrator's image.
pub struct PathImage {
    /// CIE XYZ per pixel, row-major (Y = 1: a white diffuser under the light): the mean of
    /// its samples.
    pub xyz: Vec<[f32; 3]>,
    /// The spectral image (bin averages).
    pub spectral: SpectralImage,
    /// Samples per pixel rendered.
    pub spp: u32,
    /// Passes rendered.
    pub passes: u32,
    /// Per pixel, the XYZ mean of its even samples minus that of its odd ones ([`crate::film::noise`]);
    /// empty below two samples per pixel.
    pub half_difference: Vec<[f32; 3]>,
    /// Per pixel, the variance of its XYZ mean: the samples' variance over `spp` (infinite
    /// with one sample).
    pub variance: Vec<[f32; 3]>,
    /// Per pixel, whether its centre sees the stone.
    pub on_stone: Vec<bool>,
    /// The share of the stone's luminance per class of path ([`super::orders`]); `None` where the
    /// image was not traced.
    pub bragg_orders: Option<BraggOrders>,
}

impl PathImage {
    /// The image's noise over the stone's pixels, the RGB channels through `xyz_to_rgb`
    /// (any linear map: a scale does not change relative noise); `None` below two samples
    /// per pixel.
    pub fn noise(&self, xyz_to_rgb: Mat3) -> Option<Noise> {
        noise_of(
            &self.xyz,
            &self.half_difference,
            &self.on_stone,
            self.spp,
            xyz_to_rgb,
        )
    }
}

impl<'a> From<&'a PathImage> for FilmImage<'a> {
    /// The developed parts of the image the denoiser reads.
    fn from(image: &'a PathImage) -> Self {
        FilmImage {
            xyz: &image.xyz,
            half_difference: &image.half_difference,
            variance: &image.variance,
            spp: image.spp,
        }
    }
}

//! A spectral image: `height × width` pixels of `bins` values each.

use super::WavelengthGrid;

/// A spectral image, pixel-major: value of bin `b` at pixel `(x, y)` is
/// `data[(y * width + x) * grid.bins + b]`. Values are radiance per nm averaged over the bin
/// (arbitrary but consistent units: a white diffuser lit by the scene's light at normal
/// incidence has the light's normalised spectrum).
#[derive(Clone, Debug, PartialEq)]
pub struct SpectralImage {
    /// Width in pixels.
    pub width: usize,
    /// Height in pixels.
    pub height: usize,
    /// Wavelength bins of every pixel.
    pub grid: WavelengthGrid,
    /// `width × height × bins` values, pixel-major, rows top to bottom.
    pub data: Vec<f32>,
}

impl SpectralImage {
    /// A black image.
    pub fn new(width: usize, height: usize, grid: WavelengthGrid) -> Self {
        SpectralImage {
            width,
            height,
            grid,
            data: super::zeroed(width * height * grid.bins),
        }
    }

    /// The spectrum of pixel `(x, y)`.
    pub fn pixel(&self, x: usize, y: usize) -> &[f32] {
        let b = self.grid.bins;
        let start = (y * self.width + x) * b;
        &self.data[start..start + b]
    }
}

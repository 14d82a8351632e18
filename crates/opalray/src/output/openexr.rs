//! OpenEXR output: linear RGB, and the spectral cube in the layout of Fichet, Pacanowski and
//! Wilkie, "An OpenEXR Layout for Spectral Images", JCGT 10(3), 2021.

use std::io::Cursor;
use std::path::Path;

use exr::prelude::{
    AnyChannel, AnyChannels, AttributeValue, Encoding, FlatSamples, Image, ImageAttributes, Layer,
    LayerAttributes, SpecificChannels, Text, Vec2, WritableImage,
};

use super::display::dimensions;
use super::provenance::{Provenance, SCENE_KEY};
use super::write_atomic;
use crate::color::RgbImage;
use crate::error::{Error, Result};
use crate::spectrum::SpectralImage;

/// Version of the spectral layout written (the `spectralLayoutVersion` header attribute the
/// layout requires, Fichet et al. 2021 §3).
const SPECTRAL_LAYOUT_VERSION: &str = "1.0";

/// Write a linear RGB image as a 32-bit float OpenEXR file (channels `R`, `G`, `B`, ZIP
/// compressed), atomically. Values are written unchanged: no gamut mapping, no transfer
/// curve. They are in the space chosen at [`to_rgb`](crate::color::to_rgb); OpenEXR readers
/// take a file without a `chromaticities` attribute as BT.709/sRGB primaries with a D65 white,
/// which is right for the default space.
///
/// `provenance`'s entries become text attributes of the header (UTF-8 bytes).
pub fn write_exr(path: &Path, rgb: &RgbImage, provenance: &Provenance) -> Result<()> {
    let (width, _) = dimensions(path, rgb)?;
    let width = width as usize;
    let channels = SpecificChannels::rgb(|Vec2(x, y): Vec2<usize>| {
        let [r, g, b] = rgb.data[y * width + x];
        (r, g, b)
    });
    let mut image = Image::from_channels((rgb.width, rgb.height), channels);
    tag(
        &mut image.attributes,
        &mut image.layer_data.attributes,
        provenance,
    );
    let mut bytes = Cursor::new(Vec::new());
    let written = image.write().to_buffered(&mut bytes);
    store(path, written, bytes)
}

/// The channel name of spectral bin centre `wavelength_nm` in the emissive layout of Fichet et
/// al. (2021): Stokes component `S0`, a `.` (the OpenEXR layer separator), the wavelength
/// with a decimal *comma* (a dot would start a new layer) and six decimals as the reference
/// implementation writes them (C++ `std::to_string`), then the unit: `S0.385,000000nm`.
pub fn spectral_channel_name(wavelength_nm: f64) -> String {
    format!("S0.{}nm", format!("{wavelength_nm:.6}").replace('.', ","))
}

/// Write a spectral image as OpenEXR in the spectral layout of Fichet et al. (2021): one
/// 32-bit float channel per bin named by its centre wavelength (see
/// [`spectral_channel_name`]), e.g. `S0.385,000000nm` … `S0.775,000000nm` for the default
/// grid, and the header attribute `spectralLayoutVersion = "1.0"`. Values are the image's
/// bin-averaged spectral radiance per nm in opalray's relative units, normalised so that
/// `∫ S(λ) ȳ(λ) dλ` over the range is the pixel's luminance Y (Y = 1: a white diffuser under
/// the light, which under D65 reads about 0.0097 per nm at 555 nm, not 1), so no
/// `emissiveUnits` attribute is written. `provenance`'s entries become text attributes.
/// Written atomically.
pub fn write_spectral_exr(
    path: &Path,
    image: &SpectralImage,
    provenance: &Provenance,
) -> Result<()> {
    let (width, height, bins) = (image.width, image.height, image.grid.bins);
    if width == 0 || height == 0 || bins == 0 || image.data.len() != width * height * bins {
        return Err(Error::Encode {
            path: path.to_path_buf(),
            message: format!(
                "spectral image is {width} × {height} × {bins} with {} values; need a \
                 non-empty image with width × height × bins values",
                image.data.len()
            ),
        });
    }
    let channels = (0..bins)
        .map(|b| {
            let plane: Vec<f32> = image.data.iter().skip(b).step_by(bins).copied().collect();
            AnyChannel::new(
                spectral_channel_name(image.grid.center_nm(b)).as_str(),
                FlatSamples::F32(plane),
            )
        })
        .collect();
    // The header attribute lives in the layer's attributes: a single-layer file has one header.
    let mut attributes = LayerAttributes::default();
    attributes.other.insert(
        Text::from("spectralLayoutVersion"),
        AttributeValue::Text(Text::from(SPECTRAL_LAYOUT_VERSION)),
    );
    let layer = Layer::new(
        (width, height),
        attributes,
        Encoding::SMALL_LOSSLESS,
        AnyChannels::sort(channels),
    );
    let mut image = Image::from_layer(layer);
    tag(
        &mut image.attributes,
        &mut image.layer_data.attributes,
        provenance,
    );
    let mut bytes = Cursor::new(Vec::new());
    let written = image.write().to_buffered(&mut bytes);
    store(path, written, bytes)
}

/// Record `provenance` in a header: its `Software` entry as the standard `software`
/// attribute, the rest as the one text attribute `opalray.scene` (UTF-8 bytes: OpenEXR text
/// attributes are byte strings), the scene's TOML after a comment line holding the other
/// entries. One attribute, because the `exr` crate writes a header's other attributes in
/// its hash map's order, which differs from run to run: one per map keeps the bytes alike.
fn tag(image: &mut ImageAttributes, layer: &mut LayerAttributes, provenance: &Provenance) {
    if let Some(software) = provenance.get("Software") {
        layer.software_name = Some(Text::from_slice_unchecked(software.as_bytes()));
    }
    if let Some(text) = provenance.scene_with_summary() {
        image.other.insert(
            Text::from(SCENE_KEY),
            AttributeValue::Text(Text::from_slice_unchecked(text.as_bytes())),
        );
    }
}

/// Write the bytes the encoder produced in memory (it needs to seek) to `path`, atomically.
fn store(path: &Path, written: exr::error::UnitResult, bytes: Cursor<Vec<u8>>) -> Result<()> {
    written.map_err(|e| Error::Encode {
        path: path.to_path_buf(),
        message: e.to_string(),
    })?;
    write_atomic(path, |w| w.write_all(bytes.get_ref()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::WavelengthGrid;
    use exr::prelude::{read, ReadChannels, ReadLayers};

    type Channels = Vec<(String, Vec<f32>)>;
    type Attributes = Vec<(String, AttributeValue)>;

    /// Every channel of the first layer, by name, and its header's custom attributes.
    fn read_back(path: &Path) -> (Channels, Attributes) {
        let image = read()
            .no_deep_data()
            .largest_resolution_level()
            .all_channels()
            .first_valid_layer()
            .all_attributes()
            .from_file(path)
            .unwrap();
        let channels = image
            .layer_data
            .channel_data
            .list
            .iter()
            .map(|c| (c.name.to_string(), c.sample_data.values_as_f32().collect()))
            .collect();
        let attributes = image
            .layer_data
            .attributes
            .other
            .iter()
            .map(|(k, v)| (k.to_string(), v.clone()))
            .collect();
        (channels, attributes)
    }

    #[test]
    fn exr_round_trips_linear_values_exactly() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.exr");
        let rgb = RgbImage {
            width: 3,
            height: 2,
            data: vec![
                [0.0, 1.0, 2.5],
                [-0.25, 1e-6, 100.0],
                [0.5, 0.25, 0.125],
                [3.0, 2.0, 1.0],
                [0.1, 0.2, 0.3],
                [7.0, 8.0, 9.0],
            ],
        };
        write_exr(&path, &rgb, &Provenance::default()).unwrap();
        let (channels, _) = read_back(&path);
        let names: Vec<&str> = channels.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(names, ["B", "G", "R"]);
        for (c, (_, values)) in [2, 1, 0].into_iter().zip(&channels) {
            let expected: Vec<f32> = rgb.data.iter().map(|px| px[c]).collect();
            assert_eq!(values, &expected);
        }
    }

    #[test]
    fn spectral_channel_names_follow_fichet_2021() {
        // Fichet et al. 2021 §3.1 and their reference writer: "S0.<value with comma>nm".
        assert_eq!(spectral_channel_name(385.0), "S0.385,000000nm");
        assert_eq!(spectral_channel_name(392.5), "S0.392,500000nm");
    }

    #[test]
    fn spectral_exr_round_trips_every_bin() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.exr");
        let grid = WavelengthGrid::new(400.0, 700.0, 3).unwrap();
        let mut image = SpectralImage::new(2, 2, grid);
        for (i, v) in image.data.iter_mut().enumerate() {
            *v = i as f32 * 0.5;
        }
        write_spectral_exr(&path, &image, &Provenance::default()).unwrap();
        let (channels, attributes) = read_back(&path);
        let names: Vec<&str> = channels.iter().map(|(n, _)| n.as_str()).collect();
        assert_eq!(
            names,
            ["S0.450,000000nm", "S0.550,000000nm", "S0.650,000000nm"]
        );
        for (b, (_, values)) in channels.iter().enumerate() {
            let expected: Vec<f32> = (0..4).map(|p| image.data[p * 3 + b]).collect();
            assert_eq!(values, &expected);
        }
        assert!(attributes
            .iter()
            .any(|(k, v)| k == "spectralLayoutVersion"
                && *v == AttributeValue::Text(Text::from("1.0"))));
    }

    #[test]
    fn spectral_exr_refuses_an_empty_image() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("s.exr");
        let image = SpectralImage::new(0, 4, WavelengthGrid::default());
        assert!(write_spectral_exr(&path, &image, &Provenance::default()).is_err());
        assert!(!path.exists());
    }
}

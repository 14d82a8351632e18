//! The OpenEXR map reader: the R, G, B channels of a single-part file's first layer, through
//! the `exr` crate, the size read from the header before any pixel is allocated.

use std::path::Path;

use super::{check_size, luminance, LuminanceMap};

/// Read the R, G, B channels (half or float; alpha and other channels ignored) of an
/// OpenEXR file's first layer.
pub fn read_exr(path: &Path) -> Result<LuminanceMap, String> {
    use exr::prelude::{read, ReadChannels, ReadLayers};
    // The header first: the size is checked before the pixels are allocated.
    let (width, height) = exr_size(path)?;
    check_size(width, height)?;
    let image = read()
        .no_deep_data()
        .largest_resolution_level()
        .rgb_channels(
            |size, _| LuminanceMap {
                width: size.width(),
                height: size.height(),
                luminance: vec![0.0; size.width() * size.height()],
            },
            |map: &mut LuminanceMap, pos, (r, g, b): (f32, f32, f32)| {
                map.luminance[pos.y() * map.width + pos.x()] = luminance([r, g, b]);
            },
        )
        .first_valid_layer()
        .all_attributes()
        .from_file(path)
        .map_err(|e| {
            format!(
                "cannot read its R, G, B channels: {}; give an RGB or RGBA OpenEXR map",
                one_line(&e.to_string())
            )
        })?;
    Ok(image.layer_data.channel_data.pixels)
}

/// The size of a single-part OpenEXR file's layer, from its header. A multi-part file is
/// refused: its parts may differ in size, and the one read must be the one checked.
pub(super) fn exr_size(path: &Path) -> Result<(usize, usize), String> {
    let meta = exr::meta::MetaData::read_from_file(path, false)
        .map_err(|e| format!("not a readable OpenEXR file: {}", one_line(&e.to_string())))?;
    match meta.headers.as_slice() {
        [] => Err("an OpenEXR file without a layer".into()),
        [header] if header.deep => {
            Err("a deep OpenEXR file; give a flat RGB or RGBA OpenEXR map".into())
        }
        [header] => Ok((header.layer_size.width(), header.layer_size.height())),
        parts => Err(format!(
            "a multi-part OpenEXR file ({} parts); save the map as a single-part RGB file",
            parts.len()
        )),
    }
}

fn one_line(message: &str) -> String {
    message.split_whitespace().collect::<Vec<_>>().join(" ")
}

#[cfg(test)]
mod tests {
    use super::super::read_map;
    use super::super::tests::pattern;
    use super::super::{luminance, map_size};

    #[test]
    fn exr_round_trips_through_the_exr_writer() {
        let dir = tempfile::tempdir().unwrap();
        for (name, alpha) in [("rgb.exr", false), ("rgba.exr", true)] {
            let path = dir.path().join(name);
            let (w, h) = (24, 12);
            let rgb = pattern(w, h);
            if alpha {
                // Half floats: 11 bits of mantissa.
                exr::prelude::write_rgba_file(&path, w, h, |x, y| {
                    let c = rgb[y * w + x];
                    (
                        exr::prelude::f16::from_f32(c[0]),
                        exr::prelude::f16::from_f32(c[1]),
                        exr::prelude::f16::from_f32(c[2]),
                        exr::prelude::f16::from_f32(1.0),
                    )
                })
                .unwrap();
            } else {
                exr::prelude::write_rgb_file(&path, w, h, |x, y| {
                    let c = rgb[y * w + x];
                    (c[0], c[1], c[2])
                })
                .unwrap();
            }
            let map = read_map(&path).unwrap();
            assert_eq!((map.width, map.height), (w, h));
            let tolerance = if alpha { 1e-3 } else { 1e-6 };
            for (&c, &y) in rgb.iter().zip(&map.luminance) {
                let expected = luminance(c);
                assert!(
                    (y - expected).abs() <= tolerance * expected.max(1e-3),
                    "{name}: {y} vs {expected}"
                );
            }
        }
    }

    #[test]
    fn a_multi_part_exr_is_refused() {
        use exr::prelude::*;
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("parts.exr");
        // A small first part without colour, then a larger RGB part: the part read would not
        // be the part checked.
        let depth = AnyChannels::sort(SmallVec::from_vec(vec![AnyChannel::new(
            "Z",
            FlatSamples::F32(vec![0.0; 8]),
        )]));
        let small = Layer::new(
            (4, 2),
            LayerAttributes::named("depth"),
            Encoding::UNCOMPRESSED,
            depth,
        );
        let big = Layer::new(
            (32, 16),
            LayerAttributes::named("colour"),
            Encoding::UNCOMPRESSED,
            SpecificChannels::rgb(|_pos: Vec2<usize>| (1.0f32, 1.0f32, 1.0f32)),
        );
        Image::empty(ImageAttributes::new(IntegerBounds::from_dimensions((
            32, 16,
        ))))
        .with_layer(small)
        .with_layer(big)
        .write()
        .to_file(&path)
        .unwrap();
        let err = read_map(&path).unwrap_err();
        assert!(err.contains("multi-part"), "{err}");
        assert!(map_size(&path).unwrap_err().contains("multi-part"));
    }
}

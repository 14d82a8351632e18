//! The orientation map of the paper's fig. 9: one z slice of a [`Structure`], each cluster
//! coloured by its (111) plane normal `n` as `(R, G, B) = (|nₓ|, |n_y|, |n_z|)`, voids dark
//! grey, cells outside the stone transparent. The absolute values make `n` and `−n` (the same
//! planes) one colour. Rows run from `+y` at the top to `−y` at the bottom, `+x` to the right
//! (the stone seen from `+z`); each cell becomes a `scale × scale` block of pixels.

use super::{Cell, Structure};
use crate::error::{Error, Result};

/// Colour of a void cell (RGBA): opaque dark grey.
pub const VOID_RGBA: [u8; 4] = [48, 48, 48, 255];

/// Colour of a cell outside the stone (RGBA): fully transparent.
pub const OUTSIDE_RGBA: [u8; 4] = [0, 0, 0, 0];

/// Largest pixels per cell edge accepted by [`orientation_map`].
pub const MAX_SCALE: u32 = 64;

/// Largest image accepted by [`orientation_map`]: 2²⁸ pixels (1 GiB of RGBA).
pub const MAX_PIXELS: usize = 1 << 28;

/// An 8-bit RGBA image, rows top to bottom.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct OrientationMap {
    /// Width in pixels: `nx · scale`.
    pub width: u32,
    /// Height in pixels: `ny · scale`.
    pub height: u32,
    /// `width · height · 4` bytes, RGBA, unassociated alpha.
    pub rgba: Vec<u8>,
}

/// Colour of cell `index`: see the module documentation.
fn cell_rgba(structure: &Structure, index: usize) -> [u8; 4] {
    match structure.cells[index] {
        Cell::Outside => OUTSIDE_RGBA,
        Cell::Void => VOID_RGBA,
        Cell::Cluster => {
            let n = structure.normal(index).abs();
            let channel = |c: f32| (c.clamp(0.0, 1.0) * 255.0).round() as u8;
            [channel(n.x), channel(n.y), channel(n.z), 255]
        }
    }
}

/// Draw slice `slice_z` (cell index along z, `0 .. nz`) of `structure` with `scale` pixels
/// per cell edge (`1 ..= 64`; 6 makes the paper's grid 600 × 450 pixels).
/// Errors name `slice_z` or `scale` when out of range.
pub fn orientation_map(
    structure: &Structure,
    slice_z: usize,
    scale: u32,
) -> Result<OrientationMap> {
    let [nx, ny, nz] = structure.grid;
    if slice_z >= nz {
        return Err(Error::argument(
            "slice_z",
            format!(
                "must be a cell index in 0..{nz}, got {slice_z}; the middle is {}",
                nz / 2
            ),
        ));
    }
    if !(1..=MAX_SCALE).contains(&scale) {
        return Err(Error::argument(
            "scale",
            format!("must be in 1..={MAX_SCALE} pixels per cell, got {scale}; try 6"),
        ));
    }
    let s = scale as usize;
    let (width, height) = (nx * s, ny * s);
    if width * height > MAX_PIXELS {
        return Err(Error::argument(
            "scale",
            format!(
                "{width} × {height} pixels is more than the limit of {MAX_PIXELS}; \
                 use a smaller scale"
            ),
        ));
    }
    let mut rgba = Vec::with_capacity(width * height * 4);
    let mut line = Vec::with_capacity(width * 4);
    for y in (0..ny).rev() {
        line.clear();
        for x in 0..nx {
            let pixel = cell_rgba(structure, structure.index(x, y, slice_z));
            for _ in 0..s {
                line.extend_from_slice(&pixel);
            }
        }
        for _ in 0..s {
            rgba.extend_from_slice(&line);
        }
    }
    // Both sides are at most MAX_PIXELS, well inside u32.
    Ok(OrientationMap {
        width: width as u32,
        height: height as u32,
        rgba,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::structure::StructureStats;
    use glam::Quat;

    /// A 2 × 2 × 1 structure: outside, void, and two clusters with known normals.
    fn tiny() -> Structure {
        // Rotating (1,1,1)/√3 onto +z gives the colour (0, 0, 255).
        let to_z = Quat::from_rotation_arc(crate::structure::AXIS_111, glam::Vec3::Z);
        Structure {
            grid: [2, 2, 1],
            semi_axes_mm: [1.0, 1.0, 1.0],
            cells: vec![Cell::Outside, Cell::Void, Cell::Cluster, Cell::Cluster],
            orientations: vec![Quat::IDENTITY, Quat::IDENTITY, to_z, Quat::IDENTITY],
            stats: StructureStats {
                inside_cells: 3,
                clusters: 2,
                voids: 1,
                void_ratio: 1.0 / 3.0,
                seeds_placed: 0,
                mean_radius_cells: 0.0,
            },
        }
    }

    #[test]
    fn map_colours_cells_by_normal_with_plus_y_on_top() {
        let map = orientation_map(&tiny(), 0, 1).unwrap();
        assert_eq!((map.width, map.height), (2, 2));
        // 255/√3 = 147.2 for the identity's normal (1,1,1)/√3.
        let top = [0, 0, 255, 255, 147, 147, 147, 255]; // y = 1: cells 2, 3
        let bottom = [0, 0, 0, 0, 48, 48, 48, 255]; // y = 0: cells 0, 1
        assert_eq!(&map.rgba[..8], &top);
        assert_eq!(&map.rgba[8..], &bottom);
    }

    #[test]
    fn map_scales_each_cell_to_a_block() {
        let small = orientation_map(&tiny(), 0, 1).unwrap();
        let big = orientation_map(&tiny(), 0, 3).unwrap();
        assert_eq!((big.width, big.height), (6, 6));
        for py in 0..6 {
            for px in 0..6 {
                let b = &big.rgba[(py * 6 + px) * 4..][..4];
                let s = &small.rgba[((py / 3) * 2 + px / 3) * 4..][..4];
                assert_eq!(b, s, "pixel ({px}, {py})");
            }
        }
    }

    #[test]
    fn map_refuses_bad_slice_and_scale() {
        let err = orientation_map(&tiny(), 1, 6).unwrap_err().to_string();
        assert!(err.contains("slice_z") && err.contains("0..1"), "{err}");
        let err = orientation_map(&tiny(), 0, 0).unwrap_err().to_string();
        assert!(err.contains("scale"), "{err}");
    }
}

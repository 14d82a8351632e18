//! `opalray structure` for the stone methods (path, stored, lobe): a slice through the stone
//! the renderers read ([`Stone`]: the gem presets' grains or settled plates), not the paper's
//! grown cells. Each domain is coloured by its (111) plane normal n as (|nx|, |ny|, |nz|) →
//! (R, G, B), as the paper's fig. 9 colours clusters; where two domains meet the outline is
//! drawn black; potch (and a doublet's or triplet's cap) is dark grey, outside transparent.

use glam::Vec3;
use opalray::optics::FamilyKind;
use opalray::stone::Stone;
use rayon::prelude::*;

/// Id of a point in potch (inside the stone, in no domain).
const POTCH: i32 = -1;
/// Id of a point outside the stone.
const OUTSIDE: i32 = -2;
/// Colour of potch: the paper's void colour (`structure::map::VOID_RGBA`).
const POTCH_RGBA: [u8; 4] = opalray::structure::map::VOID_RGBA;
/// Colour of an outline between two domains.
const OUTLINE_RGBA: [u8; 4] = [0, 0, 0, 255];
/// Columns and rows sampled at each level to find the level that cuts the most domain.
const PROBE: (usize, usize) = (64, 48);

/// One drawn slice: RGBA rows top (+y) to bottom, and what it cut.
pub struct StoneSlice {
    /// Image width, pixels (x from −a to a).
    pub width: usize,
    /// Image height, pixels (y from b down to −b).
    pub height: usize,
    /// RGBA8 pixels, row-major.
    pub rgba: Vec<u8>,
    /// Domains the slice cuts.
    pub domains_cut: usize,
    /// Share of the stone's pixels in a domain (the rest potch), 0 … 1.
    pub domain_share: f64,
}

/// The height of slice `k` of `levels` across the stone, mm: level centres from −c to c.
pub fn level_mm(stone: &Stone, k: usize, levels: usize) -> f32 {
    let c = stone.shape.semi_axes().z;
    -c + (k as f32 + 0.5) * 2.0 * c / levels as f32
}

/// The domain id at every pixel centre of the plane z = `z_mm`, `width` × `height` pixels over
/// the stone's box, rows from +y down: the domain's index, [`POTCH`] or [`OUTSIDE`].
fn ids(stone: &Stone, z_mm: f32, width: usize, height: usize) -> Vec<i32> {
    let half = stone.shape.semi_axes();
    (0..height)
        .into_par_iter()
        .flat_map_iter(|row| {
            let y = half.y - (row as f32 + 0.5) * 2.0 * half.y / height as f32;
            (0..width).map(move |col| {
                let x = -half.x + (col as f32 + 0.5) * 2.0 * half.x / width as f32;
                let p = Vec3::new(x, y, z_mm);
                match stone.domain_at(p) {
                    // Fewer than 2³¹ domains: `MAX_GRAINS` is 250 000.
                    Some(d) => d as i32,
                    None if stone.shape.contains(p) => POTCH,
                    None => OUTSIDE,
                }
            })
        })
        .collect()
}

/// The level (of `levels` across the stone's height) whose slice cuts the most domain, the
/// highest of equals: the play of colour's layer of a gem (a black opal's colour bar).
pub fn busiest_level(stone: &Stone, levels: usize) -> usize {
    let (w, h) = PROBE;
    let mut best = (0, 0);
    for k in 0..levels {
        let inside = ids(stone, level_mm(stone, k, levels), w, h)
            .iter()
            .filter(|&&id| id >= 0)
            .count();
        if inside >= best.1 {
            best = (k, inside);
        }
    }
    best.0
}

/// Draw the slice z = `z_mm` of `stone` at `width` × `height` pixels.
pub fn draw(stone: &Stone, z_mm: f32, width: usize, height: usize) -> StoneSlice {
    let ids = ids(stone, z_mm, width, height);
    let n111 = FamilyKind::F111.normals()[0].normalize();
    let colour = |id: i32| -> [u8; 4] {
        match id {
            OUTSIDE => [0, 0, 0, 0],
            POTCH => POTCH_RGBA,
            d => {
                let n = (stone.domains[d as usize].orientation * n111)
                    .normalize()
                    .abs();
                let channel = |c: f32| (c.clamp(0.0, 1.0) * 255.0).round() as u8;
                [channel(n.x), channel(n.y), channel(n.z), 255]
            }
        }
    };
    // A domain pixel whose right or lower neighbour is another domain is on an outline.
    let outline = |i: usize| {
        let (row, col) = (i / width, i % width);
        let other = |j: usize| ids[j] >= 0 && ids[j] != ids[i];
        ids[i] >= 0 && ((col + 1 < width && other(i + 1)) || (row + 1 < height && other(i + width)))
    };
    let mut rgba = Vec::with_capacity(width * height * 4);
    for (i, &id) in ids.iter().enumerate() {
        rgba.extend_from_slice(&if outline(i) { OUTLINE_RGBA } else { colour(id) });
    }
    let mut cut: Vec<i32> = ids.iter().copied().filter(|&id| id >= 0).collect();
    let in_domains = cut.len();
    cut.sort_unstable();
    cut.dedup();
    let in_stone = ids.iter().filter(|&&id| id != OUTSIDE).count();
    StoneSlice {
        width,
        height,
        rgba,
        domains_cut: cut.len(),
        domain_share: in_domains as f64 / in_stone.max(1) as f64,
    }
}

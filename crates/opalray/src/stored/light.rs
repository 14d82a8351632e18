//! The stored method's light pass (the paper's first pass, on the stone model): the light
//! arriving straight from the scene's light at the centre of every grid cell of the stone.
//!
//! Input: a [`Stone`] and the light → output: a [`StoredLight`]. Per cell centre inside the
//! stone: the refracted direction towards the light and the irradiance across the beam
//! ([`Stone::light_entry`]: the one refracted path through the surface), times the potch's and
//! the haze's transmittance on the way, and the Bragg lines (their `1 − R` notches) of the
//! domains crossed on the way in ([`Stone::towards_light`]), each tagged with its domain.
//! Cells are computed in parallel by rows into an ordered list: the result does not depend on
//! the number of threads.
//!
//! A lookup ([`StoredLight::at`]) interpolates the direction and the irradiance trilinearly
//! between the eight centres about the point (those inside the stone), so that the stored
//! light has no steps at cell faces; the notches are those of the nearest centre. A point
//! with no centre about it inside (the stone's outermost shell) is solved exactly.

use glam::Vec3;
use rayon::prelude::*;

use crate::geometry::LightSource;
use crate::optics::BraggLine;
use crate::stone::{ActiveLine, Hint, PathToLight, Span, Stone};

/// A grid point outside the stone.
const OUTSIDE: u32 = u32::MAX;

/// A Bragg line crossed on the way in, kept in single precision, with its domain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Notch {
    /// The domain whose planes it belongs to.
    pub domain: u32,
    center_nm: f32,
    nu_s: f32,
    nu_p: f32,
    layers: f32,
}

impl Notch {
    fn new(domain: u32, line: BraggLine) -> Notch {
        Notch {
            domain,
            center_nm: line.center_nm as f32,
            nu_s: line.nu_s as f32,
            nu_p: line.nu_p as f32,
            layers: line.layers as f32,
        }
    }

    /// The line.
    pub fn line(&self) -> BraggLine {
        BraggLine {
            center_nm: f64::from(self.center_nm),
            nu_s: f64::from(self.nu_s),
            nu_p: f64::from(self.nu_p),
            layers: f64::from(self.layers),
        }
    }
}

/// The light stored at one cell centre.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
struct Cell {
    /// Unit direction towards the light, inside (zero where no light arrives).
    to_light: Vec3,
    /// Irradiance across the beam × the light's intensity × the transmittance on the way.
    irradiance: f32,
    /// First of its notches in [`StoredLight::notches`].
    first_notch: u32,
    /// How many.
    notch_count: u32,
}

/// The light arriving at a point of the stone straight from the light.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Arrival {
    /// Unit direction towards the light, inside.
    pub to_light: Vec3,
    /// Irradiance across the beam (the light's intensity and the transmittance on the way
    /// included), relative to the light's at the stone's centre.
    pub irradiance: f32,
}

/// Scratch buffers of an exact solve.
#[derive(Default)]
pub struct Scratch {
    spans: Vec<Span>,
    lines: Vec<ActiveLine>,
}

/// One row of the light pass: its cells inside the stone (with their x) and their notches.
type Row = (Vec<(usize, Cell)>, Vec<Notch>);

/// The light of the scene's light stored on a grid over the stone's box.
#[derive(Debug)]
pub struct StoredLight {
    source: LightSource,
    intensity: f32,
    /// Centre of the first cell (the box's lowest corner), mm.
    origin: Vec3,
    cell_mm: f32,
    /// `cell_mm` as given.
    cell_mm_given: f64,
    dims: [usize; 3],
    /// Per grid point, its index in `cells`, or [`OUTSIDE`].
    slot: Vec<u32>,
    cells: Vec<Cell>,
    notches: Vec<Notch>,
}

/// What the light pass stored.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct LightStats {
    /// Grid points inside the stone (light stored there).
    pub cells: usize,
    /// Of those, how many the light reaches.
    pub lit_cells: usize,
    /// Bragg lines stored (the notches of the domains crossed on the way in).
    pub notches: usize,
    /// Edge of a cell, mm.
    pub cell_mm: f64,
    /// Bytes of the stored light.
    pub bytes: usize,
}

impl StoredLight {
    /// The light of `source` (intensity `intensity`) at every cell centre of a grid of edge
    /// `cell_mm` over the box of `stone`.
    pub fn trace(stone: &Stone, source: LightSource, intensity: f32, cell_mm_given: f64) -> Self {
        let cell_mm = cell_mm_given as f32;
        let half = stone.shape.semi_axes();
        let dims = half
            .to_array()
            .map(|a| ((2.0 * a / cell_mm).ceil() as usize + 1).max(2));
        // Centred on the box: the grid overhangs it by under a cell each side.
        let span = Vec3::new(
            (dims[0] - 1) as f32,
            (dims[1] - 1) as f32,
            (dims[2] - 1) as f32,
        ) * cell_mm;
        let origin = -0.5 * span;
        let mut light = StoredLight {
            source,
            intensity,
            origin,
            cell_mm,
            cell_mm_given,
            dims,
            slot: vec![OUTSIDE; dims[0] * dims[1] * dims[2]],
            cells: Vec::new(),
            notches: Vec::new(),
        };
        // One row along x per task, in row order; a stopped pass stores no more rows.
        let cancel = crate::cancel::Cancel::current();
        let rows: Vec<Row> = (0..dims[1] * dims[2])
            .into_par_iter()
            .map_init(Scratch::default, |scratch, row| {
                let (y, z) = (row % dims[1], row / dims[1]);
                let mut cells = Vec::new();
                let mut notches = Vec::new();
                for x in 0..dims[0] {
                    if cancel.is_cancelled() {
                        break;
                    }
                    let p = light.centre([x, y, z]);
                    if !stone.shape.contains(p) {
                        continue;
                    }
                    let first = notches.len();
                    let cell = match light.solve(stone, p, scratch, &mut |n| notches.push(n)) {
                        Some(a) => Cell {
                            to_light: a.to_light,
                            irradiance: a.irradiance,
                            first_notch: first as u32,
                            notch_count: (notches.len() - first) as u32,
                        },
                        None => {
                            notches.truncate(first);
                            Cell {
                                first_notch: first as u32,
                                ..Cell::default()
                            }
                        }
                    };
                    cells.push((x, cell));
                }
                (cells, notches)
            })
            .collect();
        for (row, (cells, notches)) in rows.into_iter().enumerate() {
            let offset = light.notches.len() as u32;
            let base = row * dims[0];
            for (x, mut cell) in cells {
                cell.first_notch += offset;
                light.slot[base + x] = light.cells.len() as u32;
                light.cells.push(cell);
            }
            light.notches.extend(notches);
        }
        light
    }

    /// The light reaching `x` straight, solved exactly ([`Stone::light_entry`],
    /// [`Stone::towards_light`]); the notches of the domains crossed go to `notch`. `None`
    /// where none (or under 10⁻⁶ of it) arrives.
    pub fn solve(
        &self,
        stone: &Stone,
        x: Vec3,
        scratch: &mut Scratch,
        notch: &mut dyn FnMut(Notch),
    ) -> Option<Arrival> {
        let (to_light, irradiance, distance) = stone.light_entry(&self.source, x)?;
        let path = PathToLight {
            x,
            to_light,
            distance,
            hint: Hint::default(),
            skip: None,
        };
        let transmitted = stone.towards_light(
            path,
            &mut scratch.spans,
            &mut scratch.lines,
            &mut |d, line| notch(Notch::new(d, line)),
        );
        (transmitted > 1e-6).then_some(Arrival {
            to_light,
            irradiance: irradiance * self.intensity * transmitted,
        })
    }

    fn centre(&self, [x, y, z]: [usize; 3]) -> Vec3 {
        self.origin + Vec3::new(x as f32, y as f32, z as f32) * self.cell_mm
    }

    /// The light at `x` (inside the stone): direction and irradiance interpolated between the
    /// cell centres about it; the notches of the nearest one go to `notch` (when given).
    /// Solved exactly where no centre about `x` lies inside the stone.
    pub fn at(
        &self,
        stone: &Stone,
        x: Vec3,
        scratch: &mut Scratch,
        notch: Option<&mut dyn FnMut(Notch)>,
    ) -> Option<Arrival> {
        let g = (x - self.origin) / self.cell_mm;
        let max = |k: usize| (self.dims[k] - 2) as f32;
        let g = Vec3::new(
            g.x.clamp(0.0, max(0)),
            g.y.clamp(0.0, max(1)),
            g.z.clamp(0.0, max(2)),
        );
        let base = [g.x as usize, g.y as usize, g.z as usize];
        let f = g - Vec3::new(base[0] as f32, base[1] as f32, base[2] as f32);
        let (mut dir, mut irradiance, mut total) = (Vec3::ZERO, 0.0f32, 0.0f32);
        let mut nearest: Option<(f32, u32)> = None;
        for corner in 0..8 {
            let o = [corner & 1, (corner >> 1) & 1, corner >> 2];
            let index = (base[2] + o[2]) * self.dims[0] * self.dims[1]
                + (base[1] + o[1]) * self.dims[0]
                + base[0]
                + o[0];
            let slot = self.slot[index];
            if slot == OUTSIDE {
                continue;
            }
            let w = (0..3)
                .map(|k| if o[k] == 1 { f[k] } else { 1.0 - f[k] })
                .product::<f32>();
            let cell = &self.cells[slot as usize];
            total += w;
            irradiance += w * cell.irradiance;
            dir += w * cell.to_light;
            if nearest.map_or(true, |(best, _)| w > best) {
                nearest = Some((w, slot));
            }
        }
        let Some((_, slot)) = nearest.filter(|_| total > 0.0) else {
            return match notch {
                Some(notch) => self.solve(stone, x, scratch, notch),
                None => self.solve(stone, x, scratch, &mut |_| {}),
            };
        };
        let to_light = dir.normalize_or_zero();
        if irradiance <= 0.0 || to_light == Vec3::ZERO {
            return None;
        }
        if let Some(notch) = notch {
            let cell = &self.cells[slot as usize];
            let first = cell.first_notch as usize;
            for n in &self.notches[first..first + cell.notch_count as usize] {
                notch(*n);
            }
        }
        Some(Arrival {
            to_light,
            irradiance: irradiance / total,
        })
    }

    /// What was stored.
    pub fn stats(&self) -> LightStats {
        LightStats {
            cells: self.cells.len(),
            lit_cells: self.cells.iter().filter(|c| c.irradiance > 0.0).count(),
            notches: self.notches.len(),
            cell_mm: self.cell_mm_given,
            bytes: self.slot.len() * 4
                + self.cells.len() * std::mem::size_of::<Cell>()
                + self.notches.len() * std::mem::size_of::<Notch>(),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::preset;

    #[test]
    fn a_lookup_between_centres_is_near_the_exact_solve() {
        // Independent: the exact solve at the point itself.
        let scene = preset("paper-stone").unwrap();
        let stone = Stone::new(&scene).unwrap();
        let source = LightSource::Directional {
            direction: Vec3::new(-0.5, 0.0, -0.866),
        };
        let light = StoredLight::trace(&stone, source, 1.0, 0.15);
        let stats = light.stats();
        assert!(stats.lit_cells > stats.cells / 2, "{stats:?}");
        let mut scratch = Scratch::default();
        let (mut worst, mut logs) = (0.0f32, Vec::new());
        for k in 0..200 {
            let t = k as f32 / 200.0;
            let x = Vec3::new(8.0 * t - 4.0, 3.0 - 5.0 * t, 1.5 - 2.5 * t);
            let Some(exact) = light.solve(&stone, x, &mut scratch, &mut |_| {}) else {
                continue;
            };
            let stored = light.at(&stone, x, &mut scratch, None).unwrap();
            worst = worst.max(exact.to_light.angle_between(stored.to_light));
            logs.push((stored.irradiance / exact.irradiance).ln().abs());
        }
        assert!(logs.len() > 150, "{} lit points", logs.len());
        assert!(worst < 0.01, "direction off by {worst} rad");
        // The transmittance through the potch changes fast where the light's way in grazes a
        // void (3 /mm): most points are close, a few at such shadow edges are not.
        logs.sort_by(f32::total_cmp);
        let (median, p90) = (logs[logs.len() / 2], logs[logs.len() * 9 / 10]);
        eprintln!("|ln(stored / exact)|: median {median}, 90 % {p90}");
        assert!(median < 0.05 && p90 < 0.25, "median {median}, 90 % {p90}");
    }
}

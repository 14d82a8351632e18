//! The paper's growth as geometry: each growth step's ball, kept analytically, so that a point
//! belongs to the latest ball that covers it (with that ball's orientation) and to potch where
//! none does. At the cells' centres this is exactly the grown cell structure; between them
//! patch edges are spheres, not the grid's staircase.

use glam::{Quat, Vec3};

use super::{Hint, Merge, Span};
use crate::error::Result;
use crate::scene::StructureConfig;
use crate::structure::{Growth, Structure};

/// One growth step's ball in cell units (centre at a cell centre, radius in cell edges).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ball {
    /// Centre, cell units: cell `i`'s centre is `i`.
    pub centre: Vec3,
    /// Radius in cell edges (squared).
    pub radius2: f32,
    /// Orientation given to the ball's cells.
    pub orientation: Quat,
}

/// The balls of a grown stone, in growth order, and the map from millimetres to cell units.
#[derive(Clone, Debug)]
pub struct Balls {
    /// Balls in growth order (later ones win).
    pub balls: Vec<Ball>,
    /// mm → cell units: `u = (p + offset) * scale`.
    scale: Vec3,
    offset: Vec3,
    /// The growth's cells: at every cell centre, the latest ball covering it.
    cells: Structure,
}

impl Balls {
    /// Grow the stone of `config` exactly as [`crate::structure::grow_structure`] does and keep
    /// every step's ball, and the grown cells.
    pub fn grow(config: &StructureConfig) -> Result<Balls> {
        let mut growth = Growth::new(config)?;
        let mut balls = Vec::new();
        while !growth.is_done() {
            let Some(step) = growth.step() else { break };
            let [x, y, z] = step.centre;
            let r = step.radius_cells as f32;
            balls.push(Ball {
                centre: Vec3::new(x as f32, y as f32, z as f32),
                radius2: r * r,
                orientation: step.orientation,
            });
        }
        let axes = Vec3::from_array(config.semi_axes_mm.map(|v| v as f32));
        let cells = Vec3::from_array(config.grid.map(|v| v as f32));
        let scale = cells / (2.0 * axes);
        // Cell i spans [−a + i·dx, −a + (i+1)·dx]: its centre −a + (i + ½)·dx maps to i.
        let offset = axes - 0.5 / scale;
        Ok(Balls {
            balls,
            scale,
            offset,
            cells: growth.finish(),
        })
    }

    /// The grown cell structure the balls were taken from, the same as
    /// [`crate::structure::grow_structure`] of the same configuration: at every cell centre
    /// the balls and the cells agree (`tests/stone_voxels.rs`).
    pub fn cells(&self) -> &Structure {
        &self.cells
    }

    fn to_cells(&self, p: Vec3) -> Vec3 {
        (p + self.offset) * self.scale
    }

    /// The ball `p` (mm) belongs to: the latest that covers it.
    pub fn at(&self, p: Vec3) -> Option<u32> {
        let u = self.to_cells(p);
        self.balls
            .iter()
            .rposition(|b| (u - b.centre).length_squared() <= b.radius2)
            .map(|i| i as u32)
    }

    /// Call `visit` for the spans of `[t0, t1]` along `origin + t·dir` (mm), in order, each with
    /// the ball it lies in (adjacent spans of one ball merged), until it returns false.
    pub fn walk(
        &self,
        origin: Vec3,
        dir: Vec3,
        t0: f32,
        t1: f32,
        visit: &mut dyn FnMut(Span) -> bool,
    ) {
        let o = self.to_cells(origin);
        let d = dir * self.scale;
        let a = d.length_squared();
        // Intervals of every ball the segment meets.
        let mut hits: Vec<(f32, f32, u32)> = Vec::new();
        let mut cuts: Vec<f32> = vec![t0, t1];
        for (k, b) in self.balls.iter().enumerate() {
            let oc = o - b.centre;
            let half_b = oc.dot(d);
            let c = oc.length_squared() - b.radius2;
            let disc = half_b * half_b - a * c;
            if disc <= 0.0 {
                continue;
            }
            let root = disc.sqrt();
            let (lo, hi) = ((-half_b - root) / a, (-half_b + root) / a);
            if hi <= t0 || lo >= t1 {
                continue;
            }
            hits.push((lo, hi, k as u32));
            cuts.extend([lo.max(t0), hi.min(t1)]);
        }
        cuts.sort_by(f32::total_cmp);
        let mut merged = Merge::default();
        for w in cuts.windows(2) {
            let (lo, hi) = (w[0], w[1]);
            if hi <= lo {
                continue;
            }
            let mid = 0.5 * (lo + hi);
            let domain = hits
                .iter()
                .filter(|h| h.0 <= mid && mid <= h.1)
                .map(|h| h.2)
                .max();
            let span = Span {
                t0: lo,
                t1: hi,
                domain,
                hint: Hint::default(),
            };
            if !merged.push(span, visit) {
                return;
            }
        }
        merged.finish(visit);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::structure::{grow_structure, Cell};

    #[test]
    fn the_balls_reproduce_the_grown_cells_at_their_centres() {
        let config = StructureConfig {
            grid: [40, 30, 10],
            semi_axes_mm: [4.0, 3.0, 1.0],
            ..StructureConfig::default()
        };
        let structure = grow_structure(&config).unwrap();
        let balls = Balls::grow(&config).unwrap();
        let size = structure.cell_size_mm();
        let mut checked = 0;
        for z in 0..10 {
            for y in 0..30 {
                for x in 0..40 {
                    let i = structure.index(x, y, z);
                    let p = Vec3::new(
                        (-4.0 + (x as f64 + 0.5) * size[0]) as f32,
                        (-3.0 + (y as f64 + 0.5) * size[1]) as f32,
                        (-1.0 + (z as f64 + 0.5) * size[2]) as f32,
                    );
                    let ball = balls.at(p);
                    match structure.cells[i] {
                        Cell::Outside => continue,
                        Cell::Void => assert_eq!(ball, None, "cell {x} {y} {z}"),
                        Cell::Cluster => {
                            let q = balls.balls[ball.expect("a cluster is in a ball") as usize];
                            assert!(q.orientation.dot(structure.orientations[i]).abs() > 0.9999);
                        }
                    }
                    checked += 1;
                }
            }
        }
        assert!(checked > 5000);
    }

    #[test]
    fn walk_spans_cover_the_segment_and_agree_with_point_queries() {
        let config = StructureConfig::default();
        let balls = Balls::grow(&config).unwrap();
        let origin = Vec3::new(-9.0, -1.0, 0.3);
        let dir = Vec3::new(1.0, 0.2, -0.05).normalize();
        let mut spans = Vec::new();
        balls.walk(origin, dir, 0.0, 18.0, &mut |s| {
            spans.push(s);
            true
        });
        assert!((spans[0].t0 - 0.0).abs() < 1e-6 && (spans.last().unwrap().t1 - 18.0).abs() < 1e-4);
        for w in spans.windows(2) {
            assert!((w[0].t1 - w[1].t0).abs() < 1e-5 && w[0].domain != w[1].domain);
        }
        for s in &spans {
            let mid = origin + dir * (0.5 * (s.t0 + s.t1));
            assert_eq!(balls.at(mid), s.domain);
        }
    }
}

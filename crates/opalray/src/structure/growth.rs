//! Cluster growth (paper §2.4, eq. 1): from a stone of voids to the cluster/void structure.
//!
//! Step `s` draws from its own stream `Rng::new(seed, stage::STRUCTURE, s)`, in this order:
//! the centre (uniform over the inside cells), the radius `r` (continuous exponential with
//! mean `R`, the density `exp(−r/R)/R` of eq. 1), then, only if the neighbourhood holds no
//! cluster, a uniformly random orientation (Shoemake), then the jitter. Every inside cell
//! within `r` (see [`ball`]) becomes a cluster and takes the new orientation,
//! the cells that were already clusters included: the paper sets "the selected cell and its
//! neighboring cells as cluster" with "the average orientation of neighboring clusters
//! already set". Growth stops as soon as voids / inside cells < the target void ratio.
//!
//! The loop is sequential by nature (each step reads the previous ones), needs no threads,
//! and so gives the same structure at any thread count.

use glam::Quat;

use super::ball;
use super::orientation::{jitter, OrientationMean};
use super::{Cell, Structure, StructureStats};
use crate::error::Result;
use crate::sampling::{stage, Rng};
use crate::scene::StructureConfig;

/// The random choices that open growth step `step`.
#[derive(Clone, Debug)]
pub struct StepDraw {
    /// Rank of the centre among the inside cells (in index order), `0 .. inside_cells`.
    pub centre_slot: usize,
    /// Neighbourhood radius `r` in cell edges, exponential with mean `mean_radius_cells`.
    pub radius_cells: f64,
    rng: Rng,
}

/// Draw the centre and radius of growth step `step`, exactly as [`Growth::step`] does.
/// `inside_cells` must be at least 1.
pub fn draw_step(seed: u64, step: u64, inside_cells: usize, mean_radius_cells: f64) -> StepDraw {
    let mut rng = Rng::new(seed, stage::STRUCTURE, step);
    let centre_slot = rng.below(inside_cells as u64) as usize;
    let radius_cells = rng.exponential(mean_radius_cells);
    StepDraw {
        centre_slot,
        radius_cells,
        rng,
    }
}

/// What one growth step did.
#[derive(Clone, Debug)]
pub struct StepReport {
    /// The selected cell `[x, y, z]`.
    pub centre: [usize; 3],
    /// The radius drawn, cell edges.
    pub radius_cells: f64,
    /// Inside cells in the neighbourhood.
    pub cells: usize,
    /// Of those, cells that were clusters before the step (the average is taken over them).
    pub averaged: usize,
    /// Of those, cells that were voids and are now clusters.
    pub converted: usize,
    /// The orientation every cell of the neighbourhood now has.
    pub orientation: Quat,
}

/// A structure being grown, one step at a time; [`grow_structure`] runs it to the end.
#[derive(Clone, Debug)]
pub struct Growth {
    structure: Structure,
    target_void_ratio: f64,
    mean_radius_cells: f64,
    jitter_rad: f64,
    seed: u64,
    /// Inside x range `[start, end)` of each row `y + ny·z` (contiguous: the ellipsoid is
    /// convex).
    row_inside: Vec<(usize, usize)>,
    /// Inside cells before each row; one more entry than rows, the last = all inside cells.
    row_prefix: Vec<usize>,
    radius_sum: f64,
    /// Reused list of the current neighbourhood's inside index ranges.
    segments: Vec<(usize, usize)>,
}

impl Growth {
    /// All inside cells void, no step taken. The configuration is validated first (grid
    /// size included, before anything is allocated).
    pub fn new(config: &StructureConfig) -> Result<Growth> {
        config.validate()?;
        let [nx, ny, nz] = config.grid;
        let mut cells = vec![Cell::Outside; nx * ny * nz];
        let mut row_inside = Vec::with_capacity(ny * nz);
        let mut row_prefix = Vec::with_capacity(ny * nz + 1);
        let mut inside = 0;
        // Normalised centre coordinate u = (−a + (i + ½)·2a/n)/a of cell i along an axis.
        let centre = |i: usize, n: usize| -1.0 + (i as f64 + 0.5) * 2.0 / n as f64;
        for z in 0..nz {
            let w = centre(z, nz);
            for y in 0..ny {
                let v = centre(y, ny);
                let row = nx * (y + ny * z);
                let (mut start, mut end) = (0, 0);
                for x in 0..nx {
                    let u = centre(x, nx);
                    if u * u + v * v + w * w <= 1.0 {
                        if start == end {
                            start = x;
                        }
                        end = x + 1;
                        cells[row + x] = Cell::Void;
                    }
                }
                row_prefix.push(inside);
                row_inside.push((start, end));
                inside += end - start;
            }
        }
        row_prefix.push(inside);
        Ok(Growth {
            structure: Structure {
                grid: config.grid,
                semi_axes_mm: config.semi_axes_mm,
                cells,
                orientations: vec![Quat::IDENTITY; nx * ny * nz],
                stats: StructureStats {
                    inside_cells: inside,
                    clusters: 0,
                    voids: inside,
                    void_ratio: if inside > 0 { 1.0 } else { 0.0 },
                    seeds_placed: 0,
                    mean_radius_cells: 0.0,
                },
            },
            target_void_ratio: config.void_ratio,
            mean_radius_cells: config.mean_radius_cells,
            jitter_rad: config.orientation_jitter_deg.to_radians(),
            seed: config.seed,
            row_inside,
            row_prefix,
            radius_sum: 0.0,
            segments: Vec::new(),
        })
    }

    /// The structure so far, with its counts up to date.
    pub fn structure(&self) -> &Structure {
        &self.structure
    }

    /// True once voids / inside cells is below the target (or there is no inside cell).
    pub fn is_done(&self) -> bool {
        let stats = &self.structure.stats;
        stats.inside_cells == 0 || stats.void_ratio < self.target_void_ratio
    }

    /// Take the next growth step (even if [`Growth::is_done`]); `None` if the stone has no
    /// inside cell.
    pub fn step(&mut self) -> Option<StepReport> {
        let stats = &self.structure.stats;
        if stats.inside_cells == 0 {
            return None;
        }
        let step = stats.seeds_placed as u64;
        let mut draw = draw_step(self.seed, step, stats.inside_cells, self.mean_radius_cells);
        let [nx, ny, _] = self.structure.grid;

        // Locate the centre: the row holding inside cell number `centre_slot`.
        let row = self.row_prefix.partition_point(|&p| p <= draw.centre_slot) - 1;
        let x = self.row_inside[row].0 + (draw.centre_slot - self.row_prefix[row]);
        let centre = [x, row % ny, row / ny];
        let centre_index = x + nx * row;

        // Collect the neighbourhood's inside cells as index ranges, and average the clusters
        // among them, aligned to the centre's orientation when it is a cluster.
        let cells = &self.structure.cells;
        let orientations = &self.structure.orientations;
        let mut mean = match cells[centre_index] {
            Cell::Cluster => OrientationMean::with_reference(orientations[centre_index]),
            _ => OrientationMean::new(),
        };
        self.segments.clear();
        ball::for_each_row(
            self.structure.grid,
            centre,
            draw.radius_cells,
            |y, z, xs| {
                let row = y + ny * z;
                let (start, end) = self.row_inside[row];
                let (lo, hi) = (xs.start.max(start), xs.end.min(end));
                if lo < hi {
                    let (lo, hi) = (nx * row + lo, nx * row + hi);
                    self.segments.push((lo, hi));
                    for index in lo..hi {
                        if cells[index] == Cell::Cluster {
                            mean.add(orientations[index]);
                        }
                    }
                }
            },
        );

        // The new orientation: the average, or uniformly random where there was no cluster.
        let orientation = match mean.mean() {
            Some(q) => q,
            None => draw.rng.rotation(),
        };
        let orientation = jitter(orientation, self.jitter_rad, &mut draw.rng);

        // Every inside cell of the neighbourhood becomes a cluster with that orientation.
        let mut converted = 0;
        let mut neighbourhood = 0;
        for &(lo, hi) in &self.segments {
            neighbourhood += hi - lo;
            for index in lo..hi {
                converted += usize::from(self.structure.cells[index] == Cell::Void);
                self.structure.cells[index] = Cell::Cluster;
            }
            self.structure.orientations[lo..hi].fill(orientation);
        }

        // Update the counts.
        self.radius_sum += draw.radius_cells;
        let stats = &mut self.structure.stats;
        stats.voids -= converted;
        stats.clusters += converted;
        stats.void_ratio = stats.voids as f64 / stats.inside_cells as f64;
        stats.seeds_placed += 1;
        stats.mean_radius_cells = self.radius_sum / stats.seeds_placed as f64;
        Some(StepReport {
            centre,
            radius_cells: draw.radius_cells,
            cells: neighbourhood,
            averaged: mean.count(),
            converted,
            orientation,
        })
    }

    /// The grown structure.
    pub fn finish(self) -> Structure {
        self.structure
    }
}

/// Growth steps between two looks at the cancel flag (a step is a ball of a few hundred cells).
pub const STEPS_PER_POLL: u32 = 64;

/// Grow the cluster/void structure of `config` (paper §2.4): step until the void ratio is
/// below `config.void_ratio`. Deterministic in `config` (seed included), at any thread
/// count. Errors: an invalid `config`, named by its field; [`Error::Cancelled`]
/// (crate::error::Error::Cancelled) once this thread's [`Cancel`](crate::cancel::Cancel) is set
/// (looked at every [`STEPS_PER_POLL`] steps).
pub fn grow_structure(config: &StructureConfig) -> Result<Structure> {
    let cancel = crate::cancel::Cancel::current();
    let mut growth = Growth::new(config)?;
    let mut steps = 0u32;
    while !growth.is_done() {
        growth.step();
        steps = steps.wrapping_add(1);
        if steps % STEPS_PER_POLL == 0 {
            cancel.check()?;
        }
    }
    Ok(growth.finish())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn small() -> StructureConfig {
        StructureConfig {
            grid: [30, 24, 10],
            semi_axes_mm: [3.0, 2.4, 1.0],
            ..StructureConfig::default()
        }
    }

    #[test]
    fn growth_counts_agree_with_the_cells() {
        let s = grow_structure(&small()).unwrap();
        let count = |c| s.cells.iter().filter(|&&x| x == c).count();
        assert_eq!(count(Cell::Cluster), s.stats.clusters);
        assert_eq!(count(Cell::Void), s.stats.voids);
        assert_eq!(s.stats.clusters + s.stats.voids, s.stats.inside_cells);
        assert!(s.stats.seeds_placed > 0);
    }

    #[test]
    fn step_sets_the_whole_neighbourhood_to_one_orientation() {
        let mut growth = Growth::new(&small()).unwrap();
        for _ in 0..20 {
            let report = growth.step().unwrap();
            let s = growth.structure();
            let mut seen = 0;
            ball::for_each_row(s.grid, report.centre, report.radius_cells, |y, z, xs| {
                for x in xs {
                    let i = s.index(x, y, z);
                    if s.cells[i] != Cell::Outside {
                        assert_eq!(s.cells[i], Cell::Cluster);
                        assert_eq!(s.orientations[i], report.orientation);
                        seen += 1;
                    }
                }
            });
            assert_eq!(seen, report.cells);
        }
    }

    #[test]
    fn first_step_draws_a_random_orientation_then_averages() {
        let mut growth = Growth::new(&small()).unwrap();
        let first = growth.step().unwrap();
        assert_eq!(first.averaged, 0);
        assert_eq!(first.converted, first.cells);
        let later: Vec<_> = (0..50).map(|_| growth.step().unwrap()).collect();
        assert!(later.iter().any(|r| r.averaged > 0));
    }

    #[test]
    fn step_inside_one_patch_keeps_its_planes() {
        // Where every cluster of the neighbourhood has one orientation, their average is
        // that orientation: the (111) planes (normal up to sign) are unchanged.
        let mut growth = Growth::new(&small()).unwrap();
        let mut checked = 0;
        for _ in 0..200 {
            let before = growth.structure().clone();
            let report = growth.step().unwrap();
            // One cell per distinct orientation among the neighbourhood's clusters.
            let mut found = Vec::new();
            ball::for_each_row(
                before.grid,
                report.centre,
                report.radius_cells,
                |y, z, xs| {
                    for x in xs {
                        let i = before.index(x, y, z);
                        let q = before.orientations[i];
                        let new = found.iter().all(|&j| before.orientations[j] != q);
                        if before.cells[i] == Cell::Cluster && new {
                            found.push(i);
                        }
                    }
                },
            );
            if let [only] = found[..] {
                let n = report.orientation * super::super::AXIS_111;
                assert!(n.dot(before.normal(only)).abs() > 1.0 - 1e-5);
                checked += 1;
            }
        }
        assert!(checked > 10, "only {checked} single-patch steps");
    }

    #[test]
    fn void_cells_become_cluster_only_inside_the_stone() {
        let s = grow_structure(&small()).unwrap();
        for (i, cell) in s.cells.iter().enumerate() {
            if *cell != Cell::Cluster {
                assert_eq!(s.orientations[i], Quat::IDENTITY);
            }
        }
    }
}

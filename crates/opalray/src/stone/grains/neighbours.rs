//! The grains' bucket grid and their neighbours: which seeds lie near a point, and each
//! grain's boundary faces, found by rays cast from its seed (a walk's next plane is among
//! them).

use std::ops::Range;

use glam::Vec3;
use rayon::prelude::*;

use super::super::faces::{Face, Faces};
use super::Grains;

impl Grains {
    pub(super) fn bucket_of(&self, q: Vec3) -> [usize; 3] {
        let b = (q - self.lo) / self.bucket;
        [0, 1, 2].map(|a| (b[a].max(0.0) as usize).min(self.dims[a] - 1))
    }

    pub(super) fn bucket_index(&self, b: [usize; 3]) -> usize {
        b[0] + self.dims[0] * (b[1] + self.dims[1] * b[2])
    }

    pub(super) fn fill_buckets(&mut self) {
        let n = self.dims.iter().product::<usize>();
        let mut counts = vec![0u32; n + 1];
        let keys: Vec<usize> = self
            .seeds
            .iter()
            .map(|&s| self.bucket_index(self.bucket_of(s)))
            .collect();
        for &k in &keys {
            counts[k + 1] += 1;
        }
        for i in 0..n {
            counts[i + 1] += counts[i];
        }
        let mut fill = counts.clone();
        let mut members = vec![0u32; self.seeds.len()];
        for (i, &k) in keys.iter().enumerate() {
            members[fill[k] as usize] = i as u32;
            fill[k] += 1;
        }
        self.starts = counts;
        self.members = members;
    }

    /// The buckets within `reach` buckets of `q`'s, as runs of `members`: each row of
    /// buckets along x is one run (its buckets are consecutive, and so are their members).
    /// With `skip_inner`, the buckets within `reach − 1` are left out.
    #[inline]
    pub(super) fn rows_near(
        &self,
        q: Vec3,
        reach: i64,
        skip_inner: bool,
        mut f: impl FnMut(Range<usize>),
    ) {
        let b = self.bucket_of(q);
        let range = |a: usize, reach: i64| {
            let lo = (b[a] as i64 - reach).max(0) as usize;
            let hi = ((b[a] as i64 + reach).max(0) as usize).min(self.dims[a] - 1);
            lo..=hi
        };
        let (x_lo, x_hi) = range(0, reach).into_inner();
        let inner = skip_inner.then(|| [0, 1, 2].map(|a| range(a, reach - 1)));
        for z in range(2, reach) {
            for y in range(1, reach) {
                let run = |x0: usize, x1: usize| {
                    let first = self.starts[self.bucket_index([x0, y, z])] as usize;
                    first..self.starts[self.bucket_index([x1, y, z]) + 1] as usize
                };
                match &inner {
                    Some([ix, iy, iz]) if iy.contains(&y) && iz.contains(&z) => {
                        if x_lo < *ix.start() {
                            f(run(x_lo, ix.start() - 1));
                        }
                        if *ix.end() < x_hi {
                            f(run(ix.end() + 1, x_hi));
                        }
                    }
                    _ => f(run(x_lo, x_hi)),
                }
            }
        }
    }

    /// A lower bound of the squared distance from `q` (stretched space) to every seed outside
    /// the buckets within `reach` of `q`'s: to the nearest face of that cube beyond which the
    /// grid goes on (seeds beyond the grid's edge are counted in its outer buckets), less a
    /// margin for the roundings of the buckets' edges; infinite if the cube covers the grid.
    pub(super) fn beyond_cube(&self, q: Vec3, reach: i64) -> f32 {
        let b = self.bucket_of(q);
        let margin = 1e-4 * self.bucket;
        let mut gap = f32::INFINITY;
        for a in 0..3 {
            let lo = b[a] as i64 - reach;
            if lo > 0 {
                gap = gap.min(q[a] - (self.lo[a] + lo as f32 * self.bucket) - margin);
            }
            let hi = b[a] as i64 + reach;
            if hi < self.dims[a] as i64 - 1 {
                gap = gap.min(self.lo[a] + (hi + 1) as f32 * self.bucket - margin - q[a]);
            }
        }
        let gap = gap.max(0.0);
        gap * gap
    }

    /// Seeds in the buckets within `reach` buckets of `q`'s, bucket by bucket.
    pub(super) fn for_each_near(&self, q: Vec3, reach: i64, mut f: impl FnMut(u32)) {
        self.rows_near(q, reach, false, |run| {
            self.members[run].iter().for_each(|&m| f(m))
        });
    }

    pub(super) fn find_neighbours(&mut self) {
        // Weights no larger than 0.45 × the squared distance to the nearest other seed keep
        // every seed inside its own cell (w_i − w_j < |s_i − s_j|²), so no cell is empty.
        let reach = 2;
        // A stopped growth skips the rest of its grains (its stone is never used).
        let cancel = crate::cancel::Cancel::current();
        let nearest: Vec<f32> = (0..self.seeds.len() as u32)
            .map(|i| {
                if cancel.is_cancelled() {
                    return f32::INFINITY;
                }
                let s = self.seeds[i as usize];
                let mut best = f32::INFINITY;
                self.for_each_near(s, reach, |j| {
                    if j != i {
                        best = best.min((self.seeds[j as usize] - s).length_squared());
                    }
                });
                best
            })
            .collect();
        for (w, d2) in self.weights.iter_mut().zip(&nearest) {
            *w = w.min(0.45 * d2);
        }
        self.largest_weight = self.weights.iter().cloned().fold(0.0, f32::max);
        // Candidates: every seed within the reach; kept: those whose plane bounds the cell
        // along one of many rays from the seed (a face no ray meets is under a few % of the
        // cell's surface, and a walk that misses it only moves that corner to a neighbour).
        let directions = fibonacci_sphere(RAYS_PER_CELL);
        let limit = (reach as f32 * self.bucket).powi(2) * 1.6;
        let neighbours: Vec<Vec<u32>> = (0..self.seeds.len() as u32)
            .into_par_iter()
            .map(|i| {
                if cancel.is_cancelled() {
                    return Vec::new();
                }
                let s = self.seeds[i as usize];
                let mut candidates = Vec::new();
                self.for_each_near(s, reach + 1, |j| {
                    if j != i && (self.seeds[j as usize] - s).length_squared() <= limit {
                        candidates.push(j);
                    }
                });
                let mut kept: Vec<u32> = directions
                    .iter()
                    .filter_map(|&d| self.exit(i, s, d, 0.0, f32::INFINITY, &candidates).1)
                    .collect();
                kept.sort_unstable();
                kept.dedup();
                kept
            })
            .collect();
        // The plane between grains i and j: `q · m = c`, `m = s_j − s_i`,
        // `c = (|s_j|² − |s_i|² − w_j + w_i) / 2`.
        let faces = neighbours.iter().enumerate().map(|(i, list)| {
            let (si, wi) = (self.seeds[i], self.weights[i]);
            list.iter()
                .map(|&j| {
                    let (sj, wj) = (self.seeds[j as usize], self.weights[j as usize]);
                    Face {
                        m: sj - si,
                        c: 0.5 * (sj.length_squared() - si.length_squared() - wj + wi),
                        next: j,
                    }
                })
                .collect()
        });
        self.faces = Faces::new(faces);
    }
}

/// Rays per grain that find its faces.
const RAYS_PER_CELL: usize = 96;

/// `n` unit vectors spread evenly over the sphere (a Fibonacci lattice).
fn fibonacci_sphere(n: usize) -> Vec<Vec3> {
    let golden = std::f32::consts::PI * (3.0 - 5f32.sqrt());
    (0..n)
        .map(|k| {
            let z = 1.0 - 2.0 * (k as f32 + 0.5) / n as f32;
            let r = (1.0 - z * z).max(0.0).sqrt();
            let phi = golden * k as f32;
            Vec3::new(r * phi.cos(), r * phi.sin(), z)
        })
        .collect()
}

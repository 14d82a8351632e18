//! Grains as a power (Laguerre) diagram: angular mosaics (harlequin, flagstone), stretched
//! grains (ribbon, straw) and tiny grains (pinfire).
//!
//! Seeds `s_i` with weights `w_i` are placed by a Poisson process over the stone's box, in a
//! space stretched by `1/stretch` along each axis; a point `p` belongs to the grain of the
//! least power distance `|q − s_i|² − w_i`, `q = p / stretch`. The boundary between two grains
//! is a plane in the stretched space, so also in the stone's: grains are convex polyhedra, and
//! a ray's walk from grain to grain is exact (the next boundary is the nearest plane crossing
//! among the grain's neighbours).

use std::ops::Range;

use glam::{Vec3, Vec4};
use rayon::prelude::*;

use super::faces::{Face, Faces};
use super::{Hint, Span};
use crate::sampling::Rng;

/// A power diagram of grains and what finds them.
#[derive(Clone, Debug)]
pub struct Grains {
    /// Seeds in the stretched space.
    pub seeds: Vec<Vec3>,
    /// Weights (squared lengths in the stretched space).
    pub weights: Vec<f32>,
    stretch: Vec3,
    /// Bucket grid over the stretched box.
    lo: Vec3,
    bucket: f32,
    dims: [usize; 3],
    starts: Vec<u32>,
    members: Vec<u32>,
    /// Per member, its seed and weight `(s, w)`, in the order of `members`: the point
    /// query's data in one run of memory.
    packed: Vec<Vec4>,
    /// The boundary faces of every grain, each grain's in the order of its neighbours'
    /// indices.
    faces: Faces,
    largest_weight: f32,
}

impl Grains {
    /// Grains over the box `[−half, half]` (mm) of mean size `size_mm` (the diameter of a ball of
    /// the mean grain volume), relative spread `spread` of the grain sizes (lognormal), stretched
    /// by `stretch`, from the random stream `rng`.
    pub fn new(half: Vec3, size_mm: f32, spread: f32, stretch: Vec3, rng: &mut Rng) -> Grains {
        let lo = -half / stretch;
        let extent = 2.0 * half / stretch;
        // Poisson seeds at the density of one per grain volume (in the stretched space the
        // volume is divided by the stretch's product).
        let volume =
            std::f32::consts::PI / 6.0 * size_mm.powi(3) / stretch.x / stretch.y / stretch.z;
        let margin = 1.0;
        let box_volume = (extent.x + 2.0 * margin * volume.cbrt())
            * (extent.y + 2.0 * margin * volume.cbrt())
            * (extent.z + 2.0 * margin * volume.cbrt());
        let count = ((box_volume / volume).round() as usize).max(1);
        let pad = Vec3::splat(margin * volume.cbrt());
        let mut seeds = Vec::with_capacity(count);
        let mut weights = Vec::with_capacity(count);
        let sigma = (1.0 + spread * spread).ln().sqrt();
        for _ in 0..count {
            let u = Vec3::new(rng.uniform_f32(), rng.uniform_f32(), rng.uniform_f32());
            seeds.push(lo - pad + u * (extent + 2.0 * pad));
            // A grain's weight grows its cell like a radius²: lognormal relative sizes.
            let z = normal(rng);
            let r = 0.5 * volume.cbrt() * (sigma * z - 0.5 * sigma * sigma).exp();
            weights.push(if spread > 0.0 { r * r } else { 0.0 });
        }
        let bucket = volume.cbrt();
        let full = extent + 2.0 * pad;
        let dims = [
            ((full.x / bucket).ceil() as usize).max(1),
            ((full.y / bucket).ceil() as usize).max(1),
            ((full.z / bucket).ceil() as usize).max(1),
        ];
        let mut grains = Grains {
            seeds,
            weights,
            stretch,
            lo: lo - pad,
            bucket,
            dims,
            starts: Vec::new(),
            members: Vec::new(),
            packed: Vec::new(),
            faces: Faces::default(),
            largest_weight: 0.0,
        };
        grains.largest_weight = grains.weights.iter().cloned().fold(0.0, f32::max);
        grains.fill_buckets();
        grains.find_neighbours();
        grains.packed = (grains.members.iter())
            .map(|&m| grains.seeds[m as usize].extend(grains.weights[m as usize]))
            .collect();
        grains
    }

    fn bucket_of(&self, q: Vec3) -> [usize; 3] {
        let b = (q - self.lo) / self.bucket;
        [0, 1, 2].map(|a| (b[a].max(0.0) as usize).min(self.dims[a] - 1))
    }

    fn bucket_index(&self, b: [usize; 3]) -> usize {
        b[0] + self.dims[0] * (b[1] + self.dims[1] * b[2])
    }

    fn fill_buckets(&mut self) {
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
    fn rows_near(&self, q: Vec3, reach: i64, skip_inner: bool, mut f: impl FnMut(Range<usize>)) {
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
    fn beyond_cube(&self, q: Vec3, reach: i64) -> f32 {
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
    fn for_each_near(&self, q: Vec3, reach: i64, mut f: impl FnMut(u32)) {
        self.rows_near(q, reach, false, |run| {
            self.members[run].iter().for_each(|&m| f(m))
        });
    }

    fn find_neighbours(&mut self) {
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

    /// The first plane of `candidates` that the ray `o + t·d` (stretched space) crosses after
    /// `t` leaving grain `i`, before `t_max`: `(t, grain)`.
    #[inline]
    fn exit(
        &self,
        i: u32,
        o: Vec3,
        d: Vec3,
        t: f32,
        t_max: f32,
        candidates: &[u32],
    ) -> (f32, Option<u32>) {
        let (si, wi) = (self.seeds[i as usize], self.weights[i as usize]);
        let mut next = (t_max, None);
        for &j in candidates {
            let (sj, wj) = (self.seeds[j as usize], self.weights[j as usize]);
            let m = sj - si;
            let denom = 2.0 * d.dot(m);
            if denom <= 0.0 {
                continue;
            }
            let rhs = sj.length_squared() - si.length_squared() - wj + wi;
            let tc = (rhs - 2.0 * o.dot(m)) / denom;
            if tc > t && tc < next.0 {
                next = (tc, Some(j));
            }
        }
        next
    }

    /// The grain holding `p` (mm) as the grains' faces see it: `hint` is tried first, then
    /// its neighbours (a grain whose rays missed a face may claim a sliver beyond it, as its
    /// walk does), else the exact point query [`Grains::at`].
    pub fn at_with(&self, p: Vec3, hint: Option<u32>) -> u32 {
        if let Some(h) = hint {
            let q = p / self.stretch;
            if self.faces.holds(h, q) {
                return h;
            }
            if let Some(j) = self.faces.neighbours(h).find(|&j| self.faces.holds(j, q)) {
                return j;
            }
        }
        self.at(p)
    }

    /// The grain holding `p` (mm).
    pub fn at(&self, p: Vec3) -> u32 {
        let q = p / self.stretch;
        let mut best = (f32::INFINITY, 0u32);
        let mut reach = 1;
        loop {
            // The least power, the least index on a tie: the same whatever the order. The
            // cube one bucket nearer was searched before.
            self.rows_near(q, reach, reach > 1, |run| {
                for (k, &s) in self.packed[run.clone()].iter().enumerate() {
                    let d = (q - s.truncate()).length_squared() - s.w;
                    // The index is read only for a power no larger than the best.
                    if d <= best.0 {
                        let j = self.members[run.start + k];
                        if d < best.0 || j < best.1 {
                            best = (d, j);
                        }
                    }
                }
            });
            // Any seed farther than the searched buckets has power ≥ (reach·bucket)² − w_max.
            let bound = (reach as f32 * self.bucket).powi(2) - self.largest_weight;
            if best.0 <= bound || reach > self.dims.iter().cloned().max().unwrap_or(1) as i64 {
                return best.1;
            }
            // Nor can a wider search change the answer when every seed beyond has a larger
            // power, as computed: the distance to the cube's open faces shows it more often
            // (margins far above the f32 roundings).
            let beyond = self.beyond_cube(q, reach) * (1.0 - 1e-5);
            if beyond - self.largest_weight * (1.0 + 1e-5) > best.0 {
                return best.1;
            }
            reach += 1;
        }
    }

    /// Call `visit` for the grains along `origin + t·dir`, `t ∈ [t0, t1]` (mm), in order,
    /// until it returns false; true if the walk reached `t1`.
    /// `hint`: a grain likely to hold the start, tried first, then its neighbours.
    pub fn walk(
        &self,
        origin: Vec3,
        dir: Vec3,
        t0: f32,
        t1: f32,
        hint: Option<u32>,
        mut visit: impl FnMut(Span, u32) -> bool,
    ) -> bool {
        let o = origin / self.stretch;
        let d = dir / self.stretch;
        let mut t = t0;
        let mut current = self.at_with(origin + dir * t0, hint);
        // Guard against a ray stuck on a boundary: at most this many grains per walk.
        for _ in 0..100_000 {
            let (t_next, next) = self.faces.next_plane(current, o, d, t, t1);
            let go_on = visit(
                Span {
                    t0: t,
                    t1: t_next,
                    domain: Some(current),
                    hint: Hint {
                        column: None,
                        grain: Some(current),
                    },
                },
                current,
            );
            if !go_on {
                return false;
            }
            match next {
                Some(j) if t_next < t1 => {
                    t = t_next;
                    current = j;
                }
                _ => return true,
            }
        }
        true
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

/// A standard normal number (Box–Muller, one of the pair).
pub fn normal(rng: &mut Rng) -> f32 {
    let u1 = (1.0 - rng.uniform()).max(1e-300);
    let u2 = rng.uniform();
    ((-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()) as f32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::stage;

    /// The power distance of `q` (stretched space) to grain `i`'s seed.
    fn power(g: &Grains, i: u32, q: Vec3) -> f32 {
        (q - g.seeds[i as usize]).length_squared() - g.weights[i as usize]
    }

    fn grains(spread: f32, stretch: Vec3) -> Grains {
        let mut rng = Rng::new(7, stage::STRUCTURE, 0);
        Grains::new(Vec3::new(10.0, 7.5, 2.5), 2.0, spread, stretch, &mut rng)
    }

    #[test]
    fn point_queries_find_the_least_power_distance() {
        let g = grains(0.4, Vec3::new(1.0, 3.0, 1.0));
        let mut rng = Rng::new(3, stage::STRUCTURE, 1);
        for _ in 0..300 {
            let p = Vec3::new(
                rng.uniform_f32() * 20.0 - 10.0,
                rng.uniform_f32() * 15.0 - 7.5,
                rng.uniform_f32() * 5.0 - 2.5,
            );
            let q = p / g.stretch;
            let brute = (0..g.seeds.len() as u32)
                .min_by(|&a, &b| power(&g, a, q).total_cmp(&power(&g, b, q)))
                .unwrap();
            assert_eq!(g.at(p), brute);
        }
    }

    #[test]
    fn a_hint_or_its_neighbours_find_the_point_querys_grain() {
        // Points near a hint's grain: in it, beside it, or a few grains away.
        let g = grains(0.4, Vec3::new(2.5, 2.5, 0.12));
        let mut rng = Rng::new(5, stage::STRUCTURE, 2);
        let (mut total, mut agree, mut by_neighbour) = (0, 0, 0);
        for _ in 0..4000 {
            let p = Vec3::new(
                rng.uniform_f32() * 16.0 - 8.0,
                rng.uniform_f32() * 12.0 - 6.0,
                rng.uniform_f32() * 4.0 - 2.0,
            );
            let step = Vec3::new(
                rng.uniform_f32() - 0.5,
                rng.uniform_f32() - 0.5,
                0.1 * (rng.uniform_f32() - 0.5),
            ) * 4.0;
            let hint = g.at(p + step);
            let exact = g.at(p);
            let found = g.at_with(p, Some(hint));
            total += 1;
            agree += usize::from(found == exact);
            let neighbour = g.faces.neighbours(hint).any(|j| j == exact);
            by_neighbour += usize::from(found == exact && neighbour);
        }
        // The faces found by rays are nearly complete: the answers are the exact ones but for
        // slivers (3998 of 4000, measured), 2364 of them a neighbour of the hint.
        assert!(agree as f64 > 0.995 * total as f64, "{agree} of {total}");
        assert!(
            by_neighbour > total / 5,
            "{by_neighbour} of {total} by a neighbour"
        );
    }

    #[test]
    fn walks_visit_the_grains_point_queries_see() {
        let g = grains(0.3, Vec3::ONE);
        let origin = Vec3::new(-9.5, -6.0, 2.0);
        let dir = Vec3::new(1.0, 0.7, -0.2).normalize();
        let mut spans = Vec::new();
        g.walk(origin, dir, 0.0, 20.0, None, &mut |s, _| {
            spans.push(s);
            true
        });
        assert!(spans.len() > 5);
        for s in &spans {
            if s.t1 - s.t0 < 1e-3 {
                continue;
            }
            let mid = origin + dir * (0.5 * (s.t0 + s.t1));
            assert_eq!(Some(g.at(mid)), s.domain, "span {s:?}");
        }
    }
}

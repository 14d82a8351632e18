//! Grains as a power (Laguerre) diagram: angular mosaics (harlequin, flagstone), stretched
//! grains (ribbon, straw) and tiny grains (pinfire).
//!
//! Seeds `s_i` with weights `w_i` are placed by a Poisson process over the stone's box, in a
//! space stretched by `1/stretch` along each axis; a point `p` belongs to the grain of the
//! least power distance `|q − s_i|² − w_i`, `q = p / stretch`. The boundary between two grains
//! is a plane in the stretched space, so also in the stone's: grains are convex polyhedra, and
//! a ray's walk from grain to grain is exact (the next boundary is the nearest plane crossing
//! among the grain's neighbours). The bucket grid and each grain's faces: `neighbours.rs`.

use glam::{Vec3, Vec4};

use super::faces::Faces;
use super::{Hint, Span};
use crate::sampling::Rng;

mod neighbours;

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

/// A standard normal number (Box–Muller, one of the pair).
pub fn normal(rng: &mut Rng) -> f32 {
    let u1 = (1.0 - rng.uniform()).max(1e-300);
    let u2 = rng.uniform();
    ((-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()) as f32
}

#[cfg(test)]
mod tests;

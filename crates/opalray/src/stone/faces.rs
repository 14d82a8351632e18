//! The faces of a power diagram's grains, four to a block, and the queries a walk makes of
//! them: input each grain's bounding planes → output [`Faces`], which finds where a ray leaves
//! a grain ([`Faces::next_plane`]) and whether a point lies in one ([`Faces::holds`]).
//!
//! A grain has about fifteen faces, and a walk asks every one of them at every grain it
//! crosses. Kept as columns of four (`x`, `y`, `z` of the normals, the offsets, the
//! neighbours), four faces are crossed at once, without a branch per face (which side of a
//! face the ray goes is a coin toss, and was mispredicted half the time). The arithmetic of
//! each face is the scalar one, lane by lane, so every crossing is the same float.

use glam::{Vec3, Vec4};

/// No grain: the neighbour of a block's unused lanes (there are far fewer than 2³² grains).
pub(super) const NO_GRAIN: u32 = u32::MAX;

/// Four faces of one grain: the planes `q · m = c` (stretched space) it shares with the grains
/// `next`. Unused lanes have `m = 0`, `c = 0` (every point is behind them, no ray crosses
/// them) and `next = NO_GRAIN`.
#[derive(Clone, Copy, Debug)]
struct FaceBlock {
    mx: Vec4,
    my: Vec4,
    mz: Vec4,
    c: Vec4,
    next: [u32; 4],
}

impl FaceBlock {
    /// `q · m` in every lane, summed as [`Vec3::dot`] sums (x, then y, then z).
    #[inline]
    fn dot(&self, q: Vec3) -> Vec4 {
        Vec4::splat(q.x) * self.mx + Vec4::splat(q.y) * self.my + Vec4::splat(q.z) * self.mz
    }
}

/// One face, as [`Faces::new`] takes it: `q · m = c` shared with grain `next`.
#[derive(Clone, Copy, Debug)]
pub(super) struct Face {
    /// The plane's normal, `s_next − s_i` (stretched space).
    pub m: Vec3,
    /// The plane's offset.
    pub c: f32,
    /// The grain beyond it.
    pub next: u32,
}

/// Every grain's faces, in blocks of four: grain `i`'s are
/// `blocks[start[i]..start[i + 1]]`, in the order they were given.
#[derive(Clone, Debug, Default)]
pub(super) struct Faces {
    blocks: Vec<FaceBlock>,
    start: Vec<u32>,
}

impl Faces {
    /// The faces of every grain, grain by grain.
    pub fn new(per_grain: impl ExactSizeIterator<Item = Vec<Face>>) -> Faces {
        let mut faces = Faces {
            blocks: Vec::new(),
            start: Vec::with_capacity(per_grain.len() + 1),
        };
        faces.start.push(0);
        for list in per_grain {
            for chunk in list.chunks(4) {
                let lane = |k: usize| chunk.get(k).copied();
                let column = |f: fn(&Face) -> f32| {
                    Vec4::from_array(std::array::from_fn(|k| lane(k).map_or(0.0, |x| f(&x))))
                };
                faces.blocks.push(FaceBlock {
                    mx: column(|f| f.m.x),
                    my: column(|f| f.m.y),
                    mz: column(|f| f.m.z),
                    c: column(|f| f.c),
                    next: std::array::from_fn(|k| lane(k).map_or(NO_GRAIN, |f| f.next)),
                });
            }
            faces.start.push(faces.blocks.len() as u32);
        }
        faces
    }

    #[inline]
    fn of(&self, i: u32) -> &[FaceBlock] {
        let i = i as usize;
        &self.blocks[self.start[i] as usize..self.start[i + 1] as usize]
    }

    /// The grains sharing a face with grain `i`, in order.
    pub fn neighbours(&self, i: u32) -> impl Iterator<Item = u32> + '_ {
        self.of(i)
            .iter()
            .flat_map(|b| b.next)
            .filter(|&j| j != NO_GRAIN)
    }

    /// Whether `q` (stretched space) lies behind every face of grain `i` (`q · m ≤ c`).
    #[inline]
    pub fn holds(&self, i: u32, q: Vec3) -> bool {
        self.of(i).iter().all(|b| b.dot(q).cmple(b.c).all())
    }

    /// The first face of grain `i` that `o + t·d` (stretched space) crosses after `t`, before
    /// `t_max`: `(t, grain beyond)`, or `(t_max, None)`. Crossed first: the least
    /// `(c − o·m) / (d·m)` over the faces the ray moves towards (`d·m > 0`), the earliest face
    /// on a tie.
    #[inline]
    pub fn next_plane(&self, i: u32, o: Vec3, d: Vec3, t: f32, t_max: f32) -> (f32, Option<u32>) {
        let (t_min, mut best_t) = (Vec4::splat(t), Vec4::splat(t_max));
        // Per lane, the least crossing and its face's index (an f32: exact below 2²⁴).
        let mut best_k = Vec4::splat(f32::INFINITY);
        let mut k = Vec4::new(0.0, 1.0, 2.0, 3.0);
        for b in self.of(i) {
            let denom = b.dot(d);
            let tc = (b.c - b.dot(o)) / denom;
            let nearer = denom.cmpgt(Vec4::ZERO) & tc.cmpgt(t_min) & tc.cmplt(best_t);
            best_t = Vec4::select(nearer, tc, best_t);
            best_k = Vec4::select(nearer, k, best_k);
            k += Vec4::splat(4.0);
        }
        // The least over the lanes, the earliest face on a tie.
        let (ts, ks) = (best_t.to_array(), best_k.to_array());
        let mut lane = 0;
        for l in 1..4 {
            if ts[l] < ts[lane] || (ts[l] == ts[lane] && ks[l] < ks[lane]) {
                lane = l;
            }
        }
        if ks[lane] == f32::INFINITY {
            return (t_max, None);
        }
        let k = ks[lane] as usize;
        (ts[lane], Some(self.of(i)[k / 4].next[k % 4]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{stage, Rng};

    /// The crossing face by face, as a scalar loop finds it.
    fn next_plane_by_face(
        faces: &[Face],
        o: Vec3,
        d: Vec3,
        t: f32,
        t_max: f32,
    ) -> (f32, Option<u32>) {
        let mut next = (t_max, None);
        for f in faces {
            let denom = d.dot(f.m);
            if denom <= 0.0 {
                continue;
            }
            let tc = (f.c - o.dot(f.m)) / denom;
            if tc > t && tc < next.0 {
                next = (tc, Some(f.next));
            }
        }
        next
    }

    #[test]
    fn blocks_cross_and_hold_as_the_faces_one_by_one() {
        // Grains of 0 to 30 random faces, some repeated (ties: the earliest face wins), rays
        // from inside and outside them; every answer bit for bit the scalar one.
        let mut rng = Rng::new(1, stage::STRUCTURE, 95);
        let mut v = |s: f32| {
            Vec3::new(rng.uniform_f32(), rng.uniform_f32(), rng.uniform_f32()) * s
                - Vec3::splat(0.5 * s)
        };
        let grains: Vec<Vec<Face>> = (0..400u32)
            .map(|i| {
                let mut list: Vec<Face> = (0..i % 31)
                    .map(|k| Face {
                        m: v(2.0),
                        c: v(1.0).x,
                        next: 1000 + k,
                    })
                    .collect();
                if list.len() > 2 {
                    let copy = Face { next: 7, ..list[0] };
                    list.insert(list.len() / 2, copy);
                }
                list
            })
            .collect();
        let faces = Faces::new(grains.clone().into_iter());
        let (mut hits, mut held) = (0, 0);
        for (i, list) in grains.iter().enumerate() {
            for _ in 0..50 {
                let (o, d) = (v(1.0), v(2.0).normalize());
                let (t, t_max) = (v(0.2).x, 2.0);
                let found = faces.next_plane(i as u32, o, d, t, t_max);
                let expected = next_plane_by_face(list, o, d, t, t_max);
                assert_eq!(found.0.to_bits(), expected.0.to_bits(), "grain {i}");
                assert_eq!(found.1, expected.1, "grain {i}");
                hits += usize::from(found.1.is_some());
                let inside = list.iter().all(|f| o.dot(f.m) <= f.c);
                assert_eq!(faces.holds(i as u32, o), inside, "grain {i}");
                held += usize::from(inside);
            }
            let nexts: Vec<u32> = faces.neighbours(i as u32).collect();
            assert_eq!(nexts, list.iter().map(|f| f.next).collect::<Vec<_>>());
        }
        assert!(hits > 5000 && held > 500, "{hits} crossings, {held} held");
    }
}

//! Irregular domain outlines: input the domains' grains (a power diagram of convex cells) and
//! a roughness → output [`Outlines`]: a finer diagram of columns, each shifting the grains
//! by its own offset in the bedding plane.
//!
//! A power diagram's cells are convex polyhedra: seen through a colour bar of settled plates,
//! patches with straight edges and sharp corners, where the patches of real opal have ragged,
//! wandering edges (domains grow from many nuclei in the gel and meet along irregular grain
//! boundaries). Here the bedding plane is cut into columns [`OUTLINE_SUBDIVISION`] times
//! finer than the grains (and eight grains tall), and inside column `j` a point `p`
//! lies in the grain holding `p + δ_j`, the offset
//!
//! `δ_j = (a_x z_x(c_j), a_y z_y(c_j), 0)`, `a_i = roughness × (grain extent along i) / 2`,
//!
//! `c_j` the column's seed, `z_x`, `z_y` independent smooth fields of unit variance and
//! correlation length a quarter of the grain's extent in the plane ([`SizeField`]). The
//! outlines wander in the plane by about `roughness` half-widths, as runs of straight pieces a
//! sixth of a grain long; the offsets have no z part, so the plates stacked through a bar keep
//! their layering exactly, and a ray meets as many domains along the view as before. Walks stay
//! exact: the columns' walk, and in each column the grains' walk along the shifted ray.

use glam::Vec3;

use super::grains::Grains;
use super::size_field::SizeField;
use super::{Hint, Span};
use crate::geometry::Ray;
use crate::sampling::Rng;
use crate::scene::{COLUMN_HEIGHT, OUTLINE_SUBDIVISION};

/// The displacement field's correlation length, as a fraction of the grain's extent in the
/// bedding plane.
const CORRELATION_PER_EXTENT: f32 = 0.25;

/// The columns that make the grains' outlines ragged, and their offsets.
#[derive(Clone, Debug)]
pub struct Outlines {
    columns: Grains,
    /// Per column, the offset its points are moved by before the grains are asked, mm.
    shift: Vec<Vec3>,
}

impl Outlines {
    /// Columns over the box `[−half, half]` (mm) for grains of mean size `size_mm` stretched
    /// by `stretch`, for outlines of `roughness` (> 0; see the module). Draws from `rng`.
    pub fn new(half: Vec3, size_mm: f32, stretch: Vec3, roughness: f32, rng: &mut Rng) -> Self {
        // A grain of size s stretched by (a, b, c) spans about (sa, sb, sc); a column spans
        // (sa/k, sb/k, sc h): size s (h/k²)^(1/3), stretch (a/k, b/k, c h) × s / size.
        let k = OUTLINE_SUBDIVISION;
        let cuts = Vec3::new(k, k, 1.0 / COLUMN_HEIGHT);
        let size = size_mm * (cuts.x * cuts.y * cuts.z).powf(-1.0 / 3.0);
        let column_stretch = stretch / cuts * (size_mm / size);
        let columns = Grains::new(half, size, 0.0, column_stretch, rng);
        let extent = stretch * size_mm;
        let length = (CORRELATION_PER_EXTENT * extent.x.min(extent.y)).max(1e-3);
        let fx = SizeField::new(f64::from(length), rng);
        let fy = SizeField::new(f64::from(length), rng);
        let amplitude = 0.5 * roughness * extent;
        let shift = columns
            .seeds
            .iter()
            .map(|&s| {
                let c = s * column_stretch;
                Vec3::new(amplitude.x * fx.at(c), amplitude.y * fy.at(c), 0.0)
            })
            .collect();
        Outlines { columns, shift }
    }

    /// The grain of `grains` holding `p` (mm) through the outlines.
    pub fn grain_at(&self, grains: &Grains, p: Vec3) -> u32 {
        let j = self.columns.at(p) as usize;
        grains.at(p + self.shift[j])
    }

    /// Call `visit` for the grains of `grains` along `ray.at(t)`, `t ∈ [t0, t1]` (mm), in
    /// order, through the outlines (a grain met in two columns in a row is visited twice).
    /// `hint`: the column and grain likely to hold the start. Each span's hint names its
    /// column.
    pub fn walk(
        &self,
        grains: &Grains,
        ray: &Ray,
        t0: f32,
        t1: f32,
        hint: Hint,
        mut visit: impl FnMut(Span, u32) -> bool,
    ) -> bool {
        let (origin, dir) = (ray.origin, ray.direction);
        // The grain a column's walk ended in most often holds the next column's start too (the
        // shifts are alike from column to column): it is tried first.
        let mut grain = hint.grain;
        self.columns.walk(
            origin,
            dir,
            t0,
            t1,
            hint.column,
            |column_span: Span, column| {
                let shifted = origin + self.shift[column as usize];
                grains.walk(
                    shifted,
                    dir,
                    column_span.t0,
                    column_span.t1,
                    grain,
                    |span, g| {
                        grain = Some(g);
                        let hint = Hint {
                            column: Some(column),
                            ..span.hint
                        };
                        visit(Span { hint, ..span }, g)
                    },
                )
            },
        )
    }
}

#[cfg(test)]
mod tests {
    use crate::sampling::{stage, Rng};
    use crate::scene::{OrientationLaw, Pattern, Scene};
    use crate::stone::{Hint, Span, Stone};
    use glam::Vec3;

    /// Settled plates as the gem presets have them, no potch grains, outlines of `roughness`.
    fn plates(roughness: f64) -> Stone {
        let mut scene = Scene::default();
        scene.domains.pattern = Pattern::Grains;
        scene.domains.stretch = [2.5, 2.5, 0.12];
        scene.domains.orientation = OrientationLaw::Settled;
        scene.domains.void_fraction = 0.0;
        scene.domains.boundary_roughness = roughness;
        Stone::new(&scene).unwrap()
    }

    /// Pairs of points in the plane z = 0 (inside the stone), `r` mm apart in a random
    /// direction of the plane: how many lie in one domain, and of those how many have their
    /// midpoint in another.
    fn pairs(stone: &Stone, r: f32) -> (usize, usize, usize) {
        let mut rng = Rng::new(7, stage::STONE, 99);
        let (mut total, mut same, mut broken) = (0, 0, 0);
        while total < 20_000 {
            let p = Vec3::new(
                (rng.uniform_f32() - 0.5) * 14.0,
                (rng.uniform_f32() - 0.5) * 10.0,
                0.0,
            );
            let phi = std::f32::consts::TAU * rng.uniform_f32();
            let q = p + Vec3::new(phi.cos(), phi.sin(), 0.0) * r;
            let (Some(a), Some(b)) = (stone.domain_at(p), stone.domain_at(q)) else {
                continue;
            };
            total += 1;
            if a == b {
                same += 1;
                if stone.domain_at((p + q) * 0.5) != Some(a) {
                    broken += 1;
                }
            }
        }
        (total, same, broken)
    }

    #[test]
    fn ragged_outlines_are_not_convex() {
        // Convex grains hold the midpoint of any two of their points; ragged clusters of
        // cells often do not.
        let (_, same, broken) = pairs(&plates(0.0), 2.0);
        assert_eq!(broken, 0, "{broken} of {same}");
        let (_, same, broken) = pairs(&plates(0.5), 2.0);
        assert!(broken as f64 > 0.03 * same as f64, "{broken} of {same}");
    }

    #[test]
    fn ragged_outlines_keep_the_patch_size() {
        // The chance that two points of the bedding plane r apart lie in one domain: at half a
        // grain's width (2.5 mm) the patches' size, as the straight-edged grains'; at 1 mm the
        // wandering edges part a few more pairs.
        let (smooth, rough) = (plates(0.0), plates(0.5));
        let share = |stone: &Stone, r: f32| {
            let (total, same, _) = pairs(stone, r);
            same as f64 / total as f64
        };
        let (a, b) = (share(&smooth, 2.5), share(&rough, 2.5));
        assert!((a - b).abs() < 0.05, "2.5 mm: {a} → {b}");
        let (a, b) = (share(&smooth, 1.0), share(&rough, 1.0));
        assert!(b > 0.8 * a && b < a, "1 mm: {a} → {b}");
    }

    /// A ray from a random point of the middle of the stone, in a random direction.
    fn random_ray(rng: &mut Rng) -> (Vec3, Vec3) {
        let origin = Vec3::new(
            (rng.uniform_f32() - 0.5) * 12.0,
            (rng.uniform_f32() - 0.5) * 8.0,
            (rng.uniform_f32() - 0.5) * 2.0,
        );
        let dir = Vec3::new(
            rng.uniform_f32() - 0.5,
            rng.uniform_f32() - 0.5,
            rng.uniform_f32() - 0.5,
        )
        .normalize();
        (origin, dir)
    }

    /// Over random segments, the share of length whose walked domain differs from the point
    /// query's at the span's middle (the power diagram's walk may miss a tiny face, `grains`).
    fn walk_mismatch(stone: &Stone) -> f64 {
        let mut rng = Rng::new(3, stage::STONE, 98);
        let (mut total, mut wrong) = (0.0f64, 0.0f64);
        for _ in 0..400 {
            let (origin, dir) = random_ray(&mut rng);
            let mut spans = Vec::new();
            stone.walk(origin, dir, 0.0, 1.5, Hint::default(), &mut |s| {
                spans.push(s);
                true
            });
            let mut t = 0.0;
            for s in &spans {
                assert!((s.t0 - t).abs() < 1e-4, "gap at {t}");
                t = s.t1;
                let inside = |t: f32| stone.shape.contains(origin + dir * t);
                if inside(s.t0) && inside(s.t1) {
                    let length = f64::from(s.t1 - s.t0);
                    total += length;
                    let mid = origin + dir * (0.5 * (s.t0 + s.t1));
                    if stone.domain_at(mid) != s.domain {
                        wrong += length;
                    }
                }
            }
            assert!((t - 1.5).abs() < 1e-4);
        }
        wrong / total
    }

    #[test]
    fn a_walk_from_a_spans_cells_finds_what_a_walk_without_them_finds() {
        // A walk's spans name the cells (column, grain) their start lies in; a later walk from
        // there (a reflection, a scattering, light estimated) starts from them. It must cross
        // the same domains at the same places as a walk that looks its start up, but where a
        // hinted grain claims a sliver beyond a face its rays missed, as a walk does (6 of
        // 1806 walks, measured).
        let stone = plates(0.4);
        let mut rng = Rng::new(5, stage::STONE, 97);
        let (mut walks, mut differ) = (0, 0);
        let walk = |origin: Vec3, dir: Vec3, t0: f32, hint: Hint| {
            let mut spans: Vec<Span> = Vec::new();
            let end = stone.walk(origin, dir, t0, 2.0, hint, &mut |s| {
                spans.push(s);
                true
            });
            let key: Vec<_> = spans.iter().map(|s| (s.domain, s.t1)).collect();
            (spans, key, end)
        };
        for _ in 0..200 {
            let (origin, dir) = random_ray(&mut rng);
            let (spans, _, end) = walk(origin, dir, 0.0, Hint::default());
            assert!(end.column.is_some() && end.grain.is_some());
            for s in spans.iter().filter(|s| s.t1 - s.t0 > 1e-3) {
                assert!(s.hint.column.is_some() && s.hint.grain.is_some());
                // From a point inside the span, away from its faces.
                let t = 0.5 * (s.t0 + s.t1);
                let (_, with, _) = walk(origin, dir, t, s.hint);
                let (_, without, _) = walk(origin, dir, t, Hint::default());
                walks += 1;
                differ += usize::from(with != without);
            }
        }
        assert!(walks > 1000, "{walks} walks");
        assert!(differ * 100 <= walks, "{differ} of {walks} walks differ");
    }

    #[test]
    fn walks_through_ragged_outlines_agree_with_point_queries() {
        // The spans tile the segment and lie in the domains point queries see, but for the
        // corners the grains' own walk may cut (1.1 % of the length without the outlines,
        // 0.8 % with them, measured).
        let (smooth, rough) = (walk_mismatch(&plates(0.0)), walk_mismatch(&plates(0.5)));
        assert!(
            rough < 0.02 && rough < 2.0 * smooth + 0.002,
            "{smooth} → {rough}"
        );
    }
}

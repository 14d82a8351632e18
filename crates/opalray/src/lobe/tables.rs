//! The set-up's tables of light: the environment's irradiance over normals, and the light
//! reaching a backing through the stone, read bilinearly by the tracer.

use super::*;
use rayon::prelude::*;

/// Rows (polar angle) and columns (azimuth) of the irradiance table.
const IRRADIANCE_GRID: (usize, usize) = (33, 64);
/// Rows of the quadrature over the environment (twice as many columns).
const QUADRATURE_ROWS: usize = 48;

/// The environment's cosine-weighted mean over the hemisphere about every normal,
/// `Ē(n) = (1/π) ∫ L(ω) max(0, n·ω) dω` in the environment's units (a white diffuser facing
/// `n` shows Ē), tabulated over the normal's polar angle and azimuth in the stone's frame and
/// read bilinearly. The quadrature reads the environment through lobes of its own spacing.
pub struct Irradiance {
    values: Vec<f32>,
}

impl Irradiance {
    /// The table of `environment`.
    pub fn new(environment: &Environment) -> Self {
        let rows = QUADRATURE_ROWS;
        let cols = 2 * rows;
        let spacing = PI / rows as f32;
        let mut dirs = Vec::with_capacity(rows * cols);
        for i in 0..rows {
            let theta = (i as f32 + 0.5) * spacing;
            let solid = spacing * spacing * theta.sin();
            for j in 0..cols {
                let phi = (j as f32 + 0.5) * spacing;
                let d = polar(theta, phi);
                dirs.push((d, environment.filtered(d, 0.5 * spacing) * solid));
            }
        }
        let (n_rows, n_cols) = IRRADIANCE_GRID;
        let mut values = vec![0.0f32; n_rows * n_cols];
        values
            .par_chunks_mut(n_cols)
            .enumerate()
            .for_each(|(i, row)| {
                let theta = PI * i as f32 / (n_rows - 1) as f32;
                for (j, v) in row.iter_mut().enumerate() {
                    let n = polar(theta, 2.0 * PI * j as f32 / n_cols as f32);
                    let sum: f64 = dirs
                        .iter()
                        .map(|&(d, l)| f64::from(l * n.dot(d).max(0.0)))
                        .sum();
                    *v = (sum / std::f64::consts::PI) as f32;
                }
            });
        Irradiance { values }
    }

    /// The largest `Ē` in the table.
    pub fn peak(&self) -> f32 {
        self.values.iter().fold(0.0, |m, &v| m.max(v))
    }

    /// `Ē(n)` for the unit normal `n` (the stone's frame).
    pub fn at(&self, n: Vec3) -> f32 {
        let (rows, cols) = IRRADIANCE_GRID;
        let theta = n.z.clamp(-1.0, 1.0).acos();
        let phi = n.y.atan2(n.x).rem_euclid(2.0 * PI);
        let y = theta / PI * (rows - 1) as f32;
        let x = phi / (2.0 * PI) * cols as f32;
        let (i, j) = ((y as usize).min(rows - 2), x as usize % cols);
        let (fy, fx) = (y - i as f32, x - x.floor());
        let j1 = (j + 1) % cols;
        let v = |r: usize, c: usize| self.values[r * cols + c];
        let top = v(i, j) * (1.0 - fx) + v(i, j1) * fx;
        let bottom = v(i + 1, j) * (1.0 - fx) + v(i + 1, j1) * fx;
        top * (1.0 - fy) + bottom * fy
    }
}

/// Points of the back plane, across and along, at which the light reaching the backing is
/// computed.
pub(super) const BACKING_GRID: (usize, usize) = (48, 36);

/// The light reaching the backing through the stone (`Tracer::light_on_backing`): tabulated
/// over the back plane on a grid spanning the girdle and read bilinearly (the points no read
/// inside the girdle weighs in are left 0, [`read_points`]).
pub(crate) struct BackingLight {
    half: (f32, f32),
    values: Vec<f32>,
}

impl BackingLight {
    /// The table of `stone` lit as `setup` says; `None` without a backing.
    pub(super) fn new(
        stone: &Stone,
        setup: &LobeSetup,
        colours: &LineColours,
        irradiance: &Irradiance,
    ) -> Option<Self> {
        stone.back?;
        let axes = stone.shape.semi_axes();
        let half = (axes.x, axes.y);
        let values = fill_table(
            BACKING_GRID,
            || trace::Tracer::new(stone, setup, colours, irradiance, trace::Lit::default()),
            |tracer, i, j| {
                let (x, y) = grid_point(half, i, j);
                // Inside the girdle (a point outside it is moved in: the edge's cells are
                // read by the pixels just inside it).
                let r = ((x / half.0).powi(2) + (y / half.1).powi(2)).sqrt();
                let pull = if r > 0.98 { 0.98 / r } else { 1.0 };
                let up = crate::geometry::Ray {
                    origin: Vec3::new(x * pull, y * pull, -1e3),
                    direction: Vec3::Z,
                };
                stone
                    .shape
                    .intersect(&up)
                    .map_or(0.0, |(t0, _)| tracer.light_on_backing(up.at(t0)))
            },
        );
        Some(BackingLight { half, values })
    }

    /// The light at `at` (on the back plane).
    pub(super) fn at(&self, at: Vec3) -> f32 {
        bilinear(
            &self.values,
            BACKING_GRID,
            at.x / self.half.0,
            at.y / self.half.1,
        )
    }
}

/// Radius (in the table's `[−1, 1]²`) within which a table over an elliptic footprint is
/// read: the footprint's edge, 1 (the potch under a bar is read inside its inner surface,
/// `|q| ≤ √1.001`; the backing inside the girdle, up to the exit's 10⁻⁴ mm), and a margin.
pub(super) const READ_RADIUS: f32 = 1.01;

/// Per point of a `grid.0 × grid.1` table over `[−1, 1]²` (row-major, x fastest), whether
/// [`bilinear`] can read it at a point within `radius` of the centre: a point all of whose
/// cells lie wholly outside that disc weighs in no read, and is left 0, not computed.
pub(super) fn read_points(grid: (usize, usize), radius: f32) -> Vec<bool> {
    let (nx, ny) = grid;
    let edge = |k: usize, n: usize| 2.0 * k as f32 / (n - 1) as f32 - 1.0;
    // The distance from 0 to the nearest point of [a, b].
    let gap = |a: f32, b: f32| a.max(0.0).max(-b);
    let mut read = vec![false; nx * ny];
    for j in 0..ny - 1 {
        let dy = gap(edge(j, ny), edge(j + 1, ny));
        for i in 0..nx - 1 {
            let dx = gap(edge(i, nx), edge(i + 1, nx));
            if dx * dx + dy * dy <= radius * radius {
                for (a, b) in [(i, j), (i + 1, j), (i, j + 1), (i + 1, j + 1)] {
                    read[b * nx + a] = true;
                }
            }
        }
    }
    read
}

/// A table over `grid` (row-major, x fastest) whose point `(i, j)` is `value(tracer, i, j)`,
/// rows in parallel (each with its own tracer from `tracer`); the points no read inside the
/// footprint reaches ([`read_points`]) are left at the value's default (0).
pub(super) fn fill_table<T, V: Copy + Default + Send>(
    grid: (usize, usize),
    tracer: impl Fn() -> T + Sync,
    value: impl Fn(&mut T, usize, usize) -> V + Sync,
) -> Vec<V> {
    let (nx, ny) = grid;
    let read = read_points(grid, READ_RADIUS);
    let mut values = vec![V::default(); nx * ny];
    // A stopped render fills no more rows (its table is never read).
    let cancel = crate::cancel::Cancel::current();
    values.par_chunks_mut(nx).enumerate().for_each(|(j, row)| {
        if cancel.is_cancelled() {
            return;
        }
        let mut t = tracer();
        for (i, v) in row.iter_mut().enumerate() {
            if read[j * nx + i] {
                *v = value(&mut t, i, j);
            }
        }
    });
    values
}

/// A table of `grid.0 × grid.1` values over `[−1, 1]²` (row-major, x fastest) read
/// bilinearly at `(u, v)`, clamped to its edges.
pub(super) fn bilinear(values: &[f32], grid: (usize, usize), u: f32, v: f32) -> f32 {
    let (nx, ny) = grid;
    let fx = ((u + 1.0) * 0.5 * (nx - 1) as f32).clamp(0.0, (nx - 1) as f32);
    let fy = ((v + 1.0) * 0.5 * (ny - 1) as f32).clamp(0.0, (ny - 1) as f32);
    let (i, j) = ((fx as usize).min(nx - 2), (fy as usize).min(ny - 2));
    let (tx, ty) = (fx - i as f32, fy - j as f32);
    let at = |i: usize, j: usize| values[j * nx + i];
    let low = at(i, j) * (1.0 - tx) + at(i + 1, j) * tx;
    let high = at(i, j + 1) * (1.0 - tx) + at(i + 1, j + 1) * tx;
    low * (1.0 - ty) + high * ty
}

/// The back plane's grid point `(i, j)` over `[−a, a] × [−b, b]`, `half = (a, b)`.
pub(super) fn grid_point(half: (f32, f32), i: usize, j: usize) -> (f32, f32) {
    let (nx, ny) = BACKING_GRID;
    (
        half.0 * (2.0 * i as f32 / (nx - 1) as f32 - 1.0),
        half.1 * (2.0 * j as f32 / (ny - 1) as f32 - 1.0),
    )
}

/// The unit vector at polar angle `theta` from +z and azimuth `phi` from +x.
pub(super) fn polar(theta: f32, phi: f32) -> Vec3 {
    let (s, c) = theta.sin_cos();
    Vec3::new(s * phi.cos(), s * phi.sin(), c)
}

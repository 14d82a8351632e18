//! Piecewise-constant distributions over an interval and over the unit square (pbrt-v4
//! §A.1 and §A.5): sampling by inversion of the cumulative sums, a marginal over rows and a
//! conditional over each row's columns.

/// A piecewise-constant density over `[0, 1)` with `n` equal cells of weight `w[i] ≥ 0`.
#[derive(Clone, Debug)]
pub struct Distribution1D {
    /// Cumulative sums normalised to end at 1: `cdf[0] = 0`, `cdf[n] = 1`, `n + 1` values
    /// (f64: a cell of a bright map's dark side keeps its small probability).
    cdf: Vec<f64>,
    /// The sum of the weights over `n` (the mean weight: the integral of the step function).
    integral: f64,
}

impl Distribution1D {
    /// The distribution of `weights` (non-negative; all zero gives the uniform one).
    pub fn new(weights: &[f32]) -> Self {
        let n = weights.len().max(1);
        let mut cdf = Vec::with_capacity(n + 1);
        cdf.push(0.0f64);
        let mut sum = 0.0f64;
        let mut running = Vec::with_capacity(n);
        for &w in weights {
            sum += f64::from(w.max(0.0));
            running.push(sum);
        }
        if sum > 0.0 {
            cdf.extend(running.iter().map(|&s| s / sum));
        } else {
            cdf.extend((1..=n).map(|i| i as f64 / n as f64));
        }
        cdf[n] = 1.0;
        Distribution1D {
            cdf,
            integral: sum / n as f64,
        }
    }

    /// Number of cells.
    pub fn len(&self) -> usize {
        self.cdf.len() - 1
    }

    /// Whether there are no cells (never: an empty weight list gives one cell).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The mean weight (the integral of the step function over `[0, 1)`).
    pub fn integral(&self) -> f64 {
        self.integral
    }

    /// Probability of cell `i`.
    pub fn probability(&self, i: usize) -> f64 {
        self.cdf[i + 1] - self.cdf[i]
    }

    /// Draw with `u ∈ [0, 1)`: `(x ∈ [0, 1), cell)`; `x`'s density is `n × probability(cell)`.
    pub fn sample(&self, u: f64) -> (f64, usize) {
        let n = self.len();
        // The last cell whose start is ≤ u, skipping cells of zero probability.
        let i = self.cdf.partition_point(|&c| c <= u).clamp(1, n) - 1;
        let p = self.probability(i);
        let within = if p > 0.0 {
            ((u - self.cdf[i]) / p).clamp(0.0, 1.0)
        } else {
            0.5
        };
        let x = ((i as f64 + within) / n as f64).min(1.0 - f64::EPSILON);
        (x, i)
    }
}

/// A piecewise-constant density over the unit square `[0, 1)²` of `width × height` cells,
/// `weights` row-major: a marginal over rows (`v`), a conditional over columns (`u`) in each.
#[derive(Clone, Debug)]
pub struct Distribution2D {
    width: usize,
    height: usize,
    rows: Vec<Distribution1D>,
    marginal: Distribution1D,
}

impl Distribution2D {
    /// The distribution of `weights` (`width × height`, row-major, non-negative).
    pub fn new(weights: &[f32], width: usize, height: usize) -> Self {
        assert_eq!(
            weights.len(),
            width * height,
            "weights must be width × height"
        );
        let rows: Vec<Distribution1D> = weights.chunks(width).map(Distribution1D::new).collect();
        let row_weights: Vec<f32> = rows.iter().map(|r| r.integral() as f32).collect();
        let marginal = Distribution1D::new(&row_weights);
        Distribution2D {
            width,
            height,
            rows,
            marginal,
        }
    }

    /// Cells per row and rows.
    pub fn size(&self) -> (usize, usize) {
        (self.width, self.height)
    }

    /// Draw a point with `u ∈ [0, 1)²`: `((x, y), density over the unit square)`.
    pub fn sample(&self, u: [f64; 2]) -> ([f64; 2], f64) {
        let (y, row) = self.marginal.sample(u[1]);
        let (x, column) = self.rows[row].sample(u[0]);
        ([x, y], self.cell_density(column, row))
    }

    /// The density over the unit square at `(x, y)`.
    pub fn density(&self, x: f64, y: f64) -> f64 {
        let column = ((x * self.width as f64).max(0.0) as usize).min(self.width - 1);
        let row = ((y * self.height as f64).max(0.0) as usize).min(self.height - 1);
        self.cell_density(column, row)
    }

    fn cell_density(&self, column: usize, row: usize) -> f64 {
        self.marginal.probability(row)
            * self.rows[row].probability(column)
            * (self.width * self.height) as f64
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::Rng;

    #[test]
    fn cells_are_drawn_in_proportion_to_their_weights() {
        let weights = [1.0, 0.0, 3.0, 4.0];
        let d = Distribution1D::new(&weights);
        let mut counts = [0u32; 4];
        let mut rng = Rng::new(1, 0, 0);
        let n = 80_000;
        for _ in 0..n {
            let (x, i) = d.sample(rng.uniform());
            assert_eq!((x * 4.0) as usize, i, "x lies in its cell");
            counts[i] += 1;
        }
        for (c, w) in counts.iter().zip(weights) {
            let p = w / 8.0;
            let expected = p * n as f32;
            // Five binomial standard deviations.
            let sd = (n as f32 * p * (1.0 - p)).sqrt();
            assert!((*c as f32 - expected).abs() <= 5.0 * sd + 1.0, "{counts:?}");
        }
        assert_eq!(counts[1], 0, "a cell of weight 0 is never drawn");
    }

    #[test]
    fn the_2d_density_integrates_to_one_and_matches_the_sample() {
        let (w, h) = (7, 5);
        let weights: Vec<f32> = (0..w * h).map(|i| ((i * 37) % 11) as f32).collect();
        let d = Distribution2D::new(&weights, w, h);
        // Midpoint rule over each cell: exact for a step function.
        let mut total = 0.0;
        for y in 0..h {
            for x in 0..w {
                total += d.density((x as f64 + 0.5) / w as f64, (y as f64 + 0.5) / h as f64);
            }
        }
        assert!((total / (w * h) as f64 - 1.0).abs() < 1e-9, "{total}");
        let mut rng = Rng::new(2, 0, 0);
        for _ in 0..1000 {
            let ([x, y], p) = d.sample([rng.uniform(), rng.uniform()]);
            assert!(p > 0.0);
            assert!((d.density(x, y) - p).abs() <= 1e-9 * p, "{x} {y}");
        }
    }
}

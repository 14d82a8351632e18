//! Fine wavelength sampling of one table row and its integration into the spectral bins.
//!
//! Input: a [`ClusterStack`] at one angle and the scene's [`WavelengthGrid`] → output: the
//! bin averages of R and T. Opal's Bragg lines are only a few nm wide, with side lobes
//! `λ/N` apart (≈ 1.5 nm at N = 400), so even a 1 nm grid does not resolve them. The row is
//! sampled on a base grid of at most [`BASE_STEP_NM`] whose nodes include every bin edge,
//! and each base interval near a Bragg order is subdivided so that the line and its side
//! lobes get [`SAMPLES_PER_FEATURE`] samples each. The samples are joined linearly and
//! integrated exactly over each bin (the trapezoid rule), as
//! [`WavelengthGrid::bin_average`] does.

use super::dispersion::CrystalIndex;
use super::fcc::ClusterStack;
use crate::spectrum::WavelengthGrid;

/// Largest step of the base grid, nm (the requirement "evaluated on ≤ 1 nm").
pub const BASE_STEP_NM: f64 = 1.0;
/// Samples across the narrower of a stop band and a side-lobe period in the core window.
pub const SAMPLES_PER_FEATURE: f64 = 10.0;
/// Side lobes on each side of a stop band in the core window.
const CORE_LOBES: f64 = 10.0;
/// Samples per side-lobe period in the skirt window.
const SAMPLES_PER_SKIRT_LOBE: f64 = 4.0;
/// Side lobes on each side of a stop band in the skirt window: the side-lobe envelope
/// falls as 1/k², and beyond 50 lobes its bin-average error at 1 nm sampling is < 1e-3.
const SKIRT_LOBES: f64 = 50.0;
/// Most subdivisions of one base interval (finest step 1/32 nm at the default grid).
const MAX_SUBDIVISIONS: usize = 32;
/// Most Bragg orders refined per row (orders beyond fall in the ultraviolet for any
/// diameter whose first order is visible).
const MAX_ORDERS: usize = 16;
/// Relative stop-band width is capped here: past it the band is broad and needs no
/// refinement (grazing rows, where it widens as 1/cos²θ).
const MAX_RELATIVE_GAP: f64 = 0.5;

/// A wavelength interval refined with a given number of subdivisions per base interval.
#[derive(Clone, Copy, Debug, Default)]
struct Window {
    lo_nm: f64,
    hi_nm: f64,
    subdivisions: usize,
}

/// Where one row needs samples finer than the base grid.
#[derive(Clone, Copy, Debug)]
pub struct RowPlan {
    windows: [Window; 2 * MAX_ORDERS],
    count: usize,
}

impl RowPlan {
    /// The refinement windows for `stack` at `cos_theta` inside, over `grid`.
    ///
    /// Order m of the square-wave period sits at `λ₁/m` with a relative width
    /// `≈ ε₁₁₁ / (m ε̄ cos²θ)` (odd m; even orders vanish for equal layer thicknesses) and
    /// side lobes `λ_m / (m N)` apart. Each order gets a core window (the band and ten side
    /// lobes, finely sampled) and a wider skirt (fifty side lobes, four samples each). With
    /// the dispersion of `index`, each order's centre is where `λ = 2 d n̄(λ) cos θ / m`.
    pub fn new(
        stack: &ClusterStack,
        index: &CrystalIndex,
        cos_theta: f64,
        grid: &WavelengthGrid,
    ) -> RowPlan {
        let mut plan = RowPlan {
            windows: [Window::default(); 2 * MAX_ORDERS],
            count: 0,
        };
        let lambda_1 = stack.bragg_wavelength_nm(cos_theta);
        let gap_1 = (stack.relative_gap() / (cos_theta * cos_theta)).min(MAX_RELATIVE_GAP);
        let periods = f64::from(stack.periods);
        for order in (1..2 * MAX_ORDERS as u32).step_by(2) {
            let m = f64::from(order);
            let centre = index.line(lambda_1 / m).centre_nm;
            let gap = gap_1 / m;
            let lobe = 1.0 / (m * periods);
            plan.push(
                grid,
                centre,
                centre * (gap + CORE_LOBES * lobe),
                centre * gap.min(lobe) / SAMPLES_PER_FEATURE,
            );
            plan.push(
                grid,
                centre,
                centre * (gap + SKIRT_LOBES * lobe),
                centre * lobe / SAMPLES_PER_SKIRT_LOBE,
            );
        }
        plan
    }

    /// Add the window `centre ± half_width` sampled at `step` if it overlaps the grid and
    /// needs more than the base grid.
    fn push(&mut self, grid: &WavelengthGrid, centre: f64, half_width: f64, step: f64) {
        let subdivisions = (base_step_nm(grid) / step)
            .ceil()
            .clamp(1.0, MAX_SUBDIVISIONS as f64);
        let overlaps = centre + half_width > grid.min_nm && centre - half_width < grid.max_nm;
        if overlaps && subdivisions > 1.0 && self.count < self.windows.len() {
            self.windows[self.count] = Window {
                lo_nm: centre - half_width,
                hi_nm: centre + half_width,
                subdivisions: subdivisions as usize,
            };
            self.count += 1;
        }
    }

    /// Subdivisions of the base interval `[x0, x1]`: the finest of the windows it overlaps.
    #[inline]
    fn subdivisions(&self, x0: f64, x1: f64) -> usize {
        self.windows[..self.count]
            .iter()
            .filter(|w| x1 > w.lo_nm && x0 < w.hi_nm)
            .map(|w| w.subdivisions)
            .max()
            .unwrap_or(1)
    }
}

/// Base grid step for `grid`: the bin width divided into whole steps of at most
/// [`BASE_STEP_NM`], so every bin edge is a node.
pub fn base_step_nm(grid: &WavelengthGrid) -> f64 {
    grid.bin_width_nm() / steps_per_bin(grid) as f64
}

fn steps_per_bin(grid: &WavelengthGrid) -> usize {
    ((grid.bin_width_nm() / BASE_STEP_NM).ceil() as usize).max(1)
}

/// Bin averages of the two functions `eval(λ) = (R, T)` over `grid`, sampled as `plan` says
/// and integrated by the trapezoid rule. `r_avg` and `t_avg` have `grid.bins` entries.
pub fn integrate_bins(
    grid: &WavelengthGrid,
    plan: &RowPlan,
    mut eval: impl FnMut(f64) -> (f64, f64),
    r_avg: &mut [f64],
    t_avg: &mut [f64],
) {
    let per_bin = steps_per_bin(grid);
    let step = base_step_nm(grid);
    let node = |k: usize| grid.min_nm + k as f64 * step;
    let mut x_prev = grid.min_nm;
    let (mut r_prev, mut t_prev) = eval(x_prev);
    for (bin, (r_out, t_out)) in r_avg.iter_mut().zip(t_avg.iter_mut()).enumerate() {
        let (mut r_sum, mut t_sum) = (0.0, 0.0);
        for j in 0..per_bin {
            let k = bin * per_bin + j;
            let (x0, x1) = (node(k), node(k + 1));
            let m = plan.subdivisions(x0, x1);
            for s in 1..=m {
                let x = if s == m {
                    x1
                } else {
                    x0 + (x1 - x0) * s as f64 / m as f64
                };
                let (r, t) = eval(x);
                let dx = x - x_prev;
                r_sum += 0.5 * (r_prev + r) * dx;
                t_sum += 0.5 * (t_prev + t) * dx;
                (x_prev, r_prev, t_prev) = (x, r, t);
            }
        }
        let width = node((bin + 1) * per_bin) - node(bin * per_bin);
        *r_out = r_sum / width;
        *t_out = t_sum / width;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::CrystalConfig;

    #[test]
    fn default_normal_incidence_row_refines_the_bragg_line() {
        let stack = ClusterStack::new(&CrystalConfig::default()).unwrap();
        let grid = WavelengthGrid::default();
        let index = CrystalIndex::new(&CrystalConfig::default());
        let plan = RowPlan::new(&stack, &index, 1.0, &grid);
        let lambda = stack.bragg_wavelength_nm(1.0);
        assert!(plan.subdivisions(lambda.floor(), lambda.floor() + 1.0) >= 5);
        assert_eq!(plan.subdivisions(400.0, 401.0), 1);
    }

    #[test]
    fn integration_of_a_line_is_exact_for_linear_functions() {
        let stack = ClusterStack::new(&CrystalConfig::default()).unwrap();
        let grid = WavelengthGrid::new(400.0, 700.0, 7).unwrap();
        let index = CrystalIndex::new(&CrystalConfig::default());
        let plan = RowPlan::new(&stack, &index, 0.9, &grid);
        let (mut r, mut t) = (vec![0.0; 7], vec![0.0; 7]);
        integrate_bins(&grid, &plan, |x| (2.0 * x, 1.0), &mut r, &mut t);
        for i in 0..7 {
            assert!(
                (r[i] - 2.0 * grid.center_nm(i)).abs() < 1e-9,
                "{i}: {}",
                r[i]
            );
            assert!((t[i] - 1.0).abs() < 1e-12);
        }
    }
}

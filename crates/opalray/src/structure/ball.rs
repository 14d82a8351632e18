//! The neighbourhood of a growth step (paper §2.4, step 4): every cell whose centre lies
//! within `r` cells of the selected cell's centre, i.e. the integer offsets `(dx, dy, dz)`
//! with `dx² + dy² + dz² ≤ r²`, clipped to the grid.
//!
//! Distances are measured in cell edges (the paper gives `R` in cells), so on a grid of
//! non-cubic cells the neighbourhood is an ellipsoid in millimetres. The ball is visited row
//! by row (fixed y and z, a contiguous x range), which touches memory in order and needs no
//! table of offsets, whatever the radius.

use std::ops::Range;

/// Largest integer `m ≥ 0` with `m² ≤ value` (`value ≥ 0`), exact for the squared integer
/// offsets used here.
fn floor_sqrt(value: f64) -> i64 {
    let mut m = value.sqrt().floor() as i64;
    while ((m + 1) * (m + 1)) as f64 <= value {
        m += 1;
    }
    while m > 0 && (m * m) as f64 > value {
        m -= 1;
    }
    m
}

/// Clip the offsets `−half ..= half` around `centre` to `0 .. n` as absolute indices.
fn clip(centre: usize, half: i64, n: usize) -> Range<usize> {
    let centre = centre as i64;
    let lo = (centre - half).max(0);
    let hi = (centre + half + 1).min(n as i64);
    if lo >= hi {
        0..0
    } else {
        lo as usize..hi as usize
    }
}

/// Visit the cells within `radius_cells` of `centre` (centre to centre, in cell edges) on a
/// grid of `grid = [nx, ny, nz]` cells: `visit(y, z, xs)` is called once per row that holds
/// any, in increasing z then y, with the x range of the row. A radius below 1 gives the
/// centre cell alone; a radius larger than the grid is clipped to it.
pub fn for_each_row(
    grid: [usize; 3],
    centre: [usize; 3],
    radius_cells: f64,
    mut visit: impl FnMut(usize, usize, Range<usize>),
) {
    debug_assert!(radius_cells >= 0.0 && centre.iter().zip(&grid).all(|(c, n)| c < n));
    let r2 = radius_cells * radius_cells;
    for z in clip(centre[2], floor_sqrt(r2), grid[2]) {
        let dz = z as f64 - centre[2] as f64;
        let rem_z = r2 - dz * dz;
        for y in clip(centre[1], floor_sqrt(rem_z), grid[1]) {
            let dy = y as f64 - centre[1] as f64;
            let xs = clip(centre[0], floor_sqrt(rem_z - dy * dy), grid[0]);
            if !xs.is_empty() {
                visit(y, z, xs);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn count(grid: [usize; 3], centre: [usize; 3], r: f64) -> usize {
        let mut n = 0;
        for_each_row(grid, centre, r, |_, _, xs| n += xs.len());
        n
    }

    #[test]
    fn ball_counts_match_lattice_points_in_a_sphere() {
        // Integer points with x² + y² + z² ≤ n²: 1, 7, 33, 123, 257, 515 (OEIS A000605).
        for (r, expected) in [
            (0.0, 1),
            (1.0, 7),
            (2.0, 33),
            (3.0, 123),
            (4.0, 257),
            (5.0, 515),
        ] {
            assert_eq!(count([21, 21, 21], [10, 10, 10], r), expected, "r = {r}");
        }
    }

    #[test]
    fn ball_includes_offsets_up_to_the_real_radius() {
        // r = 1.5 adds the 12 offsets of norm √2 to the 7 of r = 1; √3 ≈ 1.73 adds 8 more.
        assert_eq!(count([9, 9, 9], [4, 4, 4], 0.99), 1);
        assert_eq!(count([9, 9, 9], [4, 4, 4], 1.5), 19);
        assert_eq!(count([9, 9, 9], [4, 4, 4], 1.75), 27);
    }

    #[test]
    fn ball_is_clipped_at_the_grid_corner() {
        // At a corner only the octant remains: 1 + 3 of the 7 points of r = 1.
        assert_eq!(count([5, 5, 5], [0, 0, 0], 1.0), 4);
        // A radius far beyond the grid covers it exactly once.
        assert_eq!(count([4, 3, 2], [1, 1, 1], 1e6), 24);
    }

    #[test]
    fn rows_come_in_z_then_y_order() {
        let mut rows = Vec::new();
        for_each_row([5, 5, 5], [2, 2, 2], 1.0, |y, z, xs| rows.push((z, y, xs)));
        assert_eq!(
            rows,
            vec![
                (1, 2, 2..3),
                (2, 1, 2..3),
                (2, 2, 1..4),
                (2, 3, 2..3),
                (3, 2, 2..3)
            ]
        );
    }
}

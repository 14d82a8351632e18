//! The structure stage against the paper's model (§2.4) and independent numbers: the stopping
//! rule, the radius law of eq. (1), unit orientations, spatially correlated and isotropic
//! normals, the ellipsoid's frame, and determinism at any thread count.

use opalray::scene::StructureConfig;
use opalray::structure::{draw_step, orientation_map, Growth};
use opalray::{grow_structure, Cell, Structure};

fn paper(seed: u64) -> StructureConfig {
    StructureConfig {
        seed,
        ..StructureConfig::default()
    }
}

fn void_ratio_from_cells(s: &Structure) -> f64 {
    let voids = s.cells.iter().filter(|&&c| c == Cell::Void).count();
    let inside = s.cells.iter().filter(|&&c| c != Cell::Outside).count();
    voids as f64 / inside as f64
}

#[test]
fn void_ratio_ends_just_below_the_target() {
    for (seed, target) in [(1, 0.2), (2, 0.2), (3, 0.5), (4, 0.05)] {
        let config = StructureConfig {
            void_ratio: target,
            ..paper(seed)
        };
        let grown = grow_structure(&config).unwrap();
        let ratio = void_ratio_from_cells(&grown);
        assert!(ratio < target, "seed {seed}: ended at {ratio} ≥ {target}");
        assert!((grown.stats.void_ratio - ratio).abs() < 1e-12);
        // One step fewer must still be at or above the target: growth stopped at once.
        let mut growth = Growth::new(&config).unwrap();
        for _ in 1..grown.stats.seeds_placed {
            growth.step();
        }
        let before = void_ratio_from_cells(growth.structure());
        assert!(
            before >= target,
            "seed {seed}: {before} < {target} one step early"
        );
        assert_eq!(growth.structure().cells.len(), grown.cells.len());
    }
}

/// Kolmogorov–Smirnov distance between `samples` and the exponential CDF of mean `mean`.
fn ks_exponential(samples: &mut [f64], mean: f64) -> f64 {
    samples.sort_by(f64::total_cmp);
    let n = samples.len() as f64;
    samples
        .iter()
        .enumerate()
        .map(|(i, &r)| {
            let cdf = 1.0 - (-r / mean).exp();
            (cdf - i as f64 / n).abs().max((i as f64 + 1.0) / n - cdf)
        })
        .fold(0.0, f64::max)
}

#[test]
fn radii_follow_the_exponential_law() {
    let (mean_radius, n) = (6.0, 20_000);
    let mut radii: Vec<f64> = (0..n)
        .map(|step| draw_step(9, step, 98_228, mean_radius).radius_cells)
        .collect();
    let mean = radii.iter().sum::<f64>() / n as f64;
    assert!((mean / mean_radius - 1.0).abs() < 0.03, "mean {mean}");
    // KS critical value at significance 0.001: 1.95/√n (Massey 1951) ≈ 0.0138.
    let d = ks_exponential(&mut radii, mean_radius);
    assert!(d < 1.95 / (n as f64).sqrt(), "KS distance {d}");
    // The same law with a wrong mean is rejected: the test has power.
    assert!(ks_exponential(&mut radii, 1.1 * mean_radius) > 1.95 / (n as f64).sqrt());
}

#[test]
fn growth_uses_the_tested_radius_sampler() {
    let config = paper(5);
    let mut growth = Growth::new(&config).unwrap();
    let inside = growth.structure().stats.inside_cells;
    let mut sum = 0.0;
    for step in 0..40 {
        let report = growth.step().unwrap();
        let draw = draw_step(config.seed, step, inside, config.mean_radius_cells);
        assert_eq!(report.radius_cells, draw.radius_cells);
        sum += report.radius_cells;
    }
    let stats = &growth.structure().stats;
    assert!((stats.mean_radius_cells - sum / 40.0).abs() < 1e-12);
}

#[test]
fn orientations_are_unit_and_identity_off_clusters() {
    let s = grow_structure(&paper(1)).unwrap();
    for (cell, q) in s.cells.iter().zip(&s.orientations) {
        assert!((q.length() - 1.0).abs() < 1e-5, "{q}");
        if *cell != Cell::Cluster {
            assert_eq!(*q, glam::Quat::IDENTITY);
        }
    }
    for i in (0..s.cells.len()).step_by(97) {
        assert!((s.normal(i).length() - 1.0).abs() < 1e-5);
    }
}

/// Mean |cos| between the normals of cluster cells `d` apart along x and along y.
fn alignment_at(structures: &[Structure], d: usize) -> f64 {
    let (mut sum, mut pairs) = (0.0, 0usize);
    for s in structures {
        let [nx, ny, nz] = s.grid;
        for z in 0..nz {
            for y in 0..ny {
                for x in 0..nx {
                    let a = s.index(x, y, z);
                    if s.cells[a] != Cell::Cluster {
                        continue;
                    }
                    let neighbours = [(x + d < nx, (x + d, y)), (y + d < ny, (x, y + d))];
                    for (ok, (bx, by)) in neighbours {
                        let b = if ok { s.index(bx, by, z) } else { continue };
                        if s.cells[b] == Cell::Cluster {
                            sum += f64::from(s.normal(a).dot(s.normal(b)).abs());
                            pairs += 1;
                        }
                    }
                }
            }
        }
    }
    sum / pairs as f64
}

/// Mean |cos| of cluster normals 1, 4, 16 and 64 cells apart over six paper stones grown
/// with mean radius `radius` cells.
fn alignment_profile(radius: f64) -> [f64; 4] {
    let structures: Vec<_> = (1..=6)
        .map(|seed| {
            let config = StructureConfig {
                mean_radius_cells: radius,
                ..paper(seed)
            };
            grow_structure(&config).unwrap()
        })
        .collect();
    [1, 4, 16, 64].map(|d| alignment_at(&structures, d))
}

#[test]
fn neighbouring_normals_align_and_correlation_falls_with_distance() {
    // Independent isotropic normals have mean |cos| = 1/2 (cos is uniform on [−1, 1]).
    for radius in [6.0, 2.0] {
        let c = alignment_profile(radius);
        println!("R = {radius}: mean |cos| at 1, 4, 16, 64 cells: {c:?}");
        assert!(c[0] > 0.9, "R = {radius}, adjacent cells: {}", c[0]);
        assert!(
            c[0] > c[1] && c[1] > c[2] && c[2] > c[3],
            "R = {radius}: {c:?}"
        );
        if radius == 2.0 {
            // 64 cells is far beyond patches of R = 2: back to random (measured 0.48).
            assert!((c[3] - 0.5).abs() < 0.08, "R = 2, cells 64 apart: {}", c[3]);
        }
    }
}

#[test]
fn normals_are_isotropic_over_many_stones() {
    // For isotropic unit vectors E[n nᵀ] = I/3; a bias of the averaging towards any frame
    // (the lattice's, the grid's) shows as unequal diagonal or non-zero off-diagonal terms.
    let mut m = [[0.0f64; 3]; 3];
    let mut count = 0.0;
    for seed in 100..500 {
        let s = grow_structure(&paper(seed)).unwrap();
        for i in 0..s.cells.len() {
            if s.cells[i] == Cell::Cluster {
                let n = s.normal(i).to_array().map(f64::from);
                for (r, row) in m.iter_mut().enumerate() {
                    for (c, v) in row.iter_mut().enumerate() {
                        *v += n[r] * n[c];
                    }
                }
                count += 1.0;
            }
        }
    }
    for (r, row) in m.iter().enumerate() {
        for (c, v) in row.iter().enumerate() {
            let (v, expected) = (v / count, if r == c { 1.0 / 3.0 } else { 0.0 });
            println!("E[n{r} n{c}] = {v:.3}");
            // 400 stones of a few large patches each: the spread of each term is about 0.01.
            assert!((v - expected).abs() < 0.04, "E[n{r} n{c}] = {v}");
        }
    }
}

#[test]
fn outside_cells_are_exactly_those_with_centres_outside_the_ellipsoid() {
    for (grid, axes) in [
        ([100, 75, 25], [10.0, 7.5, 2.5]),
        ([17, 9, 6], [3.0, 1.0, 0.5]),
        ([2, 2, 2], [1.0, 1.0, 1.0]),
    ] {
        let config = StructureConfig {
            grid,
            semi_axes_mm: axes,
            ..paper(3)
        };
        let s = grow_structure(&config).unwrap();
        let size = s.cell_size_mm();
        for z in 0..grid[2] {
            for y in 0..grid[1] {
                for x in 0..grid[0] {
                    let index = [x, y, z];
                    let e: f64 = (0..3)
                        .map(|k| (-axes[k] + (index[k] as f64 + 0.5) * size[k]) / axes[k])
                        .map(|u| u * u)
                        .sum();
                    if (e - 1.0).abs() < 1e-9 {
                        continue; // on the surface to rounding: either answer is right
                    }
                    let cell = s.cells[s.index(x, y, z)];
                    assert_eq!(
                        cell == Cell::Outside,
                        e > 1.0,
                        "cell ({x}, {y}, {z}): {cell:?}"
                    );
                }
            }
        }
        assert_eq!(s.stats.inside_cells, s.stats.clusters + s.stats.voids);
    }
}

fn grow_and_draw(threads: usize) -> (Structure, Vec<u8>) {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| {
        let config = StructureConfig {
            orientation_jitter_deg: 5.0,
            ..paper(11)
        };
        let s = grow_structure(&config).unwrap();
        let map = orientation_map(&s, 12, 2).unwrap();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("map.png");
        opalray::output::write_png_rgba8(&path, map.width, map.height, &map.rgba).unwrap();
        (s, std::fs::read(&path).unwrap())
    })
}

#[test]
fn structure_and_png_are_identical_at_1_2_3_threads() {
    let (one, png_one) = grow_and_draw(1);
    for threads in [2, 3] {
        let (s, png) = grow_and_draw(threads);
        assert_eq!(s.cells, one.cells, "{threads} threads");
        let bits = |s: &Structure| -> Vec<[u32; 4]> {
            s.orientations
                .iter()
                .map(|q| q.to_array().map(f32::to_bits))
                .collect()
        };
        assert_eq!(bits(&s), bits(&one), "{threads} threads");
        assert_eq!(s.stats.seeds_placed, one.stats.seeds_placed);
        assert_eq!(png, png_one, "{threads} threads");
    }
}

#[test]
fn different_seeds_give_different_structures() {
    let a = grow_structure(&paper(1)).unwrap();
    let b = grow_structure(&paper(2)).unwrap();
    assert_ne!(a.cells, b.cells);
}

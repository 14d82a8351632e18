//! The cluster's binned R, T, D tables (paper §3.1): the Bragg line lands in the right bin,
//! the fine-grid integration converges, the diffuse split and the thread-independence hold.

use opalray::optics::{bragg_wavelength_inside_nm, ClusterStack};
use opalray::scene::CrystalConfig;

#[test]
fn table_peak_bin_holds_the_bragg_wavelength() {
    // The binned table's brightest bin is the bin of 2 d n_eff cos θ for every row whose
    // Bragg wavelength lies in the visible, away from bin edges.
    let c = CrystalConfig::default();
    let grid = opalray::WavelengthGrid::default();
    let tables = opalray::build_optics(&c, &grid).unwrap();
    let mut checked = 0;
    for i in 0..tables.angles {
        let lambda =
            bragg_wavelength_inside_nm(tables.d111_nm, tables.n_eff, tables.row_cos_theta(i));
        let Some(bin) = grid.bin_of(lambda) else {
            continue;
        };
        let (lo, hi) = grid.edges_nm(bin);
        if lambda - lo < 2.0 || hi - lambda < 2.0 {
            continue;
        }
        let (r, _, _) = tables.row(i);
        let brightest = (0..grid.bins)
            .max_by(|&a, &b| r[a].total_cmp(&r[b]))
            .unwrap();
        assert_eq!(brightest, bin, "row {i}: λ_B = {lambda:.1} nm");
        checked += 1;
    }
    assert!(checked > 20, "only {checked} rows checked");
}

#[test]
fn table_bins_match_a_brute_force_integral() {
    // The adaptive fine grid against a uniform 0.002 nm trapezoid integral (converged to
    // ~1e-6) for rows whose Bragg line is in the visible.
    let c = CrystalConfig::default();
    let grid = opalray::WavelengthGrid::default();
    let tables = opalray::build_optics(&c, &grid).unwrap();
    let stack = ClusterStack::new(&c).unwrap();
    for i in [0, 10, 25, 40, 55] {
        let at = stack.at(tables.row_cos_theta(i));
        let (r, t, d) = tables.row(i);
        for bin in 0..grid.bins {
            let (lo, hi) = grid.edges_nm(bin);
            let steps = ((hi - lo) / 0.002).round() as usize;
            let h = (hi - lo) / steps as f64;
            let sum: f64 = (0..=steps)
                .map(|k| {
                    let weight = if k == 0 || k == steps { 0.5 } else { 1.0 };
                    weight * at.rt_unpolarized(lo + k as f64 * h).0
                })
                .sum();
            let exact = sum * h / (hi - lo);
            // The coherent reflectance is split into specular R and diffuse D.
            let coherent = f64::from(r[bin]) + f64::from(d[bin]);
            assert!(
                (coherent - exact).abs() < 1e-3,
                "row {i} bin {bin}: table {coherent} brute force {exact}"
            );
            let total = f64::from(r[bin]) + f64::from(t[bin]) + f64::from(d[bin]);
            assert!(
                (total - 1.0).abs() < 1e-6,
                "row {i} bin {bin}: R + T + D = {total}"
            );
        }
    }
}

#[test]
fn diffuse_part_is_the_diffuse_fraction_of_the_bragg_reflection() {
    // docs/model.md: D = δ R_coh, R = (1 − δ) R_coh, T = T_coh = 1 − R_coh without absorption.
    let c = CrystalConfig {
        diffuse_fraction: 0.1,
        ..CrystalConfig::default()
    };
    let tables = opalray::build_optics(&c, &opalray::WavelengthGrid::default()).unwrap();
    for ((&r, &t), &d) in tables
        .reflectance
        .iter()
        .zip(&tables.transmittance)
        .zip(&tables.diffuse)
    {
        let coherent = r + d;
        assert!((d - 0.1 * coherent).abs() < 1e-6 && (r - 0.9 * coherent).abs() < 1e-6);
        assert!(
            (t - (1.0 - coherent)).abs() < 1e-5,
            "T = 1 − R_coh: {t} vs {coherent}"
        );
    }
}

#[test]
fn tables_do_not_depend_on_the_thread_count() {
    let build = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| {
                opalray::build_optics(
                    &CrystalConfig::default(),
                    &opalray::WavelengthGrid::default(),
                )
                .unwrap()
            })
    };
    let one = build(1);
    for threads in [2, 3] {
        let many = build(threads);
        assert_eq!(one.reflectance, many.reflectance);
        assert_eq!(one.transmittance, many.transmittance);
        assert_eq!(one.diffuse, many.diffuse);
    }
}

//! Silica's dispersion against independent numbers: fused silica's index against Malitson's
//! measurements, and the Bragg lines the stone model builds (their centre and width) against
//! a transfer-matrix scan of the stack whose indices the test computes at every wavelength.

use glam::Vec3;
use opalray::optics::dispersion::fused_silica_index;
use opalray::optics::ClusterStack;
use opalray::scene::{CrystalConfig, Dispersion, Pattern, Scene};
use opalray::stone::{ActiveLine, Stone};

/// Fused silica by Malitson's Sellmeier law, written out here from the paper (J. Opt. Soc.
/// Am. 55, 1205, 1965), λ in µm.
fn malitson(wavelength_nm: f64) -> f64 {
    let l2 = (wavelength_nm * 1e-3).powi(2);
    let term = |b: f64, l: f64| b * l2 / (l2 - l * l);
    (1.0 + term(0.6961663, 0.0684043) + term(0.4079426, 0.1162414) + term(0.8974794, 9.896161))
        .sqrt()
}

#[test]
fn fused_silica_index_matches_malitsons_measurements() {
    // Malitson (1965), table of measured indices of fused silica at 20 °C (the mercury,
    // helium and hydrogen lines); the Sellmeier fit's residuals are about 10⁻⁵.
    for (nm, measured) in [
        (404.656, 1.46962),
        (435.834, 1.46669),
        (486.133, 1.46313),
        (546.074, 1.46008),
        (587.562, 1.45846),
        (656.272, 1.45637),
        (706.519, 1.45515),
    ] {
        let (n, _) = fused_silica_index(nm);
        assert!((n - measured).abs() < 3e-5, "{nm} nm: {n} vs {measured}");
    }
}

/// A stone of grains of one sphere diameter `diameter_nm`, with or without silica's law.
fn stone(diameter_nm: f64, dispersion: Dispersion) -> Stone {
    let mut scene = Scene::default();
    scene.domains.pattern = Pattern::Grains;
    scene.domains.sphere_diameter_spread = 0.0;
    scene.crystal.sphere_diameter_nm = diameter_nm;
    scene.crystal.dispersion = dispersion;
    Stone::new(&scene).unwrap()
}

/// The (111) line domain 0 of `stone` shows face-on (a ray along its (111) normal).
fn face_on_111(stone: &Stone) -> ActiveLine {
    let n111 = stone.domains[0].orientation * Vec3::splat(1.0).normalize();
    let mut lines = Vec::new();
    stone.lines(0, -n111, 1.0, &mut lines);
    *lines
        .iter()
        .filter(|l| l.kind == 0)
        .max_by(|a, b| a.line.center_nm.total_cmp(&b.line.center_nm))
        .expect("a (111) line face-on")
}

/// The half-maximum edges `(lo, hi)` of `r` over `[from, to]`, scanned every `step` nm and
/// bisected, around its largest value.
fn half_max_edges(r: &dyn Fn(f64) -> f64, from: f64, to: f64, step: f64) -> (f64, f64) {
    let samples = ((to - from) / step) as usize;
    let (peak_at, peak) = (0..=samples)
        .map(|i| from + i as f64 * step)
        .map(|w| (w, r(w)))
        .fold((from, 0.0), |best, s| if s.1 > best.1 { s } else { best });
    let edge = |mut inside: f64, mut outside: f64| {
        for _ in 0..60 {
            let mid = 0.5 * (inside + outside);
            if r(mid) > 0.5 * peak {
                inside = mid;
            } else {
                outside = mid;
            }
        }
        0.5 * (inside + outside)
    };
    // Walk out to the first sample below half.
    let walk = |dir: f64| {
        let mut w = peak_at;
        while r(w + dir * step) > 0.5 * peak {
            w += dir * step;
        }
        edge(w, w + dir * step)
    };
    (walk(-1.0), walk(1.0))
}

#[test]
fn silica_lines_sit_where_the_dispersive_stack_reflects() {
    // Independent: at every wavelength the test computes the spheres' and the cement's
    // indices by Malitson's law shifted to 1.45 and 1.42 at 589.3 nm, builds the stack of
    // those constant indices and reads its exact transfer-matrix R at normal incidence; the
    // line is where that R is at half its maximum.
    let shift = |nm: f64| malitson(nm) - malitson(589.3);
    for diameter in [200.0, 270.0] {
        let stack_r = |nm: f64| {
            let crystal = CrystalConfig {
                sphere_diameter_nm: diameter,
                n_sphere: 1.45 + shift(nm),
                n_matrix: 1.42 + shift(nm),
                ..CrystalConfig::default()
            };
            ClusterStack::new(&crystal)
                .unwrap()
                .at(1.0)
                .rt_unpolarized(nm)
                .0
        };
        let constant = face_on_111(&stone(diameter, Dispersion::None)).line;
        let (from, to) = (constant.center_nm - 8.0, constant.center_nm + 8.0);
        let (lo, hi) = half_max_edges(&stack_r, from, to, 0.05);
        let line = face_on_111(&stone(diameter, Dispersion::Silica)).line;
        let (line_lo, line_hi) = half_max_edges(&|w| line.reflectance(w), from, to, 0.05);
        let centre = 0.5 * (lo + hi);
        assert!(
            (line.center_nm - centre).abs() < 0.01,
            "D {diameter}: line at {} nm, the stack's centre {centre} nm (constant index: {})",
            line.center_nm,
            constant.center_nm
        );
        // The width: narrower than at the constant index by the group index over the index.
        let width = hi - lo;
        let line_width = line_hi - line_lo;
        assert!(
            (line_width / width - 1.0).abs() < 0.001,
            "D {diameter}: width {line_width} nm, the stack's {width} nm"
        );
        // The half-vector law's line of the same family (`Stone::line_at`) agrees.
        let again = stone(diameter, Dispersion::Silica);
        let active = face_on_111(&again);
        let at = again.line_at(0, &active, 1.0);
        assert!(
            (at.center_nm - line.center_nm).abs() < 1e-6,
            "{at:?} vs {line:?}"
        );
        assert!((at.layers - line.layers).abs() < 1e-6 * line.layers);
    }
}

#[test]
fn the_two_pass_tables_move_the_line_by_the_fixed_point() {
    // The paper's tables (row 0, face-on) on 0.1 nm bins, with and without silica's law: the
    // line's centroid moves by the shift of the fixed point λ = 2 d n̄(λ), solved here with
    // Malitson's law (`malitson`), from 2 d n̄_d.
    let grid = opalray::WavelengthGrid::new(440.0, 500.0, 600).unwrap();
    let centroid = |dispersion| {
        let crystal = CrystalConfig {
            sphere_diameter_nm: 200.0,
            angles: 90,
            dispersion,
            ..CrystalConfig::default()
        };
        let tables = opalray::build_optics(&crystal, &grid).unwrap();
        let r = &tables.reflectance[..grid.bins];
        let (mut sum, mut weighted) = (0.0, 0.0);
        for (k, &v) in r.iter().enumerate() {
            sum += f64::from(v);
            weighted += f64::from(v) * grid.center_nm(k);
        }
        weighted / sum
    };
    let n_eff = |shift: f64| {
        let (n_s, n_m) = (1.45 + shift, 1.42 + shift);
        (0.74 * n_s * n_s + 0.26 * n_m * n_m).sqrt()
    };
    let x = 2.0 * 200.0 * (2.0f64 / 3.0).sqrt() * n_eff(0.0);
    let mut lambda = x;
    for _ in 0..20 {
        lambda = x * n_eff(malitson(lambda) - malitson(589.3)) / n_eff(0.0);
    }
    let moved = centroid(Dispersion::Silica) - centroid(Dispersion::None);
    assert!(
        (moved - (lambda - x)).abs() < 0.05,
        "moved {moved} nm, the fixed point {} nm",
        lambda - x
    );
}

#[test]
fn an_unknown_dispersion_is_refused_naming_the_field_and_the_choices() {
    let err = Scene::from_toml_str("[crystal]\ndispersion = \"sellmeier\"\n", "test")
        .unwrap_err()
        .to_string();
    assert!(err.contains("crystal.dispersion"), "{err}");
    assert!(err.contains("none") && err.contains("silica"), "{err}");
}

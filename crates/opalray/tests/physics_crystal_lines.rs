//! The crystal's Bragg lines carried at exact wavelengths, never binned before colour, against
//! brute force and the transfer matrix: a double reflection is the mean of R², and the lines a
//! path passes keep the stack's product of 1 − R.

use opalray::optics::BraggLine;
use opalray::path::{PathSpectrum, SpectralSampler};
use opalray::scene::Illuminant;
use opalray::spectrum::WavelengthGrid;
use opalray::stored::Lines;

#[test]
fn a_double_reflection_is_the_mean_of_r_squared_not_the_square_of_the_bin_mean() {
    // The crystal issue: in 10 nm bins two reflections came out 3× too weak (R̄² against
    // mean(R²)). Lines are carried at exact wavelengths; the 580–590 nm bin of a path reflected
    // twice by the face-on default line is within 2 % of mean(R²) by brute force.
    let grid = WavelengthGrid::default();
    let sampler = SpectralSampler::new(Illuminant::E, &grid, 8);
    let line = BraggLine::new(0.003_712, 588.8, 1.0, 400.0);
    let bin = grid.bin_of(585.0).unwrap();
    let draws = 20_000;
    let mut mean_bin = 0.0f64;
    for k in 0..draws {
        let mut path = PathSpectrum::default();
        path.reflect(line, &sampler, (k as f64 + 0.5) / draws as f64);
        path.reflect(line, &sampler, 0.5);
        let (mut xyz, mut bins) = ([0.0; 3], vec![0.0f32; grid.bins]);
        sampler.add_path(&path, 1.0, &mut xyz, &mut bins);
        mean_bin += f64::from(bins[bin]) / draws as f64;
    }
    // Brute force: the light's spectrum is flat (E), so the bin value is the light's level
    // times mean(R²) over the bin.
    let light = f64::from(sampler.white_bins[bin]);
    let (a, b) = grid.edges_nm(bin);
    let steps = 100_000;
    let mean_r2: f64 = (0..steps)
        .map(|i| {
            line.reflectance(a + (b - a) * (i as f64 + 0.5) / steps as f64)
                .powi(2)
        })
        .sum::<f64>()
        / steps as f64;
    let bin_mean: f64 = (0..steps)
        .map(|i| line.reflectance(a + (b - a) * (i as f64 + 0.5) / steps as f64))
        .sum::<f64>()
        / steps as f64;
    assert!(
        bin_mean * bin_mean < 0.5 * mean_r2,
        "the bins' error this guards against"
    );
    let got = mean_bin / light;
    assert!(
        (got / mean_r2 - 1.0).abs() < 0.02,
        "{got} vs mean(R²) {mean_r2}"
    );
}

#[test]
fn lines_passed_keep_the_transfer_matrix_product_of_one_minus_r() {
    // Light crossing 5 and 10 face-on domains of the default crystal (line centred in
    // 580–590 nm): the lines' analytic product Π (1 − R(λ)) over the bin, against the same
    // product of the transfer-matrix stack's 1 − R at 0.05 nm steps (independent domains add
    // incoherently), within 2 %.
    let crystal = opalray::scene::CrystalConfig::default();
    let stack = opalray::optics::ClusterStack::new(&crystal).unwrap();
    let centre = stack.bragg_wavelength_nm(1.0);
    assert!((580.0..590.0).contains(&centre), "{centre}");
    let line = BraggLine::new(0.003_712, 588.8, 1.0, 400.0);
    assert!(
        (line.center_nm - centre).abs() < 0.5,
        "{} vs {centre}",
        line.center_nm
    );
    let at = stack.at(1.0);
    let (a, b) = (580.0, 590.0);
    for domains in [5, 10] {
        let mut lines = Lines::default();
        for _ in 0..domains {
            lines.transmit(line);
        }
        let steps = 200; // 0.05 nm
        let (mut analytic, mut tmm) = (0.0f64, 0.0f64);
        for i in 0..steps {
            let w = a + (b - a) * (i as f64 + 0.5) / steps as f64;
            analytic += lines.factor(w) / steps as f64;
            tmm += (1.0 - at.rt_unpolarized(w).0).powi(domains) / steps as f64;
        }
        assert!(tmm < 0.95, "the notch matters: {tmm}");
        assert!(
            (analytic / tmm - 1.0).abs() < 0.02,
            "{domains} domains: {analytic} vs transfer matrix {tmm}"
        );
    }
}

//! CIE standard illuminants as light spectra (D65, A, C from the official tables in
//! `data/cie/`, E the constant) and their white points.

use std::sync::OnceLock;

use super::cmf::parse_embedded_table;
use super::exact::emission_xyz;
use super::ColorMatcher;
use crate::scene::Illuminant;
use crate::spectrum::WavelengthGrid;

/// CIE D65, 5 nm, 300–780 nm (CIE 15:2004 Table T.1).
const D65_CSV: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../data/cie/illuminant_d65_5nm.csv"
));
/// CIE A, 5 nm, 300–780 nm (CIE 15:2004 Table T.1).
const A_CSV: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../data/cie/illuminant_a_5nm.csv"
));
/// CIE C, 5 nm, 300–780 nm (CIE 15:2004 Table T.1).
const C_CSV: &str = include_str!(concat!(
    env!("CARGO_MANIFEST_DIR"),
    "/../../data/cie/illuminant_c_5nm.csv"
));

/// Illuminant E is the constant 1 over this range, nm: wider than any wavelength grid accepts.
const E_RANGE_NM: (f64, f64) = (0.0, 10_000.0);

/// All four illuminants, in the order of [`index`].
const ALL: [Illuminant; 4] = [Illuminant::D65, Illuminant::A, Illuminant::C, Illuminant::E];

fn index(illuminant: Illuminant) -> usize {
    match illuminant {
        Illuminant::D65 => 0,
        Illuminant::A => 1,
        Illuminant::C => 2,
        Illuminant::E => 3,
    }
}

/// The relative spectral power distribution of `illuminant` as samples `(wavelength_nm,
/// value)`, read as piecewise linear and zero outside (the tables end at 300 and 780 nm).
/// D65, A and C are scaled as the CIE tables (100 at 560 nm); E is 1 everywhere.
pub fn illuminant_samples(illuminant: Illuminant) -> &'static [(f64, f64)] {
    static TABLES: OnceLock<[Vec<(f64, f64)>; 4]> = OnceLock::new();
    let tables = TABLES.get_or_init(|| {
        let read = |csv: &str| -> Vec<(f64, f64)> {
            parse_embedded_table(csv, 1)
                .into_iter()
                .map(|(w, v)| (w, v[0]))
                .collect()
        };
        [
            read(D65_CSV),
            read(A_CSV),
            read(C_CSV),
            vec![(E_RANGE_NM.0, 1.0), (E_RANGE_NM.1, 1.0)],
        ]
    });
    &tables[index(illuminant)]
}

/// The illuminant's spectrum averaged over each bin of `grid`, scaled so that the light itself
/// (equivalently a perfect white reflector under it) has luminance `Y = Σ_b s_b ȳ_b Δλ = 1`
/// with the bin-averaged CMFs of the same grid. Bins outside the table's range get 0.
///
/// Returns `grid.bins` values (relative radiance per nm). On a grid that holds no light of
/// the illuminant (all bins beyond 780 nm, say) every value is 0.
pub fn illuminant_spectrum(illuminant: Illuminant, grid: &WavelengthGrid) -> Vec<f32> {
    let binned = grid.bin_average(illuminant_samples(illuminant));
    let matcher = ColorMatcher::new(grid);
    let luminance: f64 = binned
        .iter()
        .zip(&matcher.weights()[1])
        .map(|(s, &w)| s * w as f64)
        .sum();
    let scale = if luminance > 0.0 {
        1.0 / luminance
    } else {
        0.0
    };
    binned.iter().map(|&s| (s * scale) as f32).collect()
}

/// The white point `[X, Y, Z]` of `illuminant` with `Y = 1`, integrated exactly from the
/// shipped tables (the CIE 1931 2° observer, 1 nm, against the piecewise-linear illuminant).
/// D65 gives x, y = 0.31273, 0.32902; C 0.31009, 0.31622; A 0.44756, 0.40743; E ≈ 1/3, 1/3.
pub fn white_point_xyz(illuminant: Illuminant) -> [f64; 3] {
    static WHITES: OnceLock<[[f64; 3]; 4]> = OnceLock::new();
    WHITES.get_or_init(|| {
        ALL.map(|ill| {
            let [x, y, z] = emission_xyz(illuminant_samples(ill));
            [x / y, 1.0, z / y]
        })
    })[index(illuminant)]
}

/// Chromaticity `[x, y]` of tristimulus values; `None` when `X + Y + Z ≤ 0` (black).
pub fn chromaticity(xyz: [f64; 3]) -> Option<[f64; 2]> {
    let sum = xyz[0] + xyz[1] + xyz[2];
    (sum > 0.0).then(|| [xyz[0] / sum, xyz[1] / sum])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn illuminant_tables_match_printed_cie_values() {
        // CIE 15:2004 Table T.1: D65(560) = A(560) = 100, C(560) = 105.3, D65(300) = 0.0341.
        let at = |ill, w| super::super::cmf::interpolate(illuminant_samples(ill), w);
        assert_eq!(at(Illuminant::D65, 560.0), 100.0);
        assert_eq!(at(Illuminant::A, 560.0), 100.0);
        assert_eq!(at(Illuminant::C, 560.0), 105.3);
        assert_eq!(at(Illuminant::D65, 300.0), 0.0341);
        assert_eq!(illuminant_samples(Illuminant::D65).len(), 97);
    }

    #[test]
    fn illuminant_spectrum_has_unit_luminance_on_any_grid() {
        for grid in [
            WavelengthGrid::default(),
            WavelengthGrid::new(400.0, 700.0, 7).unwrap(),
            WavelengthGrid::new(360.0, 830.0, 470).unwrap(),
        ] {
            let m = ColorMatcher::new(&grid);
            for ill in ALL {
                let y = m.to_xyz(&illuminant_spectrum(ill, &grid))[1];
                assert!((y - 1.0).abs() < 1e-5, "{ill:?} {grid:?}: {y}");
            }
        }
    }

    #[test]
    fn illuminant_spectrum_outside_the_table_is_black() {
        let grid = WavelengthGrid::new(900.0, 1000.0, 4).unwrap();
        assert_eq!(illuminant_spectrum(Illuminant::D65, &grid), vec![0.0; 4]);
    }

    #[test]
    fn chromaticity_of_black_is_none() {
        assert_eq!(chromaticity([0.0; 3]), None);
        assert_eq!(chromaticity([1.0, 1.0, 2.0]), Some([0.25, 0.25]));
    }
}

//! Silica's dispersion: the spheres' and the cement's indices over wavelength, and what a
//! Bragg line becomes with them (`docs/model.md`, the indices over wavelength).
//!
//! Input: a [`CrystalConfig`] (its indices at the sodium d line and `crystal.dispersion`) →
//! output: a [`CrystalIndex`], the indices, the effective index and the contrast at any
//! wavelength, and for a line the [`LineIndex`] that moves its centre and sets its strength.
//!
//! - Fused silica's Sellmeier law (Malitson 1965, J. Opt. Soc. Am. 55, 1205), λ in µm:
//!   `n² − 1 = Σ Bᵢ λ² / (λ² − Cᵢ)`. Opal's hydrated silica has a lower index than fused
//!   silica (1.45 against 1.458 at the d line), so the law gives the shape and the scene the
//!   level: `n(λ) = n_d + n_silica(λ) − n_silica(589.3 nm)`, for the spheres and the cement
//!   alike (their contrast stays `n_s,d − n_m,d` at every wavelength).
//! - A family of spacing d met at θ reflects where `λ = 2 d n̄(λ) cos θ`. With
//!   `x = 2 d n̄_d cos θ` (the centre at the constant index), `λ = x n̄(λ) / n̄_d`: a fixed
//!   point whose map has slope `x |n̄'| / n̄_d`, about 0.03 at 400 nm: [`FIXED_POINT_STEPS`]
//!   steps leave about 10⁻⁴ nm and one Newton step (with the slope the line needs anyway)
//!   under 10⁻⁶ nm down to 250 nm; its inverse is explicit, `x = λ n̄_d / n̄(λ)`.
//! - The coupling `g ∝ |ε_s − ε_m| / ε̄` is taken at the line's centre.
//! - Across a line the detuning `λ_B(λ)/λ − 1` of `λ_B(λ) = 2 d n̄(λ) cos θ` runs faster than
//!   at a constant index by `k = n_g / n̄ = 1 − λ n̄'/n̄` (the group index over the index):
//!   the line is narrower by `1/k` (2.6 % at 400 nm, 1.2 % at 600 nm). A [`BraggLine`] of
//!   `k N` layers and coupling `g / k` has that detuning and the same coupling `ν`.
//!
//! [`BraggLine`]: super::BraggLine

use crate::scene::{CrystalConfig, Dispersion};

/// The sodium d line, nm: the wavelength at which the scene's `n_sphere` and `n_matrix` hold.
pub const SODIUM_D_NM: f64 = 589.3;

/// Fused silica's Sellmeier coefficients `Bᵢ` (Malitson 1965, J. Opt. Soc. Am. 55, 1205).
const SELLMEIER_B: [f64; 3] = [0.696_166_3, 0.407_942_6, 0.897_479_4];

/// Fused silica's Sellmeier resonances `Cᵢ = λᵢ²`, µm² (Malitson 1965): λᵢ = 0.0684043,
/// 0.1162414 and 9.896161 µm.
const SELLMEIER_C_UM2: [f64; 3] = [
    0.068_404_3 * 0.068_404_3,
    0.116_241_4 * 0.116_241_4,
    9.896_161 * 9.896_161,
];

/// The wavelengths (nm) of Malitson's measurements, over which the law holds; outside them
/// the index is held at the nearest end's value (the scenes' range is 200–2000 nm, and a
/// line's centre never far from it).
const LAW_RANGE_NM: (f64, f64) = (210.0, 3710.0);

/// Steps of the fixed point `λ = x n̄(λ) / n̄_d` before its Newton step (module notes): each
/// divides the error by at least 15 over 300–2000 nm.
pub const FIXED_POINT_STEPS: usize = 3;

/// Fused silica's index and its derivative (per nm) at `wavelength_nm` (held constant
/// outside 210–3710 nm, the law's range, where the derivative is 0).
pub fn fused_silica_index(wavelength_nm: f64) -> (f64, f64) {
    let (lo, hi) = LAW_RANGE_NM;
    let inside = wavelength_nm > lo && wavelength_nm < hi;
    let um = wavelength_nm.clamp(lo, hi) * 1e-3;
    let um2 = um * um;
    let (mut n_sq, mut d_n_sq) = (1.0, 0.0);
    for (b, c) in SELLMEIER_B.iter().zip(SELLMEIER_C_UM2) {
        let denominator = um2 - c;
        n_sq += b * um2 / denominator;
        // d/dλ of B λ²/(λ² − C) = −2 B C λ / (λ² − C)².
        d_n_sq -= 2.0 * b * c * um / (denominator * denominator);
    }
    let n = n_sq.sqrt();
    // Per µm to per nm.
    let slope = if inside { 0.5 * d_n_sq / n * 1e-3 } else { 0.0 };
    (n, slope)
}

/// Nodes of [`CrystalIndex`]'s table of lines: every nanometre of the constant-index centre
/// from [`TABLE_FROM_NM`]. Linear interpolation between them is within 10⁻⁴ nm of the
/// solved centre from 250 nm (the centre's curvature, `(2|n̄'| + x|n̄''|)/n̄`, times h²/8),
/// within 10⁻⁶ of the coupling scale and 10⁻⁵ of the group ratio (tested).
const TABLE_NODES: usize = 2501;

/// The first node of the table, nm: past the reach of every line of a 200 nm range.
const TABLE_FROM_NM: f64 = 100.0;

/// The crystal's indices at every wavelength.
#[derive(Clone, Debug, PartialEq)]
pub struct CrystalIndex {
    /// The law.
    pub dispersion: Dispersion,
    /// The spheres' index at the sodium d line.
    pub n_sphere_d: f64,
    /// The matrix's index at the sodium d line.
    pub n_matrix_d: f64,
    /// Volume fraction of spheres.
    pub filling_fraction: f64,
    /// The effective index `√(f n_s² + (1 − f) n_m²)` at the sodium d line.
    pub n_eff_d: f64,
    /// Fused silica's index at the sodium d line (the law's zero).
    silica_d: f64,
    /// `(ε_s − ε_m)/ε̄` at the sodium d line.
    contrast_d: f64,
    /// With a law, per nanometre of the constant-index centre x from [`TABLE_FROM_NM`]:
    /// the line's centre less x (nm), its coupling scale over its group ratio, its group
    /// ratio, and the group ratio at the wavelength x; the lines of a render read it instead
    /// of solving (`f32`: 10⁻⁵ nm and 10⁻⁷ relative, far below the interpolation's error).
    table: Vec<[f32; 4]>,
}

/// What a line whose centre at the constant index would be `x` becomes with the dispersion.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LineIndex {
    /// The line's centre, nm: the fixed point `λ = x n̄(λ) / n̄_d`.
    pub centre_nm: f64,
    /// The coupling at the centre over the coupling at the d line:
    /// `[(ε_s − ε_m)/ε̄](λ) / [(ε_s − ε_m)/ε̄](589.3 nm)`.
    pub coupling_scale: f64,
    /// `k = n_g / n̄ = 1 − λ n̄'/n̄` at the centre (≥ 1 where the index falls with λ).
    pub group_ratio: f64,
}

impl CrystalIndex {
    /// The indices of `crystal` (its ranges are checked by `CrystalConfig::validate`).
    pub fn new(crystal: &CrystalConfig) -> CrystalIndex {
        let f = crystal.filling_fraction;
        let eps_d = f * crystal.n_sphere.powi(2) + (1.0 - f) * crystal.n_matrix.powi(2);
        let mut index = CrystalIndex {
            dispersion: crystal.dispersion,
            n_sphere_d: crystal.n_sphere,
            n_matrix_d: crystal.n_matrix,
            filling_fraction: f,
            n_eff_d: eps_d.sqrt(),
            silica_d: fused_silica_index(SODIUM_D_NM).0,
            contrast_d: (crystal.n_sphere.powi(2) - crystal.n_matrix.powi(2)) / eps_d,
            table: Vec::new(),
        };
        if !index.is_constant() {
            index.table = (0..TABLE_NODES)
                .map(|i| {
                    let x = TABLE_FROM_NM + i as f64;
                    let line = index.line(x);
                    let k = index.group_ratio(x);
                    let coupling = line.coupling_scale / line.group_ratio;
                    [line.centre_nm - x, coupling, line.group_ratio, k].map(|v| v as f32)
                })
                .collect();
        }
        index
    }

    /// The table's row at `x_nm`, linearly interpolated; `None` off the table (or without a
    /// law).
    #[inline]
    fn tabulated(&self, x_nm: f64) -> Option<[f64; 4]> {
        let u = x_nm - TABLE_FROM_NM;
        // Also false for NaN.
        if !(u >= 0.0 && u < (TABLE_NODES - 1) as f64) {
            return None;
        }
        let i = u as usize;
        let (a, b) = (self.table.get(i)?, self.table.get(i + 1)?);
        let w = (u - i as f64) as f32;
        Some(std::array::from_fn(|c| f64::from(a[c] + (b[c] - a[c]) * w)))
    }

    /// True where the indices do not change with wavelength (`dispersion = "none"`).
    #[inline]
    pub fn is_constant(&self) -> bool {
        self.dispersion == Dispersion::None
    }

    /// The shift of both indices from their d-line values at `wavelength_nm`, and its
    /// derivative per nm.
    #[inline]
    fn offset(&self, wavelength_nm: f64) -> (f64, f64) {
        match self.dispersion {
            Dispersion::None => (0.0, 0.0),
            Dispersion::Silica => {
                let (n, slope) = fused_silica_index(wavelength_nm);
                (n - self.silica_d, slope)
            }
        }
    }

    /// `(n_sphere, n_matrix)` at `wavelength_nm`.
    #[inline]
    pub fn indices(&self, wavelength_nm: f64) -> (f64, f64) {
        let (shift, _) = self.offset(wavelength_nm);
        (self.n_sphere_d + shift, self.n_matrix_d + shift)
    }

    /// The effective index `√(f n_s² + (1 − f) n_m²)` at `wavelength_nm`.
    #[inline]
    pub fn n_eff(&self, wavelength_nm: f64) -> f64 {
        let (n_s, n_m) = self.indices(wavelength_nm);
        let f = self.filling_fraction;
        (f * n_s * n_s + (1.0 - f) * n_m * n_m).sqrt()
    }

    /// The constant-index centre `x = λ n̄_d / n̄(λ)` of the line centred at `wavelength_nm`
    /// (the inverse of [`CrystalIndex::line`]'s centre; increasing in λ).
    #[inline]
    pub fn constant_centre_nm(&self, wavelength_nm: f64) -> f64 {
        if self.is_constant() {
            return wavelength_nm;
        }
        wavelength_nm * self.n_eff_d / self.n_eff(wavelength_nm)
    }

    /// `k = n_g / n̄ = 1 − λ n̄'/n̄` at `wavelength_nm` (1 for `dispersion = "none"`).
    #[inline]
    pub fn group_ratio(&self, wavelength_nm: f64) -> f64 {
        if self.is_constant() {
            return 1.0;
        }
        let (shift, slope) = self.offset(wavelength_nm);
        let f = self.filling_fraction;
        let (n_s, n_m) = (self.n_sphere_d + shift, self.n_matrix_d + shift);
        let n_eff = (f * n_s * n_s + (1.0 - f) * n_m * n_m).sqrt();
        // dn̄/dλ = (f n_s + (1 − f) n_m) dn/dλ / n̄: both indices move alike.
        let n_eff_slope = (f * n_s + (1.0 - f) * n_m) * slope / n_eff;
        1.0 - wavelength_nm * n_eff_slope / n_eff
    }

    /// The line whose centre at the constant index would be `constant_centre_nm` (> 0):
    /// its centre, coupling and group ratio with the dispersion (module notes). Exactly
    /// `(x, 1, 1)` for `dispersion = "none"`.
    pub fn line(&self, constant_centre_nm: f64) -> LineIndex {
        let x = constant_centre_nm;
        if self.is_constant() {
            return LineIndex {
                centre_nm: x,
                coupling_scale: 1.0,
                group_ratio: 1.0,
            };
        }
        let mut lambda = x;
        for _ in 0..FIXED_POINT_STEPS {
            lambda = x * self.n_eff(lambda) / self.n_eff_d;
        }
        // One Newton step on λ − x n̄(λ)/n̄_d = 0, whose slope is k = 1 − x n̄'/n̄_d here.
        let residual = lambda - x * self.n_eff(lambda) / self.n_eff_d;
        lambda -= residual / self.group_ratio(lambda);
        let (n_s, n_m) = self.indices(lambda);
        let f = self.filling_fraction;
        let contrast = (n_s * n_s - n_m * n_m) / (f * n_s * n_s + (1.0 - f) * n_m * n_m);
        LineIndex {
            centre_nm: lambda,
            coupling_scale: if self.contrast_d == 0.0 {
                1.0
            } else {
                contrast / self.contrast_d
            },
            group_ratio: self.group_ratio(lambda),
        }
    }

    /// The arguments of [`BraggLine::new`](super::BraggLine::new) for a family of coupling
    /// `coupling` (at the d line) whose face-on centre at the constant index is
    /// `normal_center_nm`, met at `cos_theta`: `(g', 2 d n̄', k)` such that
    /// `BraggLine::new(g', 2 d n̄', cos θ, k N)` is its line with the dispersion for `N`
    /// layers (module notes). The arguments unchanged and `k = 1` for `dispersion = "none"`.
    #[inline]
    pub fn line_args(
        &self,
        coupling: f64,
        normal_center_nm: f64,
        cos_theta: f64,
    ) -> (f64, f64, f64) {
        if self.is_constant() {
            return (coupling, normal_center_nm, 1.0);
        }
        let c = cos_theta.clamp(1e-3, 1.0);
        let x = normal_center_nm * c;
        let [shift, coupling_over_k, k] = match self.tabulated(x) {
            Some([shift, coupling_over_k, k, _]) => [shift, coupling_over_k, k],
            None => {
                let line = self.line(x);
                let k = line.group_ratio;
                [line.centre_nm - x, line.coupling_scale / k, k]
            }
        };
        (coupling * coupling_over_k, (x + shift) / c, k)
    }

    /// [`CrystalIndex::group_ratio`] read from the table (solved off it): what
    /// [`CrystalIndex::line_args`] scaled the layers of a line centred at `wavelength_nm` by,
    /// to 10⁻⁵.
    #[inline]
    pub fn line_group_ratio(&self, wavelength_nm: f64) -> f64 {
        if self.is_constant() {
            return 1.0;
        }
        self.tabulated(wavelength_nm)
            .map_or_else(|| self.group_ratio(wavelength_nm), |row| row[3])
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn silica_crystal() -> CrystalConfig {
        CrystalConfig {
            dispersion: Dispersion::Silica,
            ..CrystalConfig::default()
        }
    }

    #[test]
    fn sellmeier_slope_is_the_derivative_of_the_index() {
        for wl in [300.0, 404.7, 589.3, 706.5, 1500.0] {
            let h = 1e-3;
            let numeric = (fused_silica_index(wl + h).0 - fused_silica_index(wl - h).0) / (2.0 * h);
            let (_, slope) = fused_silica_index(wl);
            assert!(
                (slope / numeric - 1.0).abs() < 1e-6,
                "{wl}: {slope} {numeric}"
            );
        }
    }

    #[test]
    fn indices_hold_the_scenes_values_at_the_d_line() {
        let index = CrystalIndex::new(&silica_crystal());
        let (n_s, n_m) = index.indices(SODIUM_D_NM);
        assert!((n_s - 1.45).abs() < 1e-15 && (n_m - 1.42).abs() < 1e-15);
        assert!((index.n_eff(SODIUM_D_NM) - index.n_eff_d).abs() < 1e-15);
        // Both rise alike in the blue: the contrast in index is unchanged.
        let (n_s, n_m) = index.indices(420.0);
        assert!(
            n_s > 1.455 && ((n_s - n_m) - 0.03).abs() < 1e-12,
            "{n_s} {n_m}"
        );
    }

    #[test]
    fn the_line_centre_is_the_inverse_of_the_constant_centre() {
        let index = CrystalIndex::new(&silica_crystal());
        for lambda in [250.0, 380.0, 450.0, 589.3, 700.0, 1200.0, 2000.0] {
            let x = index.constant_centre_nm(lambda);
            let line = index.line(x);
            assert!((line.centre_nm - lambda).abs() < 1e-6, "{lambda}: {line:?}");
        }
    }

    #[test]
    fn the_table_agrees_with_the_solved_lines() {
        let index = CrystalIndex::new(&silica_crystal());
        let mut worst = [0.0f64; 3];
        for i in 0..20_000 {
            let x = 250.0 + 1800.0 * f64::from(i) / 20_000.0 + 0.013;
            let exact = index.line(x);
            let (coupling, normal, k) = index.line_args(0.01, x, 1.0);
            worst[0] = worst[0].max((normal - exact.centre_nm).abs());
            worst[1] = worst[1].max((coupling / 0.01 * k - exact.coupling_scale).abs());
            worst[2] = worst[2].max((k - exact.group_ratio).abs());
            let k_at = index.line_group_ratio(exact.centre_nm);
            worst[2] = worst[2].max((k_at - exact.group_ratio).abs());
        }
        assert!(
            worst[0] < 1e-4 && worst[1] < 1e-6 && worst[2] < 1e-5,
            "{worst:?}"
        );
        // Off the table, solved.
        let (_, normal, _) = index.line_args(0.01, 3000.0, 1.0);
        assert_eq!(normal, index.line(3000.0).centre_nm);
    }

    #[test]
    fn no_dispersion_leaves_a_line_unchanged() {
        let index = CrystalIndex::new(&CrystalConfig::default());
        let line = index.line(471.3);
        assert_eq!(line.centre_nm, 471.3);
        assert_eq!((line.coupling_scale, line.group_ratio), (1.0, 1.0));
        assert_eq!(index.n_eff(400.0), index.n_eff_d);
    }

    #[test]
    fn the_group_ratio_is_one_minus_the_log_slope_of_the_index() {
        // k = 1 − λ n̄'/n̄, with n̄' by central differences of n̄.
        let index = CrystalIndex::new(&silica_crystal());
        let line = index.line(index.constant_centre_nm(420.0));
        let h = 1e-3;
        let slope = (index.n_eff(420.0 + h) - index.n_eff(420.0 - h)) / (2.0 * h);
        let k = 1.0 - 420.0 * slope / index.n_eff(420.0);
        assert!((line.group_ratio - k).abs() < 1e-6, "{line:?} vs {k}");
        assert!(k > 1.02 && k < 1.03, "{k}");
    }
}

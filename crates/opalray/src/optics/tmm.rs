//! Thin-film transfer matrices for lossless layer stacks (Abelès characteristic matrices).
//!
//! Conventions (Macleod, *Thin-Film Optical Filters*, ch. 2): a layer of index `n` and
//! thickness `h`, met by light whose in-plane invariant is `κ = n₀ sin θ₀`, has the phase
//! thickness `β = 2π h √(n² − κ²) / λ` and the tilted admittance `η = √(n² − κ²)` for s
//! (TE) and `η = n² / √(n² − κ²)` for p (TM), in units of the free-space admittance. Its
//! characteristic matrix is `[[cos β, i sin β / η], [i η sin β, cos β]]`; a stack's matrix is
//! the product from the incident side.
//!
//! For real indices every such matrix has the form `[[a, i b], [i c, d]]` with real
//! `a, b, c, d` and determinant `ad + bc = 1`, also where a layer is evanescent
//! (`n < κ`: cos and sin become cosh and sinh). [`CharMatrix`] stores those four reals, so
//! the whole computation is real arithmetic.
//!
//! The N-th power of a unimodular 2×2 matrix is closed form (Abelès; Yeh, *Optical Waves in
//! Layered Media*, §6.2): `Mᴺ = U_{N−1}(x) M − U_{N−2}(x) I` with `x = tr M / 2` and `U` the
//! Chebyshev polynomials of the second kind.

use std::f64::consts::PI;

/// Polarisation of a plane wave relative to its plane of incidence.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Polarization {
    /// Electric field perpendicular to the plane of incidence (TE).
    S,
    /// Electric field in the plane of incidence (TM).
    P,
}

/// A homogeneous, lossless layer.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Layer {
    /// Real refractive index, ≥ 1 in practice (any positive value is accepted).
    pub n: f64,
    /// Physical thickness, nm, ≥ 0.
    pub thickness_nm: f64,
}

/// Characteristic matrix `[[a, i b], [i c, d]]` of a lossless layer or stack, with real
/// `a, b, c, d` and `ad + bc = 1`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CharMatrix {
    /// Upper-left element (real).
    pub a: f64,
    /// Upper-right element divided by `i`.
    pub b: f64,
    /// Lower-left element divided by `i`.
    pub c: f64,
    /// Lower-right element (real).
    pub d: f64,
}

impl CharMatrix {
    /// The identity: a stack of no layers.
    pub const IDENTITY: CharMatrix = CharMatrix {
        a: 1.0,
        b: 0.0,
        c: 0.0,
        d: 1.0,
    };

    /// Matrix of one layer of index `n` and thickness `thickness_nm` at `wavelength_nm`, for
    /// light whose squared in-plane invariant is `kappa_sq = (n₀ sin θ₀)²`.
    pub fn layer(
        n: f64,
        thickness_nm: f64,
        wavelength_nm: f64,
        kappa_sq: f64,
        pol: Polarization,
    ) -> CharMatrix {
        let g = n * n - kappa_sq;
        let k = 2.0 * PI * thickness_nm / wavelength_nm;
        let (cos_beta, sinc_beta) = cos_and_sinc(k * k * g);
        CharMatrix::from_phase(cos_beta, k * sinc_beta, g, n * n, 1.0 / (n * n), pol)
    }

    /// Assemble a layer matrix from `cos β`, `k·sin β / β` (with `k = 2π h / λ`), the
    /// squared normal index `g = n² − κ²`, `n²` and `1/n²`. Real for both signs of `g`:
    /// s: `b = k·sinc`, `c = g·k·sinc`; p: `b = g·k·sinc / n²`, `c = n²·k·sinc`.
    #[inline]
    pub(crate) fn from_phase(
        cos_beta: f64,
        k_sinc: f64,
        g: f64,
        n_sq: f64,
        inv_n_sq: f64,
        pol: Polarization,
    ) -> CharMatrix {
        let (b, c) = match pol {
            Polarization::S => (k_sinc, g * k_sinc),
            Polarization::P => (g * k_sinc * inv_n_sq, n_sq * k_sinc),
        };
        CharMatrix {
            a: cos_beta,
            b,
            c,
            d: cos_beta,
        }
    }

    /// Half the trace, `x = (a + d) / 2`: `|x| < 1` in a pass band of the periodic stack this
    /// matrix is the period of, `|x| > 1` in a stop band.
    #[inline]
    pub fn half_trace(&self) -> f64 {
        0.5 * (self.a + self.d)
    }

    /// Determinant `ad + bc` (1 up to rounding).
    pub fn det(&self) -> f64 {
        self.a * self.d + self.b * self.c
    }

    /// `selfⁿ` in closed form, `U_{n−1}(x)·M − U_{n−2}(x)·I` (no repeated products).
    #[must_use]
    pub fn power(self, n: u32) -> CharMatrix {
        if n == 0 {
            return CharMatrix::IDENTITY;
        }
        let x = self.half_trace();
        let u1 = chebyshev_u(n - 1, x);
        let u2 = if n >= 2 { chebyshev_u(n - 2, x) } else { 0.0 };
        CharMatrix {
            a: u1 * self.a - u2,
            b: u1 * self.b,
            c: u1 * self.c,
            d: u1 * self.d - u2,
        }
    }
}

/// Below this |β| the series `1 − β²/2`, `1 − β²/6` are exact to rounding.
pub(crate) const SERIES_BELOW: f64 = 1e-4;

impl std::ops::Mul for CharMatrix {
    type Output = CharMatrix;

    /// The product `self · rhs` (`self` nearer the incident medium).
    #[inline]
    fn mul(self, rhs: CharMatrix) -> CharMatrix {
        CharMatrix {
            a: self.a * rhs.a - self.b * rhs.c,
            b: self.a * rhs.b + self.b * rhs.d,
            c: self.c * rhs.a + self.d * rhs.c,
            d: self.d * rhs.d - self.c * rhs.b,
        }
    }
}

/// `cos β` and `sin β / β` for `β² = beta_sq`, continued to `cosh` and `sinh β / β` for
/// `beta_sq < 0` (evanescent layers).
#[inline]
pub(crate) fn cos_and_sinc(beta_sq: f64) -> (f64, f64) {
    let beta = beta_sq.abs().sqrt();
    if beta < SERIES_BELOW {
        return (1.0 - 0.5 * beta_sq, 1.0 - beta_sq / 6.0);
    }
    if beta_sq >= 0.0 {
        let (s, c) = beta.sin_cos();
        (c, s / beta)
    } else {
        (beta.cosh(), beta.sinh() / beta)
    }
}

/// Chebyshev polynomial of the second kind `U_n(x)` in closed form:
/// `sin((n+1)φ) / sin φ` with `x = cos φ` for `|x| ≤ 1`, `sinh((n+1)φ) / sinh φ` with
/// `|x| = cosh φ` beyond (times `(−1)ⁿ` for `x < −1`); `n + 1` at `|x| = 1`. Overflows to
/// ±∞ deep in a stop band of a long stack, which callers treat as total reflection.
pub fn chebyshev_u(n: u32, x: f64) -> f64 {
    let m = f64::from(n) + 1.0;
    let y = x.abs();
    let magnitude_sign = if x < 0.0 && n % 2 == 1 { -1.0 } else { 1.0 };
    if y <= 1.0 {
        // sin φ from (1 − y)(1 + y) keeps precision near the band edge y → 1.
        let s = ((1.0 - y) * (1.0 + y)).sqrt();
        if s == 0.0 {
            return magnitude_sign * m;
        }
        let phi = s.atan2(x);
        (m * phi).sin() / s
    } else {
        let s = ((y - 1.0) * (y + 1.0)).sqrt();
        let phi = s.asinh();
        magnitude_sign * (m * phi).sinh() / s
    }
}

/// Tilted admittance of a semi-infinite medium for `g = n² − κ² > 0`.
#[inline]
pub(crate) fn admittance(g: f64, n_sq: f64, pol: Polarization) -> f64 {
    match pol {
        Polarization::S => g.sqrt(),
        Polarization::P => n_sq / g.sqrt(),
    }
}

/// Reflectance and transmittance `(R, T)` (energy fractions) of a stack with matrix `m`
/// between an incident medium of admittance `eta0 > 0` and a substrate of admittance
/// `eta_s > 0` (both propagating). `R + T = 1` up to rounding, since `det m = 1`.
pub fn stack_rt_from_matrix(m: &CharMatrix, eta0: f64, eta_s: f64) -> (f64, f64) {
    // r = (η₀B − C)/(η₀B + C), [B, C] = M·[1, η_s] (Macleod eq. 2.89); t = 2η₀/(η₀B + C).
    let re_num = eta0 * m.a - eta_s * m.d;
    let im_num = eta0 * eta_s * m.b - m.c;
    let re_den = eta0 * m.a + eta_s * m.d;
    let im_den = eta0 * eta_s * m.b + m.c;
    let den = re_den * re_den + im_den * im_den;
    (
        (re_num * re_num + im_num * im_num) / den,
        4.0 * eta0 * eta_s / den,
    )
}

/// `(R, T)` of `layers` (listed from the incident side) between an incident medium of index
/// `n0` and a substrate of index `n_sub`, for light arriving at `theta0_rad` (in `n0`, from
/// the normal, `[0, π/2)`) and `wavelength_nm`. A substrate the light cannot enter (total
/// internal reflection) gives `(1, 0)`.
pub fn stack_rt(
    n0: f64,
    layers: &[Layer],
    n_sub: f64,
    theta0_rad: f64,
    wavelength_nm: f64,
    pol: Polarization,
) -> (f64, f64) {
    let kappa_sq = (n0 * theta0_rad.sin()).powi(2);
    let g0 = n0 * n0 - kappa_sq;
    let g_sub = n_sub * n_sub - kappa_sq;
    if g_sub <= 0.0 {
        return (1.0, 0.0);
    }
    let m = layers.iter().fold(CharMatrix::IDENTITY, |acc, l| {
        acc * CharMatrix::layer(l.n, l.thickness_nm, wavelength_nm, kappa_sq, pol)
    });
    stack_rt_from_matrix(
        &m,
        admittance(g0, n0 * n0, pol),
        admittance(g_sub, n_sub * n_sub, pol),
    )
}

/// `U_n(x)²` in closed form, as [`chebyshev_u`] squared but cheaper (no sign, one inverse
/// trigonometric call): `sin²((n+1)φ) / (1 − x²)`, `x = cos φ`, or `sinh²((n+1)φ) / (x² − 1)`,
/// `|x| = cosh φ`.
#[inline]
pub fn chebyshev_u_squared(n: u32, x: f64) -> f64 {
    let m = f64::from(n) + 1.0;
    let y = x.abs();
    // 1 − x² as (1 − y)(1 + y) keeps precision near the band edge y → 1.
    let one_minus_y_sq = (1.0 - y) * (1.0 + y);
    if one_minus_y_sq == 0.0 {
        return m * m;
    }
    let s = if y < 1.0 {
        (m * x.acos()).sin()
    } else {
        (m * y.acosh()).sinh()
    };
    s * s / one_minus_y_sq.abs()
}

/// `(R, T)` of `periods` repeats of the period matrix `period`, embedded in one medium of
/// admittance `eta > 0` on both sides, via the closed-form power:
/// `R = U²P / (U²P + 4)`, `T = 4 / (U²P + 4)`, `U = U_{N−1}(x)`,
/// `P = (a − d)² + (ηb − c/η)²` (Yeh eq. 6.2-25 in matrix form). Overflow deep in a stop
/// band gives `(1, 0)`.
#[inline]
pub fn periodic_rt(period: &CharMatrix, periods: u32, eta: f64) -> (f64, f64) {
    if periods == 0 {
        return (0.0, 1.0);
    }
    let u_sq = chebyshev_u_squared(periods - 1, period.half_trace());
    let p = (period.a - period.d).powi(2) + (eta * period.b - period.c / eta).powi(2);
    let q = u_sq * p;
    if q.is_finite() {
        // Two correctly rounded divisions: q / (q + 4) never rounds above 1, where
        // q · (1 / (q + 4)) can by an ulp.
        let sum = q + 4.0;
        (q / sum, 4.0 / sum)
    } else if p == 0.0 {
        (0.0, 1.0)
    } else {
        (1.0, 0.0)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn chebyshev_u_matches_its_recurrence() {
        // U_0 = 1, U_1 = 2x, U_{n+1} = 2x U_n − U_{n−1} (the definition).
        for &x in &[
            -1.7, -1.0, -0.99, -0.3, 0.0, 0.4, 0.999_999, 1.0, 1.000_001, 1.3,
        ] {
            let (mut prev, mut cur) = (1.0, 2.0 * x);
            assert!((chebyshev_u(0, x) - 1.0).abs() < 1e-12);
            for n in 1..40u32 {
                let expect: f64 = cur;
                let got = chebyshev_u(n, x);
                assert!(
                    (got - expect).abs() <= 1e-9 * expect.abs().max(1.0),
                    "U_{n}({x}) = {got}, recurrence {expect}"
                );
                (prev, cur) = (cur, 2.0 * x * cur - prev);
            }
        }
    }

    #[test]
    fn chebyshev_u_squared_is_the_square_of_chebyshev_u() {
        for &x in &[
            -3.0,
            -1.0,
            -0.999_999_9,
            -0.2,
            0.0,
            0.5,
            0.999_999_9,
            1.0,
            1.000_01,
            2.5,
        ] {
            for n in [0u32, 1, 2, 7, 64, 399] {
                let u = chebyshev_u(n, x);
                let sq = chebyshev_u_squared(n, x);
                let ok = sq == u * u || (sq - u * u).abs() <= 1e-9 * (u * u).max(1.0);
                assert!(ok, "n {n} x {x}: {sq} vs {}", u * u);
            }
        }
    }

    #[test]
    fn layer_matrix_is_unimodular_for_propagating_and_evanescent_layers() {
        for pol in [Polarization::S, Polarization::P] {
            for &kappa_sq in &[0.0, 1.0, 2.1, 2.5] {
                let m = CharMatrix::layer(1.45, 120.0, 550.0, kappa_sq, pol);
                assert!(
                    (m.det() - 1.0).abs() < 1e-12,
                    "{pol:?} κ²={kappa_sq}: {m:?}"
                );
            }
        }
    }

    #[test]
    fn zero_thickness_layer_is_the_identity() {
        let m = CharMatrix::layer(2.0, 0.0, 500.0, 0.3, Polarization::P);
        assert_eq!(m, CharMatrix::IDENTITY);
    }

    #[test]
    fn half_wave_layer_is_absent_at_normal_incidence() {
        // A half-wave layer (n h = λ/2) is an "absentee": matrix −I (Macleod §2.5).
        let m = CharMatrix::layer(1.5, 200.0, 600.0, 0.0, Polarization::S);
        assert!((m.a + 1.0).abs() < 1e-12 && (m.d + 1.0).abs() < 1e-12);
        assert!(m.b.abs() < 1e-12 && m.c.abs() < 1e-12);
    }

    #[test]
    fn periodic_rt_with_no_periods_is_transparent() {
        let m = CharMatrix::layer(1.5, 100.0, 500.0, 0.0, Polarization::S);
        assert_eq!(periodic_rt(&m, 0, 1.4), (0.0, 1.0));
    }
}

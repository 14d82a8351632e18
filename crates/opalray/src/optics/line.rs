//! One Bragg line as an analytic function of wavelength: the first-order reflection of a
//! family of planes met at a given angle by a finite stack, by coupled-wave theory.
//!
//! Input: the family's coupling `g`, the Bragg wavelength, the angle and the number of layers →
//! output: [`BraggLine`], whose [`BraggLine::reflectance`] can be evaluated at any wavelength
//! (no bins: lines are ~2 nm wide and are carried exactly through chains of reflections and
//! transmissions, and binned only for colour).
//!
//! A sinusoidal permittivity `ε̄ + 2ε_G cos(Gz)` of N periods d, met by a plane wave at angle θ
//! to its normal inside (c = cos θ), couples the forward and backward waves with
//! `κL = ν = (π/2)·N·g/c²·(λ_B/λ)` (s polarisation; p: times |cos 2θ|) and detunes them by
//! `σL = π N (λ_B/λ − 1)`, `λ_B = 2 d n̄ c`. The reflectance of the uniform grating is
//! (Kogelnik 1969; Yariv & Yeh, *Optical Waves in Crystals*, §6.5)
//!
//! `R = ν² sinh² s / (s² + ν² sinh² s)`, `s = √(ν² − (σL)²)` (sinh → sin past the band edge).
//!
//! At the Bragg wavelength `R = tanh² ν`; the stop band spans `|λ_B/λ − 1| < g/(2c²)`. For weak
//! contrast this agrees with the transfer-matrix result of the square-wave stack (`optics::tmm`)
//! to a few 10⁻³ (tested), at a fraction of its cost.

use std::f64::consts::PI;

/// Half-width of the window outside which a line is treated as zero, in units of its stop
/// band's half-width: past it the side lobes average `ν²/(2σ²)`, under 3·10⁻⁴ of the peak, and
/// the area left out, `ν/40` against the stop band's `2ν` (in units of σL), about 1 % of the
/// line's.
pub const WINDOW_HALF_WIDTHS: f64 = 40.0;

/// Side lobes (each `λ/N` wide) a thin stack's window keeps at least on either side.
const WINDOW_SIDE_LOBES: f64 = 8.0;

/// Relative margin of [`BraggLine::window_may_hold`]'s bound over the window's computed
/// half-width: far above the few roundings of either (~10⁻¹⁵), so the bound never excludes a
/// wavelength the window holds.
const WINDOW_BOUND_MARGIN: f64 = 1e-6;

/// A family's first-order Bragg line at one angle, for one finite stack.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BraggLine {
    /// Bragg wavelength `2 d n̄ cos θ`, nm.
    pub center_nm: f64,
    /// Coupling `ν` of s-polarised light at the Bragg wavelength.
    pub nu_s: f64,
    /// Coupling of p-polarised light at the Bragg wavelength (`ν_s |cos 2θ|`).
    pub nu_p: f64,
    /// Periods N met.
    pub layers: f64,
}

impl BraggLine {
    /// The line of a family of coupling `coupling` (`g`), Bragg wavelength at normal incidence
    /// `normal_center_nm` (`2 d n̄`), met at `cos_theta` (inside, in (0, 1]) by `layers` periods.
    #[inline]
    pub fn new(coupling: f64, normal_center_nm: f64, cos_theta: f64, layers: f64) -> BraggLine {
        let c = cos_theta.clamp(1e-3, 1.0);
        let nu_s = 0.5 * PI * layers * coupling / (c * c);
        BraggLine {
            center_nm: normal_center_nm * c,
            nu_s,
            nu_p: nu_s * (2.0 * c * c - 1.0).abs(),
            layers,
        }
    }

    /// Half-width of the stop band, nm (s polarisation, the wider).
    #[inline]
    pub fn half_width_nm(&self) -> f64 {
        // |λ_B/λ − 1| < ν/(πN) at the band edge.
        self.center_nm * self.nu_s / (PI * self.layers).max(1e-9)
    }

    /// The wavelengths outside which the line is treated as zero, nm.
    #[inline]
    pub fn window_nm(&self) -> (f64, f64) {
        // Thin stacks have broad lines: at least a few side lobes (λ/N apart) are kept.
        let half = (WINDOW_HALF_WIDTHS * self.half_width_nm())
            .max(WINDOW_SIDE_LOBES * self.center_nm / self.layers.max(1.0));
        (self.center_nm - half, self.center_nm + half)
    }

    /// False only if the window ([`BraggLine::window_nm`]) of the line
    /// `BraggLine::new(coupling, normal_center_nm, cos_theta, layers)` cannot
    /// hold `wavelength_nm`, without building the line: its half-width is
    /// `λ_B · max(40 g / 2c², 8 / N)` (the stop band's `ν/(πN) = g/2c²`), bounded here with a
    /// margin so that every line whose window holds the wavelength passes.
    #[inline]
    pub fn window_may_hold(
        coupling: f64,
        normal_center_nm: f64,
        cos_theta: f64,
        layers: f64,
        wavelength_nm: f64,
    ) -> bool {
        let c = cos_theta.clamp(1e-3, 1.0);
        let center = normal_center_nm * c;
        let off = (wavelength_nm - center).abs();
        let reach = center * (1.0 + WINDOW_BOUND_MARGIN);
        // Outside when beyond both parts of the half-width (NaN never counts as outside).
        let beyond_band = off * c * c >= 0.5 * WINDOW_HALF_WIDTHS * coupling * reach;
        let beyond_lobes = off * layers.max(1.0) >= WINDOW_SIDE_LOBES * reach;
        !(beyond_band && beyond_lobes)
    }

    /// Unpolarised reflectance at `wavelength_nm`: the mean of
    /// [`BraggLine::reflectance_sp`]'s two.
    #[inline]
    pub fn reflectance(&self, wavelength_nm: f64) -> f64 {
        let (rs, rp) = self.reflectance_sp(wavelength_nm);
        0.5 * (rs + rp)
    }

    /// Reflectances of s- and p-polarised light at `wavelength_nm`, `(R_s, R_p)`, each in
    /// [0, 1] (relative to the plane holding the incident direction and the planes' normal).
    #[inline]
    pub fn reflectance_sp(&self, wavelength_nm: f64) -> (f64, f64) {
        let ratio = self.center_nm / wavelength_nm;
        let sigma = PI * self.layers * (ratio - 1.0);
        (
            grating_r(self.nu_s * ratio, sigma),
            grating_r(self.nu_p * ratio, sigma),
        )
    }

    /// Peak reflectance (unpolarised), `(tanh² ν_s + tanh² ν_p)/2`.
    pub fn peak(&self) -> f64 {
        0.5 * (self.nu_s.tanh().powi(2) + self.nu_p.tanh().powi(2))
    }
}

/// Reflectance of a uniform grating of coupling `nu` (= κL) at detuning `sigma` (= σL).
#[inline]
fn grating_r(nu: f64, sigma: f64) -> f64 {
    let nu2 = nu * nu;
    let d = nu2 - sigma * sigma;
    if d > 1e-12 {
        let s = d.sqrt();
        if s > 20.0 {
            // sinh² s / (s²/ν² + sinh² s) → 1 − s²/(ν² sinh² s), under 10⁻¹⁵ off 1.
            return 1.0;
        }
        let sh = s.sinh();
        let sh2 = sh * sh;
        nu2 * sh2 / (d + nu2 * sh2)
    } else if d < -1e-12 {
        let sn2 = sin_squared((-d).sqrt());
        nu2 * sn2 / (-d + nu2 * sn2)
    } else {
        nu2 / (1.0 + nu2)
    }
}

/// `sin² x` (libm's past 10⁶, where the lines never reach): x reduced by the nearest multiple of π (sin² has period π)
/// to `r ∈ [−π/2, π/2]`, then sin r by its Taylor series to r¹⁵, whose first term left out
/// is at most 6.1·10⁻¹² there. The side lobes of every line a path crosses are evaluated here,
/// and libm's `sin`, with its general range reduction, took an eighth of a render's time.
#[inline]
fn sin_squared(x: f64) -> f64 {
    if x.is_nan() || x.abs() >= 1e6 {
        return x.sin().powi(2);
    }
    // π as the sum of two doubles, the first of 33 bits so that k·PI_HI is exact for k < 2²⁰
    // and x − k·PI_HI loses nothing (Cody & Waite); what is left of π is under 10⁻²⁶.
    const PI_HI: f64 = 3.141_592_653_468_251_2;
    const PI_LO: f64 = 1.215_420_101_301_238_4e-10;
    let k = round_half_away(x * (1.0 / PI));
    let r = (x - k * PI_HI) - k * PI_LO;
    let r2 = r * r;
    // sin r = r (1 − r²/3! + r⁴/5! − … − r¹⁴/15!), in Horner form.
    let mut p = -1.0 / 1_307_674_368_000.0;
    p = p * r2 + 1.0 / 6_227_020_800.0;
    p = p * r2 - 1.0 / 39_916_800.0;
    p = p * r2 + 1.0 / 362_880.0;
    p = p * r2 - 1.0 / 5_040.0;
    p = p * r2 + 1.0 / 120.0;
    p = p * r2 - 1.0 / 6.0;
    p = p * r2 + 1.0;
    let sn = r * p;
    sn * sn
}

/// `y.round()` (halves away from 0) for `|y| < 2⁵²`, without the library call that `round`
/// is on processors before SSE4.1 (3 % of a render's instructions).
#[inline]
fn round_half_away(y: f64) -> f64 {
    let a = y.abs();
    // The integer part (exact below 2⁶³), and one more where the fraction (exact) is ½ or more.
    let whole = a as i64 as f64;
    let k = if a - whole >= 0.5 { whole + 1.0 } else { whole };
    k.copysign(y)
}

/// Full width at half maximum of the rocking curve, radians: the reflectance at the fixed
/// wavelength `λ_B(θ₀)` as the stack turns about θ₀ (`cos_theta0` = cos θ₀, inside), for a
/// family of coupling `coupling` and `layers` periods. Turning through the normal is allowed
/// (θ < 0), as a real rocking scan does.
pub fn rocking_fwhm_rad(coupling: f64, cos_theta0: f64, layers: f64) -> f64 {
    let theta0 = cos_theta0.clamp(0.0, 1.0).acos();
    let lambda = 2.0 * cos_theta0; // λ_B(θ₀) for 2 d n̄ = 2 (the scale drops out)
    let r_at = |theta: f64| BraggLine::new(coupling, 2.0, theta.cos(), layers).reflectance(lambda);
    let half = 0.5 * r_at(theta0);
    // Walk out from θ₀ in small steps until the curve falls below half, then bisect.
    let edge = |dir: f64| {
        let step = 1e-4;
        let mut inner = theta0;
        let mut outer = theta0;
        for _ in 0..200_000 {
            outer += dir * step;
            if r_at(outer) < half {
                break;
            }
            inner = outer;
        }
        for _ in 0..50 {
            let mid = 0.5 * (inner + outer);
            if r_at(mid) < half {
                outer = mid;
            } else {
                inner = mid;
            }
        }
        0.5 * (inner + outer)
    };
    edge(1.0) - edge(-1.0)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::ClusterStack;
    use crate::scene::CrystalConfig;

    #[test]
    fn sin_squared_agrees_with_libm() {
        // Over the side lobes' range (and far past it), near the zeros and the peaks.
        let mut worst = 0.0f64;
        let mut worst_near_zero = 0.0f64;
        for i in 0..200_000 {
            let x = f64::from(i) * 0.013_7 + 1e-7 * f64::from(i % 7);
            let exact = x.sin().powi(2);
            worst = worst.max((sin_squared(x) - exact).abs());
            // Near a zero, relative accuracy: the reduction must not lose the small remainder.
            let k = f64::from(i % 3000);
            let z = k * PI + 1e-6;
            let exact_z = z.sin().powi(2);
            worst_near_zero = worst_near_zero.max((sin_squared(z) / exact_z - 1.0).abs());
        }
        assert!(worst < 2e-11, "largest difference {worst:e}");
        for x in [-2.5, 1e6, 3.7e7] {
            assert!((sin_squared(x) - x.sin().powi(2)).abs() < 2e-11, "at {x}");
        }
        assert!(
            worst_near_zero < 1e-6,
            "largest relative difference near zeros {worst_near_zero:e}"
        );
    }

    #[test]
    fn round_half_away_is_round() {
        // Halves, their neighbours an ulp away, and the reduction's range of multiples of π.
        let mut xs = vec![
            0.0,
            -0.0,
            0.5,
            -0.5,
            1.5,
            2.5,
            -2.5,
            0.499_999_999_999_999_94,
        ];
        for k in 0..400_000 {
            let y = f64::from(k) * 0.8 - 2e5 + f64::from(k % 13) * 1e-3;
            xs.extend([
                y,
                (y.floor() + 0.5),
                (y.floor() + 0.5).next_down(),
                y.next_up(),
            ]);
        }
        for y in xs {
            assert_eq!(round_half_away(y).to_bits(), y.round().to_bits(), "{y:e}");
        }
    }

    #[test]
    fn window_bound_keeps_every_wavelength_the_window_holds() {
        // Lines from thin to thick stacks, weak to strong coupling, face-on to grazing; the
        // wavelengths at and next to each window's edges, and spread over twice its width.
        let mut state = 0x2545_f491_4f6c_dd1du64;
        let mut uniform = || {
            state ^= state << 13;
            state ^= state >> 7;
            state ^= state << 17;
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        let (mut held, mut outside, mut excluded) = (0, 0, 0);
        for _ in 0..20_000 {
            let g = 10f64.powf(-4.0 + 3.0 * uniform());
            let normal_center = 300.0 + 900.0 * uniform();
            let c = 1.05 * uniform();
            let layers = (10f64.powf(4.0 * uniform())).max(1.0);
            let line = BraggLine::new(g, normal_center, c, layers);
            let (lo, hi) = line.window_nm();
            // At the edges and just inside them (a few ulps).
            let ulps = |x: f64| 4.0 * x.abs() * f64::EPSILON;
            let mut wavelengths = vec![lo, hi, lo + ulps(lo), hi - ulps(hi)];
            wavelengths.extend((0..8).map(|_| lo - 0.5 * (hi - lo) + 2.0 * (hi - lo) * uniform()));
            for w in wavelengths {
                let holds = !(w <= lo || w >= hi);
                let may = BraggLine::window_may_hold(g, normal_center, c, layers, w);
                assert!(may || !holds, "{line:?} holds {w} in ({lo}, {hi})");
                held += usize::from(holds);
                // Beyond the margin, the bound excludes what the window does.
                if (w - 0.5 * (lo + hi)).abs() > 0.5 * (hi - lo) * (1.0 + 1e-5) {
                    outside += 1;
                    excluded += usize::from(!may);
                }
            }
        }
        assert!(held > 50_000, "{held} held");
        assert_eq!(excluded, outside, "{excluded} of {outside} excluded");
    }

    #[test]
    fn peak_is_tanh_squared_at_normal_incidence() {
        let line = BraggLine::new(0.0037, 589.0, 1.0, 400.0);
        let expected = (0.5 * PI * 400.0 * 0.0037f64).tanh().powi(2);
        assert!((line.reflectance(589.0) - expected).abs() < 1e-12);
        assert!((line.peak() - expected).abs() < 1e-12);
    }

    #[test]
    fn the_line_agrees_with_the_transfer_matrix_stack() {
        // Independent check: the exact TMM of the square-wave stack (optics::tmm).
        let crystal = CrystalConfig::default();
        let stack = ClusterStack::new(&crystal).unwrap();
        let g = stack.relative_gap();
        let two_dn = 2.0 * stack.d111_nm * stack.n_eff;
        for cos_theta in [1.0, 0.9, 0.75] {
            let line = BraggLine::new(g, two_dn, cos_theta, f64::from(crystal.layers));
            let at = stack.at(cos_theta);
            let mut worst = 0.0f64;
            let (lo, hi) = (line.center_nm - 6.0, line.center_nm + 6.0);
            for k in 0..=1200 {
                let lambda = lo + (hi - lo) * k as f64 / 1200.0;
                let (r_tmm, _) = at.rt_unpolarized(lambda);
                worst = worst.max((line.reflectance(lambda) - r_tmm).abs());
            }
            assert!(worst < 0.03, "cos θ {cos_theta}: worst |ΔR| {worst}");
        }
    }

    #[test]
    fn rocking_widths_match_the_finite_stack() {
        // DESIGN §4 / the crystal issue: 400 layers in cement 1.42, FWHM inside at
        // 5°/10°/20°/30°: 3.46°/1.60°/0.76°/0.48° (from a separate transfer-matrix code).
        let stack = ClusterStack::new(&CrystalConfig::default()).unwrap();
        let g = stack.relative_gap();
        for (deg, fwhm) in [(5.0f64, 3.46f64), (10.0, 1.60), (20.0, 0.76), (30.0, 0.48)] {
            let w = rocking_fwhm_rad(g, deg.to_radians().cos(), 400.0).to_degrees();
            assert!((w / fwhm - 1.0).abs() < 0.1, "{deg}°: {w}° vs {fwhm}°");
        }
    }
}

//! The FCC cluster seen along \[111\] as a one-dimensional periodic stack (paper §2.3).
//!
//! Input: a [`CrystalConfig`] → output: a [`ClusterStack`], the layer model the reflectance
//! tables are computed from.
//!
//! - (111) spacing `d = D·√(2/3)` (D = centre-to-centre distance of touching spheres);
//!   mean permittivity `ε̄ = f ε_s + (1 − f) ε_m`, `n_eff = √ε̄` (DESIGN §4).
//! - First Fourier coefficient of ε(r) for the (111) reciprocal vector, spheres of radius r
//!   on the FCC lattice (four per cubic cell, all in phase for 111):
//!   `ε₁₁₁ = 3 f (ε_s − ε_m) (sin x − x cos x) / x³`, `x = G₁₁₁ r`, `G₁₁₁ = 2π / d`.
//!   The radius follows from the filling fraction on the lattice of D:
//!   `f = 16π r³ / (3 a³)`, `a = √2 D` (r = D/2 at f = π/(3√2) ≈ 0.7405).
//! - The period is two layers of equal thickness `d/2` and permittivities `ε̄ ± π ε₁₁₁ / 2`:
//!   a square wave of duty 1/2 has mean `ε̄` and first Fourier coefficient
//!   `(ε_hi − ε_lo) / π = ε₁₁₁`, so the stack couples forward and backward waves exactly as
//!   strongly as the crystal does and its stop band has the crystal's width. Its even
//!   harmonics vanish (the crystal's (222) is ~1 % of the (111), negligible).

use std::f64::consts::PI;

use super::tmm::{periodic_rt, CharMatrix, Polarization, SERIES_BELOW};
use crate::error::Result;
use crate::scene::CrystalConfig;

/// Sphere form factor `3 (sin x − x cos x) / x³` (the Fourier transform of a uniform ball,
/// normalised to 1 at x = 0).
pub fn sphere_form_factor(x: f64) -> f64 {
    if x.abs() < 1e-3 {
        return 1.0 - x * x / 10.0;
    }
    3.0 * (x.sin() - x * x.cos()) / (x * x * x)
}

/// The (111) layer model of one cluster: `periods` repeats of a high-index and a low-index
/// layer, each `d111_nm / 2` thick, embedded in the effective medium `n_eff` on both sides.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ClusterStack {
    /// (111) plane spacing `D·√(2/3)`, nm.
    pub d111_nm: f64,
    /// Effective index `√(f n_s² + (1 − f) n_m²)` of the cluster.
    pub n_eff: f64,
    /// `|ε₁₁₁|`, modulus of the first Fourier coefficient of the permittivity along \[111\].
    pub eps_111: f64,
    /// Index of the high layer, `√(n_eff² + π ε₁₁₁ / 2)`.
    pub n_high: f64,
    /// Index of the low layer, `√(n_eff² − π ε₁₁₁ / 2)`.
    pub n_low: f64,
    /// Number of periods N (coherent (111) layers).
    pub periods: u32,
}

impl ClusterStack {
    /// The layer model of `crystal` (validated first).
    pub fn new(crystal: &CrystalConfig) -> Result<ClusterStack> {
        crystal.validate()?;
        Ok(ClusterStack::with_indices(
            crystal,
            crystal.n_sphere,
            crystal.n_matrix,
        ))
    }

    /// The layer model of `crystal` (valid) with the spheres' index `n_sphere` and the
    /// matrix's `n_matrix` in place of its own: the stack at one wavelength when the indices
    /// vary with it ([`CrystalIndex::indices`](super::CrystalIndex::indices)).
    pub fn with_indices(crystal: &CrystalConfig, n_sphere: f64, n_matrix: f64) -> ClusterStack {
        let f = crystal.filling_fraction;
        let eps_s = n_sphere * n_sphere;
        let eps_m = n_matrix * n_matrix;
        let eps_mean = f * eps_s + (1.0 - f) * eps_m;
        let d111_nm = crystal.sphere_diameter_nm * (2.0f64 / 3.0).sqrt();
        let cube_nm = std::f64::consts::SQRT_2 * crystal.sphere_diameter_nm;
        let radius_nm = cube_nm * (3.0 * f / (16.0 * PI)).cbrt();
        let x = 2.0 * PI / d111_nm * radius_nm;
        let eps_111 = (f * (eps_s - eps_m) * sphere_form_factor(x)).abs();
        let half_step = 0.5 * PI * eps_111;
        ClusterStack {
            d111_nm,
            n_eff: eps_mean.sqrt(),
            eps_111,
            n_high: (eps_mean + half_step).sqrt(),
            n_low: (eps_mean - half_step).sqrt(),
            periods: crystal.layers,
        }
    }

    /// Coupled-wave estimate of the relative width `Δλ/λ` of the first-order stop band at
    /// normal incidence, `ε₁₁₁ / ε̄`.
    pub fn relative_gap(&self) -> f64 {
        self.eps_111 / (self.n_eff * self.n_eff)
    }

    /// Bragg wavelength inside the stone, `2 d n_eff cos θ`, nm.
    pub fn bragg_wavelength_nm(&self, cos_theta: f64) -> f64 {
        super::bragg_wavelength_inside_nm(self.d111_nm, self.n_eff, cos_theta)
    }

    /// The stack for light meeting the planes at `cos θ` inside the stone (`[0, 1]`).
    pub fn at(&self, cos_theta: f64) -> StackAtAngle {
        let cos_theta = cos_theta.clamp(0.0, 1.0);
        let kappa_sq = self.n_eff * self.n_eff * (1.0 - cos_theta * cos_theta);
        StackAtAngle {
            high: LayerAtAngle::new(self.n_high, kappa_sq),
            low: LayerAtAngle::new(self.n_low, kappa_sq),
            pi_d_nm: PI * self.d111_nm,
            eta_s: self.n_eff * cos_theta,
            eta_p: self.n_eff / cos_theta,
            periods: self.periods,
        }
    }

    /// The first-order stop band `(λ_lo, λ_hi)` in nm for polarisation `pol` at `cos θ`
    /// inside: the wavelengths where the half trace of the period matrix crosses ±1 around
    /// the Bragg wavelength (the band gap of the infinite crystal). `None` where there is no
    /// gap (p light at the Brewster angle of the layers, or evanescent low layers).
    pub fn stop_band_nm(&self, cos_theta: f64, pol: Polarization) -> Option<(f64, f64)> {
        let at = self.at(cos_theta);
        if at.low.g <= 0.0 {
            return None;
        }
        // Centre of the first-order gap: phase thickness of one period = π.
        let centre = self.d111_nm * (at.high.g.sqrt() + at.low.g.sqrt());
        let excess = |wl: f64| at.period(wl, pol).half_trace().abs() - 1.0;
        if excess(centre) <= 0.0 {
            return None;
        }
        let edge = |mut inside: f64, mut outside: f64| {
            for _ in 0..80 {
                let mid = 0.5 * (inside + outside);
                if excess(mid) > 0.0 {
                    inside = mid;
                } else {
                    outside = mid;
                }
            }
            0.5 * (inside + outside)
        };
        Some((edge(centre, 0.75 * centre), edge(centre, 1.5 * centre)))
    }
}

/// One layer (thickness d/2) of the period at a fixed angle.
#[derive(Clone, Copy, Debug)]
struct LayerAtAngle {
    /// `g = n² − κ²`, negative where the layer is evanescent.
    g: f64,
    /// `n²` and `1/n²`.
    n_sq: f64,
    inv_n_sq: f64,
    /// `√|g|` and its inverse (0 where g = 0).
    root: f64,
    inv_root: f64,
}

impl LayerAtAngle {
    fn new(n: f64, kappa_sq: f64) -> LayerAtAngle {
        let g = n * n - kappa_sq;
        let root = g.abs().sqrt();
        LayerAtAngle {
            g,
            n_sq: n * n,
            inv_n_sq: 1.0 / (n * n),
            root,
            inv_root: if root > 0.0 { 1.0 / root } else { 0.0 },
        }
    }

    /// `(cos β, k·sin β / β)` for `k = 2π h / λ` and the phase thickness `β = k √g`
    /// (cosh and sinh where g < 0).
    #[inline]
    fn phase(&self, k: f64) -> (f64, f64) {
        let beta = k * self.root;
        if beta < SERIES_BELOW {
            let beta_sq = k * k * self.g;
            (1.0 - 0.5 * beta_sq, k * (1.0 - beta_sq / 6.0))
        } else if self.g > 0.0 {
            let (s, c) = beta.sin_cos();
            (c, s * self.inv_root)
        } else {
            (beta.cosh(), beta.sinh() * self.inv_root)
        }
    }

    /// Characteristic matrix from [`LayerAtAngle::phase`].
    #[inline]
    fn matrix(&self, (cos_beta, k_sinc): (f64, f64), pol: Polarization) -> CharMatrix {
        CharMatrix::from_phase(cos_beta, k_sinc, self.g, self.n_sq, self.inv_n_sq, pol)
    }
}

/// A [`ClusterStack`] at one angle inside the stone: everything that does not depend on
/// the wavelength is precomputed, so a wavelength costs two sin/cos pairs and two
/// Chebyshev evaluations.
#[derive(Clone, Copy, Debug)]
pub struct StackAtAngle {
    high: LayerAtAngle,
    low: LayerAtAngle,
    /// `π d` = `2π h` for the layer thickness `h = d/2`, nm.
    pi_d_nm: f64,
    eta_s: f64,
    eta_p: f64,
    periods: u32,
}

impl StackAtAngle {
    /// The period matrix (high layer first) at `wavelength_nm`.
    pub fn period(&self, wavelength_nm: f64, pol: Polarization) -> CharMatrix {
        let k = self.pi_d_nm / wavelength_nm;
        let (high, low) = (self.high.phase(k), self.low.phase(k));
        self.high.matrix(high, pol) * self.low.matrix(low, pol)
    }

    /// `(R, T)` for one polarisation at `wavelength_nm` (nm, > 0).
    pub fn rt(&self, wavelength_nm: f64, pol: Polarization) -> (f64, f64) {
        if self.eta_s <= 0.0 {
            // Grazing incidence: every interface reflects totally in the limit.
            return (1.0, 0.0);
        }
        let eta = match pol {
            Polarization::S => self.eta_s,
            Polarization::P => self.eta_p,
        };
        periodic_rt(&self.period(wavelength_nm, pol), self.periods, eta)
    }

    /// Unpolarised `(R, T)` (mean of s and p) at `wavelength_nm` (nm, > 0).
    #[inline]
    pub fn rt_unpolarized(&self, wavelength_nm: f64) -> (f64, f64) {
        if self.eta_s <= 0.0 {
            return (1.0, 0.0);
        }
        let k = self.pi_d_nm / wavelength_nm;
        let (high, low) = (self.high.phase(k), self.low.phase(k));
        let period = |pol| self.high.matrix(high, pol) * self.low.matrix(low, pol);
        let (rs, ts) = periodic_rt(&period(Polarization::S), self.periods, self.eta_s);
        let (rp, tp) = periodic_rt(&period(Polarization::P), self.periods, self.eta_p);
        (0.5 * (rs + rp), 0.5 * (ts + tp))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sphere_form_factor_matches_its_series_near_zero() {
        // 3(sin x − x cos x)/x³ = 1 − x²/10 + x⁴/280 − … (Taylor series).
        for &x in &[1e-3f64, 0.01, 0.1] {
            let series = 1.0 - x * x / 10.0 + x.powi(4) / 280.0;
            assert!((sphere_form_factor(x) - series).abs() < 1e-9);
        }
        // First zero of tan x = x is 4.4934 (Abramowitz & Stegun table 10.6).
        assert!(sphere_form_factor(4.493_409_457_9).abs() < 1e-9);
    }

    #[test]
    fn default_cluster_has_the_design_spacing_and_index() {
        // DESIGN §4: d = D √(2/3), n_eff² = f n_s² + (1 − f) n_m².
        let c = CrystalConfig::default();
        let s = ClusterStack::new(&c).unwrap();
        assert!((s.d111_nm - c.sphere_diameter_nm * (2.0f64 / 3.0).sqrt()).abs() < 1e-12);
        let eps = c.filling_fraction * c.n_sphere.powi(2)
            + (1.0 - c.filling_fraction) * c.n_matrix.powi(2);
        assert!((s.n_eff - eps.sqrt()).abs() < 1e-12);
        let mean_eps = 0.5 * (s.n_high.powi(2) + s.n_low.powi(2));
        assert!((mean_eps - eps).abs() < 1e-12);
    }

    #[test]
    fn index_matched_cluster_is_transparent() {
        let c = CrystalConfig {
            n_matrix: 1.45,
            ..CrystalConfig::default()
        };
        let s = ClusterStack::new(&c).unwrap();
        let (r, t) = s.at(0.8).rt_unpolarized(550.0);
        assert!(r < 1e-20 && (t - 1.0).abs() < 1e-12, "R = {r}, T = {t}");
    }

    #[test]
    fn unpolarized_is_the_mean_of_s_and_p() {
        let s = ClusterStack::new(&CrystalConfig::default()).unwrap();
        let at = s.at(0.7);
        for wl in [400.0, 412.3, 500.0, 700.0] {
            let (rs, ts) = at.rt(wl, Polarization::S);
            let (rp, tp) = at.rt(wl, Polarization::P);
            let (r, t) = at.rt_unpolarized(wl);
            assert!((r - 0.5 * (rs + rp)).abs() < 1e-15 && (t - 0.5 * (ts + tp)).abs() < 1e-15);
        }
    }

    #[test]
    fn grazing_incidence_reflects_totally() {
        let s = ClusterStack::new(&CrystalConfig::default()).unwrap();
        assert_eq!(s.at(0.0).rt_unpolarized(600.0), (1.0, 0.0));
    }
}

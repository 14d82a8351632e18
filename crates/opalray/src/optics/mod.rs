//! Cluster optics (paper §2.3, §3.1): what one FCC cluster of silica spheres does to light of
//! each wavelength at each angle.
//!
//! Input: the scene's [`CrystalConfig`](crate::scene::CrystalConfig) and
//! [`WavelengthGrid`](crate::spectrum::WavelengthGrid) → output: [`OpticsTables`], the
//! bin-averaged specular reflectance R, coherent transmittance T and diffuse part D over
//! angle inside the stone.
//!
//! - [`dispersion`]: silica's dispersion, the indices at every wavelength and a line's
//!   centre and strength with them.
//! - [`fcc`]: the cluster along \[111\] as a two-layer periodic stack whose mean permittivity
//!   and first Fourier component equal the crystal's.
//! - [`tmm`]: transfer matrices of lossless layers, s and p, the N-th power in closed form
//!   (Chebyshev polynomials of the second kind).
//! - [`fine`]: the fine wavelength sampling (≤ 1 nm, finer at the Bragg lines) and its
//!   integration into the bins.
//! - [`scan`]: one cluster's exact R and T at any wavelength and angle, with the indices of
//!   each wavelength (the tables' and `opalray spectrum`'s evaluation).
//! - [`tables`]: the tables, built in parallel over angles.
//!
//! Bragg–Snell (DESIGN §4): the first-order peak for light meeting the (111) planes at θ
//! inside the stone is `λ = 2 d n_eff cos θ`; from air at θ₀ onto a face parallel to the
//! planes, `λ = 2 d √(n_eff² − sin² θ₀)`.

pub mod dispersion;
pub mod families;
pub mod fcc;
pub mod fine;
pub mod line;
pub mod scan;
pub mod tables;
pub mod tmm;

pub use dispersion::{CrystalIndex, LineIndex};
pub use families::{Families, FamilyKind, FamilyOptics};
pub use fcc::{ClusterStack, StackAtAngle};
pub use line::{rocking_fwhm_rad, BraggLine};
pub use scan::{ClusterOptics, OpticsAtAngle};
pub use tables::{build_optics, OpticsTables};
pub use tmm::Polarization;

/// First-order Bragg wavelength in vacuum, nm, for light meeting the (111) planes at
/// `cos_theta_inside` inside the stone: `2 d n_eff cos θ`. `d111_nm` > 0, `n_eff` ≥ 1, constant
/// over wavelength (with silica's dispersion, [`CrystalIndex::line`] solves
/// `λ = 2 d n_eff(λ) cos θ`).
pub fn bragg_wavelength_inside_nm(d111_nm: f64, n_eff: f64, cos_theta_inside: f64) -> f64 {
    2.0 * d111_nm * n_eff * cos_theta_inside
}

/// First-order Bragg wavelength in vacuum, nm, for light arriving from air at
/// `theta_air_rad` (from the normal of a face parallel to the (111) planes, `[0, π/2)`):
/// `2 d √(n_eff² − sin² θ₀)` (Snell's law into `n_eff`, then Bragg).
pub fn bragg_wavelength_air_nm(d111_nm: f64, n_eff: f64, theta_air_rad: f64) -> f64 {
    2.0 * d111_nm * (n_eff * n_eff - theta_air_rad.sin().powi(2)).sqrt()
}

/// `cos θ` inside a medium of index `n_eff` (≥ 1) for light refracted from air at
/// `theta_air_rad` (Snell's law, `sin θ = sin θ₀ / n_eff`).
pub fn cos_inside_from_air(n_eff: f64, theta_air_rad: f64) -> f64 {
    let sin_inside = theta_air_rad.sin() / n_eff;
    (1.0 - sin_inside * sin_inside).max(0.0).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bragg_laws_agree_through_snell() {
        let (d, n) = (204.1, 1.4423);
        for deg in [0.0f64, 15.0, 45.0, 80.0] {
            let theta0 = deg.to_radians();
            let inside = bragg_wavelength_inside_nm(d, n, cos_inside_from_air(n, theta0));
            assert!((inside - bragg_wavelength_air_nm(d, n, theta0)).abs() < 1e-9);
        }
    }

    #[test]
    fn design_diameter_flashes_orange_face_on() {
        // DESIGN §4: λ/D ≈ 2.36 for natural opal; D = 250 nm gives ≈ 590 nm face-on.
        let s = ClusterStack::new(&crate::scene::CrystalConfig::default()).unwrap();
        let lambda = bragg_wavelength_air_nm(s.d111_nm, s.n_eff, 0.0);
        assert!((lambda / 250.0 - 2.36).abs() < 0.01, "λ = {lambda}");
    }
}

//! One cluster's exact transfer-matrix R and T over wavelength, with the indices of each
//! wavelength where the crystal's `dispersion` gives a law: what the reflectance tables
//! integrate into bins and what `opalray spectrum` prints and plots.
//!
//! Input: a [`CrystalConfig`] → output: a [`ClusterOptics`], and per angle inside the stone
//! an [`OpticsAtAngle`] giving unpolarised `(R, T)` at any wavelength. Without a law the
//! stack is the same at every wavelength ([`ClusterStack::at`], precomputed once per angle);
//! with one it is built from [`CrystalIndex::indices`] at each wavelength, the angle θ taken
//! in the effective medium of that wavelength (`docs/model.md`, "Silica's dispersion").

use super::dispersion::CrystalIndex;
use super::fcc::{ClusterStack, StackAtAngle};
use super::tmm::Polarization;
use crate::error::Result;
use crate::scene::CrystalConfig;

/// A cluster's layer model and its indices over wavelength.
#[derive(Clone, Debug)]
pub struct ClusterOptics {
    /// The crystal (validated).
    pub crystal: CrystalConfig,
    /// The layer model at the sodium d line (the constant-index model).
    pub stack: ClusterStack,
    /// The indices at every wavelength.
    pub index: CrystalIndex,
}

/// A [`ClusterOptics`] at one angle inside the stone.
#[derive(Clone, Copy, Debug)]
pub struct OpticsAtAngle<'a> {
    optics: &'a ClusterOptics,
    cos_theta: f64,
    /// The one stack of every wavelength, without a law.
    constant: Option<StackAtAngle>,
}

impl ClusterOptics {
    /// The optics of `crystal` (validated first).
    pub fn new(crystal: &CrystalConfig) -> Result<ClusterOptics> {
        let stack = ClusterStack::new(crystal)?;
        Ok(ClusterOptics {
            crystal: crystal.clone(),
            stack,
            index: CrystalIndex::new(crystal),
        })
    }

    /// The layer model with the indices at `wavelength_nm` (the d line's without a law).
    pub fn stack_at_wavelength(&self, wavelength_nm: f64) -> ClusterStack {
        if self.index.is_constant() {
            return self.stack;
        }
        let (n_s, n_m) = self.index.indices(wavelength_nm);
        ClusterStack::with_indices(&self.crystal, n_s, n_m)
    }

    /// The cluster for light meeting the (111) planes at `cos_theta` inside (`[0, 1]`).
    pub fn at(&self, cos_theta: f64) -> OpticsAtAngle<'_> {
        OpticsAtAngle {
            optics: self,
            cos_theta,
            constant: self.index.is_constant().then(|| self.stack.at(cos_theta)),
        }
    }

    /// The first-order (111) line's centre, nm, at `cos_theta` inside: `2 d n̄ cos θ`, with a
    /// law the fixed point `λ = 2 d n̄(λ) cos θ` ([`CrystalIndex::line`]).
    pub fn bragg_wavelength_nm(&self, cos_theta: f64) -> f64 {
        self.index
            .line(self.stack.bragg_wavelength_nm(cos_theta))
            .centre_nm
    }

    /// The face-on first-order stop band `(λ_lo, λ_hi)`, nm, for s light: that of the stack
    /// of the indices at the line's centre (the indices change by about 10⁻⁴ across it).
    pub fn stop_band_nm(&self) -> Option<(f64, f64)> {
        self.stack_at_wavelength(self.bragg_wavelength_nm(1.0))
            .stop_band_nm(1.0, Polarization::S)
    }
}

impl OpticsAtAngle<'_> {
    /// Unpolarised `(R, T)` (mean of s and p) at `wavelength_nm` (nm, > 0).
    #[inline]
    pub fn rt_unpolarized(&self, wavelength_nm: f64) -> (f64, f64) {
        match &self.constant {
            Some(at) => at.rt_unpolarized(wavelength_nm),
            None => self
                .optics
                .stack_at_wavelength(wavelength_nm)
                .at(self.cos_theta)
                .rt_unpolarized(wavelength_nm),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Dispersion;

    #[test]
    fn without_a_law_the_scan_is_the_d_line_stack() {
        let optics = ClusterOptics::new(&CrystalConfig::default()).unwrap();
        let at = optics.stack.at(0.9);
        for wl in [420.0, 530.7, 700.0] {
            assert_eq!(optics.at(0.9).rt_unpolarized(wl), at.rt_unpolarized(wl));
        }
    }

    #[test]
    fn with_silica_the_face_on_peak_is_at_the_fixed_point() {
        // The scan's largest R lies within its 0.01 nm step of λ = 2 d n̄(λ), solved by
        // CrystalIndex, and away from the constant-index centre (docs/model.md: D = 200 nm
        // moves by +1.81 nm).
        let crystal = CrystalConfig {
            sphere_diameter_nm: 200.0,
            dispersion: Dispersion::Silica,
            ..CrystalConfig::default()
        };
        let optics = ClusterOptics::new(&crystal).unwrap();
        let centre = optics.bragg_wavelength_nm(1.0);
        let at = optics.at(1.0);
        let (peak, _) = (0..1000)
            .map(|i| centre - 5.0 + 0.01 * f64::from(i))
            .map(|wl| (wl, at.rt_unpolarized(wl).0))
            .fold((0.0, -1.0), |best, s| if s.1 > best.1 { s } else { best });
        assert!((peak - centre).abs() < 0.011, "{peak} vs {centre}");
        let shift = centre - optics.stack.bragg_wavelength_nm(1.0);
        assert!((shift - 1.81).abs() < 0.01, "{shift}");
    }
}

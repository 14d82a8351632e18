//! A path's spectrum deposited on the film: the light's white less the notches passed before
//! a reflection, else the wavelengths it carries, through the film's light × colour-matching
//! table ([`SpectralSampler`]).

use super::{Notches, PathSpectrum, SpectralSampler};

impl SpectralSampler {
    /// Add `weight` × the light's white after `tints` ironstone reflections, less what
    /// `notches` took from it.
    fn add_notched(
        &self,
        tints: u8,
        notches: Option<&Notches>,
        weight: f64,
        xyz: &mut [f64; 3],
        bins: &mut [f32],
    ) {
        self.add_white(tints, weight, xyz, bins);
        if let Some(notches) = notches {
            notches.take_from(self, tints, weight, xyz, bins);
        }
    }

    /// Add `weight · ∫ Π f(λ) S(λ) c̄(λ) dλ` of a path's spectrum to `xyz` and the binned
    /// spectrum to `bins`: the light's white before a reflection, else the sum over the
    /// wavelengths it carries.
    pub fn add_path(&self, path: &PathSpectrum, weight: f64, xyz: &mut [f64; 3], bins: &mut [f32]) {
        if weight == 0.0 || path.dark {
            return;
        }
        if !path.reflects() {
            self.add_notched(path.tints, path.notches.as_deref(), weight, xyz, bins);
            return;
        }
        for (f, w) in path.carried() {
            if f != 0.0 {
                self.add_at(w, weight * f64::from(f), xyz, bins);
            }
        }
    }
}

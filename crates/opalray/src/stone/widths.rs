//! The width of a domain's reflection lobe over directions: its mosaic spread and the
//! diffraction of the domain's width, tabulated over cos θ per family kind (the rocking width
//! is an acceptance in wavelength, kept in R(λ, θ)).

use super::Stone;
use crate::optics::Families;
use crate::scene::{Pattern, Scene};

/// Rows of the rocking-width table over cos θ.
pub(super) const WIDTH_ROWS: usize = 64;
/// Lowest cos θ of the rocking-width table (below it the width of this row is used).
const WIDTH_MIN_COS: f64 = 0.2;
/// Full width at half maximum of a Gaussian over its standard deviation, `2√(2 ln 2)`.
pub(super) const FWHM_PER_SIGMA: f64 = 2.354_820_045;
/// FWHM of a slit's Fraunhofer pattern `sinc²`, in wavelengths over the slit's width.
const SLIT_FWHM_PER_WAVELENGTH: f64 = 0.885_893;

impl Stone {
    /// Standard deviation (rad) of the reflection lobe of family kind `kind` about its normal
    /// at cos θ `cos_theta`: the mosaic spread and the diffraction of the domain's width
    /// ([`diffraction_sigma_rad`]). A perfect domain (mosaic 0) is a mirror; the stack's
    /// rocking width is not in it (it sets which wavelengths reflect, in R(λ, θ)).
    pub fn lobe_sigma(&self, kind: u8, cos_theta: f32) -> f32 {
        let table = &self.lobe_sigma[kind as usize];
        let x = (f64::from(cos_theta) - WIDTH_MIN_COS) / (1.0 - WIDTH_MIN_COS)
            * (WIDTH_ROWS - 1) as f64;
        let x = x.clamp(0.0, (WIDTH_ROWS - 1) as f64);
        let i = (x as usize).min(WIDTH_ROWS - 2);
        let f = (x - i as f64) as f32;
        table[i] * (1.0 - f) + table[i + 1] * f
    }
}

/// The far-field spread of a reflection by a domain `width_mm` wide, as the standard deviation
/// (rad, inside) of the Gaussian of the same half width: a uniformly lit aperture's `sinc²`
/// has FWHM `0.886 λ/w` (Born & Wolf §8.5), λ the wavelength inside, `2 d cos θ` for planes of
/// spacing `spacing_mm` met at `cos_theta` (Bragg's law).
pub fn diffraction_sigma_rad(spacing_mm: f64, cos_theta: f64, width_mm: f64) -> f64 {
    SLIT_FWHM_PER_WAVELENGTH * 2.0 * spacing_mm * cos_theta / width_mm / FWHM_PER_SIGMA
}

/// A domain's width, mm: the grains' `grain_size_mm`, or the diameter of the paper's mean
/// ball (`2 R` cells of the growth grid).
fn domain_width_mm(scene: &Scene) -> f64 {
    let s = &scene.structure;
    match scene.domains.pattern {
        Pattern::Grains => scene.domains.grain_size_mm,
        Pattern::Paper => 2.0 * s.mean_radius_cells * 2.0 * s.semi_axes_mm[0] / s.grid[0] as f64,
    }
}

fn width_row_cos(row: usize) -> f64 {
    WIDTH_MIN_COS + (1.0 - WIDTH_MIN_COS) * row as f64 / (WIDTH_ROWS - 1) as f64
}

/// Per family, the reflection's spread over directions (rad) at each row's cos θ: the mosaic
/// and the diffraction of the domain's width (the rocking width is an acceptance in
/// wavelength, kept in R(λ, θ)).
pub(super) fn lobe_sigmas(scene: &Scene, families: &Families) -> Vec<[f32; WIDTH_ROWS]> {
    let mosaic = scene.domains.mosaic_spread_deg.to_radians();
    let width_mm = domain_width_mm(scene);
    families
        .kinds
        .iter()
        .map(|f| {
            let spacing_mm = f.spacing_over_diameter * scene.crystal.sphere_diameter_nm * 1e-6;
            std::array::from_fn(|row| {
                let diffraction = diffraction_sigma_rad(spacing_mm, width_row_cos(row), width_mm);
                mosaic.hypot(diffraction) as f32
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::stone::tests::grains_scene;

    #[test]
    fn a_perfect_domain_spreads_its_reflection_by_its_width_alone() {
        // Mosaic 0: the lobe is the diffraction of the 2 mm grain, FWHM 0.886 λ/w with λ the
        // wavelength inside (the line's centre over n_eff) — about 0.01°, not the stack's
        // rocking width (0.48° at 30° for 400 layers, DESIGN §4).
        let mut scene = grains_scene();
        scene.domains.mosaic_spread_deg = 0.0;
        let stone = Stone::new(&scene).unwrap();
        let c = 30f64.to_radians().cos();
        let fwhm = f64::from(stone.lobe_sigma(0, c as f32)) * FWHM_PER_SIGMA;
        let d111_nm = 250.0 * (2.0f64 / 3.0).sqrt();
        let lambda_inside_mm = 2.0 * d111_nm * c * 1e-6;
        let expected = 0.886 * lambda_inside_mm / scene.domains.grain_size_mm;
        assert!((fwhm / expected - 1.0).abs() < 0.01, "{fwhm} vs {expected}");
        assert!(fwhm.to_degrees() < 0.02, "{}°", fwhm.to_degrees());
        // With a mosaic, the mosaic rules it.
        scene.domains.mosaic_spread_deg = 1.5;
        let stone = Stone::new(&scene).unwrap();
        let sigma = f64::from(stone.lobe_sigma(0, c as f32)).to_degrees();
        assert!((sigma - 1.5).abs() < 1e-3, "{sigma}°");
    }
}

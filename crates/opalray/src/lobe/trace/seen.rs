//! What a ray sees outside the stone (the environment, sharp or through a lobe, the light's
//! disc, the irradiance on the body), and how a light is added to the pixel's sums.

use super::*;

impl Tracer<'_> {
    /// Add `v` of the light's white less the eye ray's notches.
    pub(super) fn add_notched_white(&self, v: f64, sums: &mut Sums) {
        if v == 0.0 {
            return;
        }
        sums.white += v;
        for c in 0..3 {
            sums.xyz[c] -= v * self.notch_xyz[c];
        }
        for (b, n) in sums.bins.iter_mut().zip(&self.notch_bins) {
            *b -= (v * f64::from(*n)) as f32;
        }
    }

    /// Add `v` times a line's colour `xyz` (and `s`, its `∫ R S dλ`) at `center_nm`.
    pub(super) fn add_line(&self, v: f64, xyz: [f64; 3], s: f64, center_nm: f64, sums: &mut Sums) {
        if v == 0.0 {
            return;
        }
        for (sum, x) in sums.xyz.iter_mut().zip(xyz) {
            *sum += v * x;
        }
        if let Some(b) = self.setup.spectral.grid.bin_of(center_nm) {
            sums.bins[b] += (v * s / self.bin_width_nm) as f32;
        }
    }

    /// What a ray leaving the stone at `at` along `dir` sees: the area light where it meets
    /// it, else the environment.
    pub(super) fn seen_sharp(&self, at: Vec3, dir: Vec3) -> f32 {
        seen(
            self.setup.environment,
            self.setup.area_light.as_ref(),
            at,
            dir,
        )
        .0
    }

    /// What a lobe of directions of width `spread` (radians, per axis) about `dir` sees
    /// leaving the stone at `at`: the area light over the share of the lobe it fills
    /// ([`crate::lights::AreaLight::lobe_share`]), the environment through the rest.
    pub(super) fn seen_through_lobe(&self, at: Vec3, dir: Vec3, spread: f32) -> f32 {
        let env = self.setup.environment.filtered(dir, spread);
        match self.setup.area_light {
            Some(light) => {
                let share = light.lobe_share(at, dir, spread);
                env * (1.0 - share) + light.value() * share
            }
            None => env,
        }
    }

    /// The irradiance on a plane of unit normal `n` outside the stone: the environment's
    /// ([`Irradiance`]) and the light's, `E max(0, n·ℓ)` (its horizon's clipping of a large
    /// area light left out).
    pub(super) fn irradiance_on(&self, n: Vec3) -> f32 {
        let light = self
            .body_light
            .map_or(0.0, |(to, e)| e * n.dot(to).max(0.0));
        self.irradiance.at(n) + light
    }

    /// The light's disc seen along `dir` from outside, in image units.
    pub(super) fn disc(&self, dir: Vec3) -> f32 {
        self.setup.light.map_or(0.0, |light| light.disc(dir))
    }
}

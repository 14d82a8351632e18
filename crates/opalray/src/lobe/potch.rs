//! The light reaching the top of the potch under a colour bar ([`PotchLight`]): the potch
//! there is a chip lit through the bar and the dome, not by the room's irradiance at the
//! point the eye ray entered.

use glam::Vec3;

use super::{trace, Irradiance, LineColours, LobeSetup};
use crate::geometry::{fresnel_dielectric, Ellipsoid};
use crate::stone::Stone;

/// Points across and along the bar's footprint at which the light is computed.
const GRID: (usize, usize) = (48, 36);
/// Directions of the quadrature at each point, each reading the environment through a lobe
/// of half their spacing ([`trace::Tracer::light_on`]). Twice as many (96) take twice the
/// time and change no gem preset's pixel at 320 × 240 by more than 7 codes (the mean by
/// under 0.06) nor the white body's value by more than 0.002 (BENCHMARKS.md, 2026-12-06).
const DIRECTIONS: usize = 48;
/// Rows of the quadrature of [`hemispherical_fresnel`].
const FRESNEL_ROWS: usize = 256;

/// The light reaching the top of the potch under a colour bar, as the irradiance outside
/// that would light a chip at the surface as much (`Ē` of [`Irradiance`]): the mean, over
/// cosine-distributed directions about the bar's inner surface's normal, of what each sees
/// through the bar and the dome ([`trace::Tracer::light_on`]: the lamp, the environment, the
/// dome's internal reflections followed; dimmed as [`trace::Dim::Potch`] says), over
/// `1 − F̄`, the share of a diffuse irradiance
/// that the surface lets in ([`hemispherical_fresnel`]); for potch at a flat surface this is
/// `Ē` again. Tabulated over the footprint and read bilinearly (the points no read inside
/// the footprint weighs in are left 0, [`super::read_points`]).
///
/// Beside it, the share of the potch's own diffuse light that the bar and the dome send back
/// into it ([`PotchLight::returned_at`]), from the same directions: what the dimming by the
/// potch took on their way out. Under a flat surface it is Saunderson's `r_i = 1 − (1 −
/// F̄)/n²` (every direction beyond the critical angle comes back at once); under a curved
/// dome over a clear or faintly milky bar, part of what the dome reflects inside travels
/// along the bar and leaves elsewhere (through the dome further on, or the polished back
/// where the bar reaches it), so less comes back. Each direction is counted once: as the
/// light it brings from outside, or as the body's light it returns.
pub(crate) struct PotchLight {
    inner: Ellipsoid,
    centre: Vec3,
    values: Vec<f32>,
    returned: Vec<f32>,
    /// The most light times the most the body's return can raise its reflectance over a
    /// polished surface's: the bound of [`PotchLight::peak`].
    peak: f32,
}

impl PotchLight {
    /// The table of `stone` lit as `setup` says; `None` without a colour bar.
    pub(super) fn new(
        stone: &Stone,
        setup: &LobeSetup,
        colours: &LineColours,
        irradiance: &Irradiance,
    ) -> Option<Self> {
        let (inner, centre) = stone.bar_surface()?;
        let entering = 1.0 - hemispherical_fresnel(stone.n_eff);
        let table = super::fill_table(
            GRID,
            || trace::Tracer::new(stone, setup, colours, irradiance, trace::Lit::default()),
            |tracer, i, j| {
                let (p, normal) = point(&inner, centre, i, j);
                let (light, returned) = tracer.light_and_return_on(
                    p + normal * 1e-3,
                    normal,
                    DIRECTIONS,
                    trace::Dim::Potch,
                );
                (light / entering, returned)
            },
        );
        // A body of reflectance R under a top returning `r` shows `(1 − r_i R)/(1 − r R)`
        // times what it shows under a polished surface, at most `(1 − r_i)/(1 − r)` (R = 1).
        let r_inside = 1.0 - entering / (stone.n_eff * stone.n_eff);
        let peak = table.iter().fold(0.0f32, |m, &(light, r)| {
            m.max(light * ((1.0 - r_inside) / (1.0 - r).max(1e-3)).max(1.0))
        });
        Some(PotchLight {
            inner,
            centre,
            values: table.iter().map(|v| v.0).collect(),
            returned: table.iter().map(|v| v.1).collect(),
            peak,
        })
    }

    /// The light at `p`, a point of the potch under the bar (on or just under its top).
    pub(super) fn at(&self, p: Vec3) -> f32 {
        let a = self.inner.semi_axes();
        let q = p - self.centre;
        super::bilinear(&self.values, GRID, q.x / a.x, q.y / a.y)
    }

    /// The share of the potch's own diffuse light that comes back to it from above at the
    /// point of its top under `p` (any point over the bar's footprint), `None` beyond it.
    pub(super) fn returned_at(&self, p: Vec3) -> Option<f32> {
        let a = self.inner.semi_axes();
        let q = p - self.centre;
        let (u, v) = (q.x / a.x, q.y / a.y);
        (u * u + v * v <= 1.0).then(|| super::bilinear(&self.returned, GRID, u, v))
    }

    /// The largest light in the table, times the most its return can raise a body's
    /// reflectance over a polished surface's (a bound on what the body under the bar sends).
    pub(super) fn peak(&self) -> f32 {
        self.peak
    }

    /// Whether `p` lies under the bar (inside its inner surface).
    pub(super) fn holds(&self, p: Vec3) -> bool {
        let q = (p - self.centre) / self.inner.semi_axes();
        q.length_squared() <= 1.0 + 1e-3
    }
}

/// The grid point `(i, j)` on the upper half of the bar's inner surface, and the surface's
/// normal there (a point beyond the footprint's edge is pulled in).
fn point(inner: &Ellipsoid, centre: Vec3, i: usize, j: usize) -> (Vec3, Vec3) {
    let (nx, ny) = GRID;
    let a = inner.semi_axes();
    let u = 2.0 * i as f32 / (nx - 1) as f32 - 1.0;
    let v = 2.0 * j as f32 / (ny - 1) as f32 - 1.0;
    let r = (u * u + v * v).sqrt();
    let pull = if r > 0.98 { 0.98 / r } else { 1.0 };
    let (u, v) = (u * pull, v * pull);
    let w = (1.0 - u * u - v * v).max(0.0).sqrt();
    let q = Vec3::new(u * a.x, v * a.y, w * a.z);
    (centre + q, inner.normal(q))
}

/// The share of a uniform diffuse light outside that the surface of index `n` reflects,
/// `F̄ = ∫ F(θ) 2 cos θ sin θ dθ` over the hemisphere (midpoint rule).
pub(super) fn hemispherical_fresnel(n: f32) -> f32 {
    let step = std::f32::consts::FRAC_PI_2 / FRESNEL_ROWS as f32;
    (0..FRESNEL_ROWS)
        .map(|k| {
            let theta = (k as f32 + 0.5) * step;
            fresnel_dielectric(theta.cos(), 1.0, n) * 2.0 * theta.cos() * theta.sin() * step
        })
        .sum()
}

#[cfg(test)]
mod tests {
    use super::hemispherical_fresnel;

    #[test]
    fn the_hemispherical_fresnel_of_glass_is_about_nine_percent() {
        // Diffuse reflectance of a smooth dielectric lit from outside: 0.092 for n = 1.5
        // (Judd 1942; Kubelka-Munk's surface correction, r_e), 0.0 for n = 1.
        assert!(
            (hemispherical_fresnel(1.5) - 0.092).abs() < 0.002,
            "{}",
            hemispherical_fresnel(1.5)
        );
        assert!(hemispherical_fresnel(1.0).abs() < 1e-6);
    }
}

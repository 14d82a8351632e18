//! Polarisation carried as two incoherent intensities, s and p, relative to the plane of
//! incidence of a path's last event (a 2-component reduction of the Stokes vector).
//!
//! Input: the state after the previous event and the next event's plane (its s axis, the unit
//! normal of the plane holding the incoming direction and the surface's or the planes'
//! normal) and reflectances `(R_s, R_p)` (or transmittances) → output: the state after it.
//!
//! Model (`docs/model.md`, "Polarisation"): between events the light is described by its
//! intensities along the old s and p axes; projected on the new plane's axes, at angle φ
//! between the planes, `s' = cos²φ s + sin²φ p`, `p' = sin²φ s + cos²φ p` (the coherence term,
//! Stokes U, is dropped), then `s' R_s`, `p' R_p`. The rotation and the diagonal event
//! matrices are symmetric, so the state can be carried from the camera as well as from the
//! light; unpolarised light starts at (½, ½) and the detector reads `s + p`. This is exact
//! for up to two polarising events from unpolarised light (U made by the rotation before
//! the second event does not reach the intensity); from the third on, U and the phase
//! between `r_s` and `r_p` (which the line model does not carry) would be needed.

use glam::Vec3;

/// A beam's polarisation state: its intensities along the s and p axes of the plane of its
/// last event.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SpState {
    /// Intensity polarised perpendicular to the last plane of incidence (≥ 0).
    pub s: f32,
    /// Intensity polarised in the last plane of incidence (≥ 0).
    pub p: f32,
    /// Unit s axis of the last plane of incidence; zero where no event has set one (the
    /// state is then unpolarised, `s = p`).
    pub axis: Vec3,
}

impl SpState {
    /// Unpolarised light of `intensity`: `(intensity/2, intensity/2)`, no plane.
    pub fn unpolarised(intensity: f32) -> Self {
        SpState {
            s: 0.5 * intensity,
            p: 0.5 * intensity,
            axis: Vec3::ZERO,
        }
    }

    /// The total intensity `s + p` (what an unpolarised detector or a white,
    /// unpolarised environment reads).
    pub fn intensity(&self) -> f32 {
        self.s + self.p
    }

    /// The s axis of the plane of incidence of a beam along `dir` (unit) meeting a surface
    /// or a family of planes of unit normal `normal`: `dir × normal`, normalised; zero at
    /// normal incidence, where the plane is undefined and `R_s = R_p`.
    pub fn s_axis(dir: Vec3, normal: Vec3) -> Vec3 {
        let a = dir.cross(normal);
        if a.length_squared() < 1e-12 {
            Vec3::ZERO
        } else {
            a.normalize()
        }
    }

    /// The state projected on the plane whose s axis is `axis` (`cos²φ`, `sin²φ` split,
    /// module notes); unchanged where either axis is zero.
    pub fn rotated_to(&self, axis: Vec3) -> Self {
        if axis == Vec3::ZERO {
            return *self;
        }
        if self.axis == Vec3::ZERO {
            return SpState { axis, ..*self };
        }
        let c2 = self.axis.dot(axis).powi(2).clamp(0.0, 1.0);
        let s2 = 1.0 - c2;
        SpState {
            s: c2 * self.s + s2 * self.p,
            p: s2 * self.s + c2 * self.p,
            axis,
        }
    }

    /// The state after an event of plane `axis` (see [`SpState::s_axis`]) that keeps `rs` of
    /// the s part and `rp` of the p part (reflectances or transmittances, in [0, 1]).
    pub fn event(&self, axis: Vec3, rs: f32, rp: f32) -> Self {
        let r = self.rotated_to(axis);
        SpState {
            s: r.s * rs,
            p: r.p * rp,
            axis: r.axis,
        }
    }

    /// The same intensity unpolarised (a diffuse scattering or a Lambert backing).
    pub fn depolarised(&self) -> Self {
        SpState::unpolarised(self.intensity())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::reflect;
    use crate::optics::BraggLine;

    /// Reflectance of the quarter-wave stack (H L)^N at its design wavelength, tilted
    /// admittances `η_s = n cos θ`, `η_p = n / cos θ`, in and behind the stack the L medium
    /// (Macleod, *Thin-Film Optical Filters*, §5.2: `R = ((1 − y)/(1 + y))²`,
    /// `y = (η_L/η_H)^{2N}`). Independent of the crate's transfer matrices and line model.
    fn quarter_wave(n_h: f64, n_l: f64, cos_l: f64, periods: i32) -> (f64, f64) {
        let sin_l = (1.0 - cos_l * cos_l).sqrt();
        let cos_h = (1.0 - (n_l * sin_l / n_h).powi(2)).sqrt();
        let r = |eta_h: f64, eta_l: f64| {
            let y = (eta_l / eta_h).powi(2 * periods);
            ((1.0 - y) / (1.0 + y)).powi(2)
        };
        (r(n_h * cos_h, n_l * cos_l), r(n_h / cos_h, n_l / cos_l))
    }

    /// The intensity of unpolarised light of intensity 1 after the amplitude (Jones)
    /// matrices `diag(r_s1, r_p1)`, a turn of the basis by `phi`, then `diag(r_s2, r_p2)`:
    /// the mean over two orthogonal input polarisations. Real amplitudes (no retardance).
    fn jones_two_reflections(r1: (f64, f64), r2: (f64, f64), phi: f64) -> f64 {
        let (c, s) = (phi.cos(), phi.sin());
        let mut total = 0.0;
        for e in [[1.0, 0.0], [0.0, 1.0]] {
            let a = [r1.0.sqrt() * e[0], r1.1.sqrt() * e[1]];
            let b = [c * a[0] + s * a[1], -s * a[0] + c * a[1]];
            total += r2.0 * b[0] * b[0] + r2.1 * b[1] * b[1];
        }
        0.5 * total
    }

    /// Two reflections of unpolarised light along `d0`: by planes of normal `n1`, then by
    /// planes of normal `n2`, each keeping `(R_s, R_p)` = `r1`, `r2`.
    fn chain(d0: Vec3, n1: Vec3, n2: Vec3, r1: (f64, f64), r2: (f64, f64)) -> f32 {
        let first =
            SpState::unpolarised(1.0).event(SpState::s_axis(d0, n1), r1.0 as f32, r1.1 as f32);
        let d1 = reflect(d0, n1);
        first
            .event(SpState::s_axis(d1, n2), r2.0 as f32, r2.1 as f32)
            .intensity()
    }

    #[test]
    fn double_reflection_matches_the_two_plate_stacks() {
        // Plate 1 met at 45° inside (near the layers' Brewster angle: p hardly reflected),
        // plate 2 at 45° too, its plane of incidence turned by φ about the beam between them.
        let theta = std::f64::consts::FRAC_PI_4;
        let r1 = quarter_wave(1.46, 1.42, theta.cos(), 100);
        assert!(r1.1 < 0.05 * r1.0, "p nearly vanishes at 45°: {r1:?}");
        let r2 = r1;
        let d0 = Vec3::new(0.0, 0.0, -1.0);
        let t = theta as f32;
        let n1 = Vec3::new(0.0, t.sin(), t.cos());
        let d1 = reflect(d0, n1);
        let a1 = SpState::s_axis(d0, n1);
        let averaged = 0.25 * (r1.0 + r1.1) * (r2.0 + r2.1);
        for phi_deg in [0.0f64, 30.0, 60.0, 90.0] {
            // Plate 2's normal at 45° to −d1, its plane turned by φ from plate 1's.
            let phi = phi_deg.to_radians() as f32;
            let across = d1.cross(a1).normalize();
            let lateral = across * phi.cos() + a1 * phi.sin();
            let n2 = (-d1 * t.cos() + lateral * t.sin()).normalize();
            let model = f64::from(chain(d0, n1, n2, r1, r2));
            let exact = jones_two_reflections(r1, r2, f64::from(phi));
            assert!(
                (model - exact).abs() < 1e-5 * exact.max(1e-3),
                "φ {phi_deg}°: {model} vs {exact}"
            );
            // The averaged product misses it by far where the planes differ or p ≠ s.
            assert!(
                (averaged - exact).abs() > 0.2 * exact.max(averaged),
                "φ {phi_deg}°: averaged {averaged} vs {exact}"
            );
        }
        // The closed forms: same plane ½(Rs Rs' + Rp Rp'), crossed ½(Rs Rp' + Rp Rs').
        let same = 0.5 * (r1.0 * r2.0 + r1.1 * r2.1);
        let crossed = 0.5 * (r1.0 * r2.1 + r1.1 * r2.0);
        assert!((jones_two_reflections(r1, r2, 0.0) - same).abs() < 1e-12);
        let right = std::f64::consts::FRAC_PI_2;
        assert!((jones_two_reflections(r1, r2, right) - crossed).abs() < 1e-12);
    }

    #[test]
    fn a_single_reflection_of_unpolarised_light_is_the_average() {
        let d0 = Vec3::new(0.3, -0.2, -0.93).normalize();
        let n = Vec3::new(0.1, 0.4, 0.9).normalize();
        let line = BraggLine::new(0.004, 590.0, 0.8, 400.0);
        for w in [585.0, 588.0, 590.0] {
            let (rs, rp) = line.reflectance_sp(0.8 * w);
            let out = SpState::unpolarised(1.0).event(SpState::s_axis(d0, n), rs as f32, rp as f32);
            let r = line.reflectance(0.8 * w) as f32;
            assert!((out.intensity() - r).abs() < 1e-6, "{out:?} vs {r}");
        }
    }

    #[test]
    fn the_line_reflects_no_p_light_at_45_degrees() {
        // ν_p = ν_s |cos 2θ| (Kogelnik): zero at 45° inside; s as the unpolarised line's double.
        let c = std::f64::consts::FRAC_1_SQRT_2;
        let line = BraggLine::new(0.004, 590.0, c, 400.0);
        let (rs, rp) = line.reflectance_sp(line.center_nm);
        assert!(rp < 1e-12 && rs > 0.5, "{rs} {rp}");
        assert!((line.reflectance(line.center_nm) - 0.5 * rs).abs() < 1e-12);
    }

    #[test]
    fn events_conserve_intensity_when_lossless() {
        // R + T = 1 per component: the reflected and transmitted states sum to the incoming.
        let state = SpState {
            s: 0.7,
            p: 0.3,
            axis: Vec3::X,
        };
        let axis = Vec3::new(0.6, 0.8, 0.0);
        let (rs, rp) = (0.4, 0.05);
        let sum = state.event(axis, rs, rp).intensity()
            + state.event(axis, 1.0 - rs, 1.0 - rp).intensity();
        assert!((sum - 1.0).abs() < 1e-6, "{sum}");
    }
}

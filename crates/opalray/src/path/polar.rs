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

use super::spectral::MAX_DRAWS;
use super::Tracer;
use crate::geometry::fresnel_dielectric_sp;

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

/// The polarisation a path carries, as the share of its light that is s-polarised relative
/// to the plane of its last polarising event: one share for its white before its first
/// Bragg reflection, one per wavelength it carries after it ([`super::PathSpectrum`]; its
/// intensities stay in the spectrum's weights). A zero axis means no plane yet: the light is
/// unpolarised (every share ½).
#[derive(Clone, Copy, Debug)]
pub struct Polarisation {
    /// Unit s axis of the last plane ([`SpState::s_axis`]); zero: unpolarised.
    axis: Vec3,
    /// The s share of the white, before the first reflection.
    white: f32,
    /// The s share at each wavelength carried.
    shares: [f32; MAX_DRAWS],
}

impl Default for Polarisation {
    fn default() -> Self {
        Polarisation {
            axis: Vec3::ZERO,
            white: 0.5,
            shares: [0.5; MAX_DRAWS],
        }
    }
}

/// An event that keeps `rs` of the s part and `rp` of the p part of light whose s share is
/// `q`: the factor on its intensity and its s share after. Without a plane (`plane` false:
/// normal incidence, or a plane the path does not know) the mean, the share unchanged.
#[inline]
pub(super) fn apply(q: f32, rs: f64, rp: f64, plane: bool) -> (f64, f32) {
    if !plane {
        return (0.5 * (rs + rp), q);
    }
    let q64 = f64::from(q);
    let kept_s = q64 * rs;
    let factor = kept_s + (1.0 - q64) * rp;
    let share = if factor > 0.0 {
        (kept_s / factor) as f32
    } else {
        q
    };
    (factor, share)
}

impl Polarisation {
    /// The same state, unpolarised (a diffuse scattering or a backing).
    pub fn depolarise(&mut self) {
        *self = Polarisation::default();
    }

    /// The white's s share turned to the plane of s axis `axis` (unchanged where either
    /// axis is zero), without turning the state.
    pub(super) fn white_in(&self, axis: Vec3) -> f32 {
        match self.cos2_to(axis) {
            Some(c2) => turned(self.white, c2),
            None => self.white,
        }
    }

    /// The state turned to the plane of s axis `axis`, its first `carried` shares and the
    /// white's (`s' = cos²φ s + sin²φ p`); nothing where `axis` is zero.
    pub(super) fn turn(&mut self, axis: Vec3, carried: usize) {
        if axis == Vec3::ZERO {
            return;
        }
        if let Some(c2) = self.cos2_to(axis) {
            self.white = turned(self.white, c2);
            for q in &mut self.shares[..carried] {
                *q = turned(*q, c2);
            }
        }
        self.axis = axis;
    }

    /// Set the white's s share (after an event on the white).
    pub(super) fn set_white(&mut self, q: f32) {
        self.white = q;
    }

    /// The s shares at the wavelengths carried.
    pub(super) fn shares_mut(&mut self) -> &mut [f32; MAX_DRAWS] {
        &mut self.shares
    }

    /// `cos²φ` between the last plane's s axis and `axis`; `None` where either is zero or
    /// they are the same plane (no turn).
    fn cos2_to(&self, axis: Vec3) -> Option<f32> {
        if axis == Vec3::ZERO || self.axis == Vec3::ZERO {
            return None;
        }
        let c2 = self.axis.dot(axis).powi(2).clamp(0.0, 1.0);
        (c2 < 1.0).then_some(c2)
    }
}

impl Tracer<'_> {
    /// The s axis of the plane of an event of a path along `dir` at a surface or planes of
    /// unit normal `normal` ([`SpState::s_axis`]); zero (no plane: the mean of s and p) where
    /// the tracer does not polarise.
    pub(super) fn plane(&self, dir: Vec3, normal: Vec3) -> Vec3 {
        if self.polarised {
            SpState::s_axis(dir, normal)
        } else {
            Vec3::ZERO
        }
    }

    /// The light's refraction in at `entry`, seen from a path inside that leaves towards it
    /// along `to_light`, the light outside along `out` (unit, towards the light): the plane's
    /// s axis and `T_s`, `T_p` over their mean (the estimate's irradiance holds the mean).
    pub(super) fn entry_sp(&self, entry: Vec3, to_light: Vec3, out: Vec3) -> (Vec3, f32, f32) {
        let normal = self.stone.shape.normal(entry);
        let (fs, fp) = fresnel_dielectric_sp(out.dot(normal).max(0.0), 1.0, self.n_eff);
        let (ts, tp) = (1.0 - fs, 1.0 - fp);
        let mean = 0.5 * (ts + tp);
        if mean <= 0.0 {
            return (Vec3::ZERO, 1.0, 1.0);
        }
        (self.plane(to_light, normal), ts / mean, tp / mean)
    }
}

/// The s share `q` projected on axes turned by φ from its own (`cos²φ` = `c2`).
#[inline]
fn turned(q: f32, c2: f32) -> f32 {
    c2 * q + (1.0 - c2) * (1.0 - q)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::{reflect, Camera, LightSource, Ray};
    use crate::lights::Environment;
    use crate::optics::BraggLine;
    use crate::path::nee::tests::mean_y_with;
    use crate::path::{PathLight, PathSetup, PathSpectrum, SpectralSampler};
    use crate::scene::{FamilyChoice, Scene};
    use crate::stone::Stone;
    use glam::Quat;

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

    /// A single crystal of `layers` (111) periods (weak lines for a few), mosaic 0, its
    /// planes' normal tilted from the top's by `tilt` radians towards +x.
    fn weak_crystal(tilt: f32, layers: u32) -> (Scene, Stone) {
        let mut scene = Scene::default();
        scene.domains.mosaic_spread_deg = 0.0;
        scene.domains.sphere_diameter_spread = 0.0;
        scene.domains.families = FamilyChoice::Only111;
        scene.body.domain_haze = 0.0;
        scene.crystal.layers = layers;
        let planes = Vec3::new(tilt.sin(), 0.0, tilt.cos());
        let q = Quat::from_rotation_arc(Vec3::splat(1.0).normalize(), planes);
        let stone = Stone::single_crystal(&scene, q).unwrap();
        (scene, stone)
    }

    /// A 4 × 4 view (0.035 mm) straight down on the stone's apex under a directional light
    /// `light_deg` from the zenith towards +x (its disc 0.5°), nothing else in the room.
    fn apex_view<'a>(stone: &Stone, sampler: &'a SpectralSampler, light_deg: f32) -> PathSetup<'a> {
        let top = Ray::new(Vec3::new(0.0, 0.0, 100.0), -Vec3::Z);
        let (t0, _) = stone.shape.intersect(&top).unwrap();
        let apex = top.at(t0);
        let b = light_deg.to_radians();
        PathSetup {
            camera: Camera::look_at(apex + Vec3::Z * 100.0, apex, Vec3::Y, 0.02, 4, 4),
            width: 4,
            height: 4,
            spp: 1,
            max_depth: 8,
            max_scatterings: 0,
            light: Some(PathLight {
                source: LightSource::Directional {
                    direction: -Vec3::new(b.sin(), 0.0, b.cos()),
                },
                intensity: 1.0,
                disc_radius_rad: 0.5f32.to_radians(),
            }),
            environment: Environment::new(&Default::default(), 0.0).unwrap(),
            area_light: None,
            gloss: 0.0,
            seed: 9,
            spectral: sampler,
        }
    }

    #[test]
    fn a_line_seen_through_the_surface_near_its_critical_angle_is_the_jones_product() {
        // Two polarising events in one plane (x–z): the eye looks straight down on the apex
        // (normal incidence: unpolarised), the planes tilted by α reflect the light that
        // refracted in at 2α = 43° inside, close to the critical angle (43.6° at n 1.45).
        // From unpolarised light the detector reads ½ (R_s T_s + R_p T_p) (Jones, φ = 0),
        // the averaged events R̄ T̄. For weak lines (15 periods, ν ≈ 0.1) ∫R_p / ∫R_s =
        // (ν_p / ν_s)² = cos² 2θ (Kogelnik 1969), so the ratio of the two is
        // (T_s + c T_p) / (T̄ (1 + c)), c = cos² 2α, with T from Fresnel's formulas here.
        let two_alpha = 43f32.to_radians();
        let alpha = 0.5 * two_alpha;
        let (scene, stone) = weak_crystal(alpha, 15);
        let sampler = SpectralSampler::new(scene.light.illuminant, &scene.spectrum, 8);
        let n = f64::from(stone.n_eff);
        let light_deg = (n as f32 * two_alpha.sin()).asin().to_degrees();
        let setup = apex_view(&stone, &sampler, light_deg);
        let spp = 64;
        let [polarised, se, _] = mean_y_with(&stone, &setup, 0, spp, |_| {});
        let [averaged, ..] = mean_y_with(&stone, &setup, 0, spp, |t| t.polarised = false);
        assert!(polarised > 0.0 && averaged > 0.0, "{polarised} {averaged}");
        // Fresnel from inside at 2α (Born & Wolf §1.5.2).
        let cos_i = f64::from(two_alpha.cos());
        let sin_t = n * f64::from(two_alpha.sin());
        let cos_t = (1.0 - sin_t * sin_t).sqrt();
        let r_s = (n * cos_i - cos_t) / (n * cos_i + cos_t);
        let r_p = (cos_i - n * cos_t) / (cos_i + n * cos_t);
        let (t_s, t_p) = (1.0 - r_s * r_s, 1.0 - r_p * r_p);
        let c = cos_i * cos_i;
        let expected = (t_s + c * t_p) / (0.5 * (t_s + t_p) * (1.0 + c));
        let ratio = polarised / averaged;
        eprintln!(
            "Y {polarised:.5} ± {se:.5} (averaged {averaged:.5}): {ratio:.4} vs {expected:.4}"
        );
        assert!(expected < 0.95, "the chain polarises: {expected}");
        assert!(
            (ratio - expected).abs() < 0.01,
            "polarised / averaged {ratio} (Y {polarised} ± {se}) vs Jones {expected}"
        );
    }

    #[test]
    fn a_single_reflection_of_an_unpolarised_path_keeps_its_spectrum() {
        // A line met at 45° (p not reflected at all): the path reflected in that plane carries
        // the same light at every wavelength as the averaged reflection, R̄ = R_s / 2.
        let s = SpectralSampler::new(crate::scene::Illuminant::D65, &Default::default(), 8);
        let line = BraggLine::new(0.0037, 590.0, std::f64::consts::FRAC_1_SQRT_2, 400.0);
        let axis = SpState::s_axis(Vec3::new(0.6, 0.0, -0.8), Vec3::Z);
        for u in [0.1, 0.5, 0.9] {
            let plain = PathSpectrum::default();
            let averaged = plain.reflected(line, &s, u, Vec3::ZERO);
            let polarised = plain.reflected(line, &s, u, axis);
            let y = |p: &PathSpectrum| {
                let (mut xyz, mut bins) = ([0.0; 3], vec![0.0; s.grid.bins]);
                s.add_path(p, 1.0, &mut xyz, &mut bins);
                xyz
            };
            let (a, b) = (y(&averaged), y(&polarised));
            for c in 0..3 {
                assert!((a[c] - b[c]).abs() <= 1e-6 * a[c].abs(), "{a:?} vs {b:?}");
            }
            // And it is all s light now: a second such line in the same plane reflects R_s of
            // it, twice the averaged R̄.
            let again = |p: &PathSpectrum, axis| p.reflected(line, &s, u, axis);
            let (a2, b2) = (
                y(&again(&averaged, Vec3::ZERO)),
                y(&again(&polarised, axis)),
            );
            assert!((b2[1] / a2[1] - 2.0).abs() < 0.01, "{b2:?} vs {a2:?}");
        }
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

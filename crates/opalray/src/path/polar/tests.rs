//! Tests of the polarisation state against Jones matrices and the two-plate stacks.

use super::*;
use crate::geometry::{reflect, Camera, LightSource, Ray};
use crate::lights::Environment;
use crate::lights::Lamp;
use crate::optics::BraggLine;
use crate::path::tests::mean_y_with;
use crate::path::{PathSetup, PathSpectrum, Sampling, SpectralSampler};
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
    let first = SpState::unpolarised(1.0).event(SpState::s_axis(d0, n1), r1.0 as f32, r1.1 as f32);
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
        light: Some(Lamp {
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

        sampling: Sampling::Sobol,
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
    eprintln!("Y {polarised:.5} ± {se:.5} (averaged {averaged:.5}): {ratio:.4} vs {expected:.4}");
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
    let sum =
        state.event(axis, rs, rp).intensity() + state.event(axis, 1.0 - rs, 1.0 - rp).intensity();
    assert!((sum - 1.0).abs() < 1e-6, "{sum}");
}

//! The crystal as the stone model builds it, against independent numbers: how many domains
//! flash, the {220} line, the spread of hues, and the path tracer's determinism (its lines
//! carried at exact wavelengths: `physics_crystal_lines.rs`).

use glam::Vec3;
use opalray::path::SpectralSampler;
use opalray::render::prepare;
use opalray::scene::{preset, FamilyChoice, Illuminant, Pattern, Scene};
use opalray::stone::{ActiveLine, Stone};

fn grains(size_mm: f64) -> Scene {
    let mut scene = Scene::default();
    scene.domains.pattern = Pattern::Grains;
    scene.domains.grain_size_mm = size_mm;
    scene.domains.void_fraction = 0.0;
    scene
}

/// The {111} normals of domain `k` (lines met along every normal, face on).
fn normals_111(stone: &Stone, k: u32) -> Vec<Vec3> {
    let q = stone.domains[k as usize].orientation;
    [[1., 1., 1.], [-1., 1., 1.], [1., -1., 1.], [1., 1., -1.]]
        .iter()
        .map(|v: &[f32; 3]| (q * Vec3::from_array(*v)).normalize())
        .collect()
}

#[test]
fn four_families_make_four_times_the_domains_flash() {
    // For isotropic orientations the chance that one of N families has a normal (±n) within
    // a cone of half-angle δ about a direction is N·(1 − cos δ) (small δ: cones do not meet).
    let mut scene = grains(0.8);
    scene.domains.families = FamilyChoice::Only111;
    let stone = Stone::new(&scene).unwrap();
    let n = stone.domains.len() as f64;
    assert!(n > 5000.0, "{n} domains");
    for delta_deg in [5.0f64, 10.0] {
        let cos_delta = delta_deg.to_radians().cos() as f32;
        let flashing = (0..stone.domains.len() as u32)
            .filter(|&k| {
                normals_111(&stone, k)
                    .iter()
                    .any(|m| m.z.abs() >= cos_delta)
            })
            .count() as f64;
        let p = 4.0 * (1.0 - f64::from(cos_delta));
        let expected = n * p;
        let sigma = (n * p * (1.0 - p)).sqrt();
        assert!(
            (flashing - expected).abs() < 4.0 * sigma,
            "δ {delta_deg}°: {flashing} flashing, expected {expected:.0} ± {sigma:.0}"
        );
    }
}

#[test]
fn the_220_line_follows_d_n_eff_cos_theta() {
    // DESIGN §4: {220} reflects at λ = D·n_eff·cos θ (d₂₂₀ = D/2).
    let mut scene = grains(3.0);
    scene.crystal.sphere_diameter_nm = 300.0;
    scene.domains.sphere_diameter_spread = 0.0;
    let stone = Stone::new(&scene).unwrap();
    let q = stone.domains[0].orientation;
    let n220 = (q * Vec3::new(1.0, 1.0, 0.0)).normalize();
    for theta_deg in [0.0f32, 15.0, 25.0] {
        // A direction at θ to the (220) normal.
        let (t, _) = n220.any_orthonormal_pair();
        let dir = -(n220 * theta_deg.to_radians().cos() + t * theta_deg.to_radians().sin());
        let mut lines: Vec<ActiveLine> = Vec::new();
        stone.lines(0, dir, 2.0, &mut lines);
        let expected = 300.0 * stone.families.n_eff * f64::from(theta_deg.to_radians().cos());
        let found = lines
            .iter()
            .map(|l| l.line.center_nm)
            .min_by(|a, b| (a - expected).abs().total_cmp(&(b - expected).abs()))
            .unwrap();
        assert!(
            (found / expected - 1.0).abs() < 0.01,
            "θ {theta_deg}°: {found} vs {expected}"
        );
    }
}

#[test]
fn the_311_line_follows_bragg_snell_for_350_nm_spheres() {
    // DESIGN §4: for D ≳ 310 nm {311} (d₃₁₁ = a/√11, a = √2 D) reaches the visible. Light
    // from air at θ₀ to the (311) planes' normal reflects at λ = 2 d √(n̄² − sin² θ₀) (Bragg–
    // Snell), n̄² = f n_s² + (1 − f) n_m²: 430.5 nm face-on for D = 350 nm.
    let mut scene = grains(3.0);
    scene.crystal.sphere_diameter_nm = 350.0;
    scene.domains.sphere_diameter_spread = 0.0;
    let stone = Stone::new(&scene).unwrap();
    let c = &scene.crystal;
    let n_bar = (c.filling_fraction * c.n_sphere.powi(2)
        + (1.0 - c.filling_fraction) * c.n_matrix.powi(2))
    .sqrt();
    let d311 = 2f64.sqrt() * 350.0 / 11f64.sqrt();
    let q = stone.domains[0].orientation;
    let n311 = (q * Vec3::new(3.0, 1.0, 1.0)).normalize();
    for theta0_deg in [0.0f64, 20.0, 40.0] {
        let sin_inside = theta0_deg.to_radians().sin() / n_bar;
        let (t, _) = n311.any_orthonormal_pair();
        let dir = -(n311 * (1.0 - sin_inside * sin_inside).sqrt() as f32 + t * sin_inside as f32);
        let mut lines: Vec<ActiveLine> = Vec::new();
        stone.lines(0, dir.normalize(), 2.0, &mut lines);
        let expected = 2.0 * d311 * (n_bar * n_bar - theta0_deg.to_radians().sin().powi(2)).sqrt();
        let line = lines.iter().find(|l| l.normal.dot(n311).abs() > 0.9999);
        let Some(line) = line else {
            panic!("θ₀ {theta0_deg}°: no line along the (311) normal ({expected:.1} nm expected)")
        };
        assert!(
            (line.line.center_nm - expected).abs() < 0.1,
            "θ₀ {theta0_deg}°: {} vs {expected} nm",
            line.line.center_nm
        );
    }
    // Face-on, 430.5 nm (n̄ = 1.4423 for the default crystal).
    assert!((2.0 * d311 * n_bar - 430.5).abs() < 0.1);
}

#[test]
fn a_randomly_stacked_crystal_reflects_only_along_its_stacking_and_in_layer_normals() {
    // `families = "stacked"`: face on to each normal of a domain, the stone meets a line along
    // that normal for the stacking (111) and the three {220} normal to it (in-layer), and none
    // for the three oblique {111} (streaks under random stacking; `optics::families` tests
    // the phase rule). D = 300 nm puts {220} at 432 nm face-on.
    let mut scene = grains(3.0);
    scene.crystal.sphere_diameter_nm = 300.0;
    scene.domains.sphere_diameter_spread = 0.0;
    scene.domains.families = FamilyChoice::Stacked;
    let stone = Stone::new(&scene).unwrap();
    let all = Stone::new(&Scene {
        domains: opalray::scene::DomainsConfig {
            families: FamilyChoice::All,
            ..scene.domains.clone()
        },
        ..scene.clone()
    })
    .unwrap();
    let q = stone.domains[0].orientation;
    let along = |stone: &Stone, v: [f32; 3]| {
        let n = (q * Vec3::from_array(v)).normalize();
        let mut lines: Vec<ActiveLine> = Vec::new();
        stone.lines(0, -n, 2.0, &mut lines);
        lines.iter().any(|l| l.normal.dot(n).abs() > 0.9999)
    };
    let stacking = [1., 1., 1.];
    let in_layer = [[1., -1., 0.], [1., 0., -1.], [0., 1., -1.]];
    let oblique = [[-1., 1., 1.], [1., -1., 1.], [1., 1., -1.]];
    assert!(along(&stone, stacking));
    for v in in_layer {
        assert!(along(&stone, v), "in-layer {v:?}");
    }
    for v in oblique {
        assert!(!along(&stone, v), "oblique {v:?} reflects when stacked");
        assert!(
            along(&all, v),
            "oblique {v:?} must reflect in the FCC crystal"
        );
    }
}

#[test]
fn a_spread_of_sphere_sizes_spreads_the_hues_of_face_on_domains() {
    // Face-on {111} lines of every domain: one wavelength without spread, tens of nm with 3 %.
    let span = |spread: f64| {
        let mut scene = grains(1.0);
        scene.domains.sphere_diameter_spread = spread;
        let stone = Stone::new(&scene).unwrap();
        let centres: Vec<f64> = (0..200u32)
            .map(|k| {
                let n = normals_111(&stone, k)[0];
                let mut lines = Vec::new();
                stone.lines(k, -n, 2.0, &mut lines);
                lines
                    .iter()
                    .find(|l| l.kind == 0 && l.normal.dot(-n) < -0.999)
                    .unwrap()
                    .line
                    .center_nm
            })
            .collect();
        let lo = centres.iter().cloned().fold(f64::INFINITY, f64::min);
        let hi = centres.iter().cloned().fold(0.0, f64::max);
        hi - lo
    };
    assert!(span(0.0) < 0.01, "{}", span(0.0));
    // 3 % of 589 nm is 18 nm; 200 draws span about ±2.7 σ.
    assert!(span(0.03) > 60.0, "{}", span(0.03));
}

#[test]
fn path_tracer_is_identical_at_one_two_and_three_threads() {
    // And however the passes fall: 5 spp as passes of 2 + 2 + 1, or five of 1, are the same
    // bytes; a time limit that stops after the first pass gives the 2 spp image.
    use opalray::integrator::Passes;
    use std::time::Duration;
    let mut scene = preset("harlequin").unwrap();
    scene.integrator = scene.integrator.switched(opalray::scene::Method::Path);
    scene.render.width = 48;
    scene.render.height = 36;
    scene.integrator.set_spp(5);
    let prepared = prepare(&scene).unwrap();
    let bits = |frame: &opalray::Frame| -> Vec<u32> {
        frame
            .rgb
            .data
            .iter()
            .flatten()
            .chain(frame.spectral.data.iter())
            .map(|v| v.to_bits())
            .collect()
    };
    let threads = |n: usize, passes: Passes| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build()
            .unwrap()
            .install(|| prepared.render_progressive(scene.light.angle_deg, &passes))
    };
    let runs: Vec<_> = [1, 2, 3]
        .into_iter()
        .map(|n| threads(n, Passes::default()))
        .collect();
    assert!(
        bits(&runs[0]).iter().any(|&v| v != 0),
        "the image is not black"
    );
    assert_eq!(runs[0].path().unwrap().passes, 3);
    assert_eq!(bits(&runs[0]), bits(&runs[1]), "1 vs 2 threads");
    assert_eq!(bits(&runs[0]), bits(&runs[2]), "1 vs 3 threads");
    assert_eq!(runs[0].path(), runs[2].path(), "the noise estimate too");
    for n in [1, 3] {
        let single = threads(
            n,
            Passes {
                max_pass_spp: Some(1),
                ..Passes::default()
            },
        );
        assert_eq!(single.path().unwrap().passes, 5);
        assert_eq!(
            bits(&runs[0]),
            bits(&single),
            "passes of 1 spp, {n} threads"
        );
    }
    let limited = threads(
        2,
        Passes {
            time_limit: Some(Duration::from_nanos(1)),
            ..Passes::default()
        },
    );
    let stats = *limited.path().unwrap();
    assert!(stats.stopped_by_time_limit && stats.spp == 2, "{stats:?}");
    let mut two = scene.clone();
    two.integrator.set_spp(2);
    let two = prepare(&two).unwrap().render(scene.light.angle_deg);
    assert_eq!(
        bits(&limited),
        bits(&two),
        "time-limited = rendered with the spp reached"
    );
}

#[test]
fn flashing_colour_follows_the_half_vector_law() {
    // DESIGN §4: a flat face, the eye on its normal, the light at 0° / 30° / 45° / 60° in air:
    // a D = 250 nm domain whose (111) planes face the half vector shows λ = 2 d₁₁₁ n_eff cos θ_h
    // = 588.8 / 579.6 / 569.5 / 558.5 nm, θ_h half the angle between the refracted light and
    // the eye inside. Rendered: a single crystal, a narrow view of the stone's flat centre,
    // the light's spectrum flat (E), 1 nm bins; the spectrum's centroid over the line.
    use opalray::geometry::Camera;
    use opalray::light_pass::LightSource;
    use opalray::lights::Environment;
    use opalray::lights::Lamp;
    use opalray::path::{trace_paths, PathSetup, Sampling};
    let mut scene = Scene::default();
    scene.domains.sphere_diameter_spread = 0.0;
    scene.domains.mosaic_spread_deg = 0.0;
    scene.domains.families = FamilyChoice::Only111;
    scene.light.illuminant = Illuminant::E;
    scene.spectrum.bins = 400;
    let grid = scene.spectrum;
    let sampler = SpectralSampler::new(Illuminant::E, &grid, 16);
    let n_eff = opalray::optics::Families::new(&scene.crystal, true).n_eff;
    for (theta_deg, expected) in [(0.0f64, 588.8), (30.0, 579.6), (45.0, 569.5), (60.0, 558.5)] {
        let theta_t = (theta_deg.to_radians().sin() / n_eff).asin();
        // Planes facing the half vector of the refracted light (towards +x) and the eye (+z).
        let h = Vec3::new(
            (0.5 * theta_t).sin() as f32,
            0.0,
            (0.5 * theta_t).cos() as f32,
        );
        let q = glam::Quat::from_rotation_arc(Vec3::splat(1.0).normalize(), h);
        let stone = Stone::single_crystal(&scene, q).unwrap();
        let t = (theta_deg as f32).to_radians();
        let image = trace_paths(
            &stone,
            &PathSetup {
                camera: Camera::look_at(Vec3::new(0.0, 0.0, 100.0), Vec3::ZERO, Vec3::Y, 0.2, 8, 8),
                width: 8,
                height: 8,
                spp: 4,
                max_depth: 2,
                max_scatterings: 0,
                light: Some(Lamp {
                    source: LightSource::Directional {
                        direction: Vec3::new(-t.sin(), 0.0, -t.cos()),
                    },
                    intensity: 1.0,
                    disc_radius_rad: 0.0,
                }),
                environment: Environment::new(&Default::default(), 0.0).unwrap(),
                area_light: None,
                gloss: 0.0,
                seed: 1,

                sampling: Sampling::Sobol,
                spectral: &sampler,
            },
        );
        let (mut sum, mut weight) = (0.0f64, 0.0f64);
        for px in image.spectral.data.chunks(grid.bins) {
            for (b, v) in px.iter().enumerate() {
                let w = grid.center_nm(b);
                if (w - expected).abs() < 15.0 {
                    sum += w * f64::from(*v);
                    weight += f64::from(*v);
                }
            }
        }
        let total: f64 = image.xyz.iter().map(|v| f64::from(v[1])).sum();
        assert!(weight > 0.0, "{theta_deg}°: no flash (Y sum {total})");
        let centroid = sum / weight;
        assert!(
            (centroid - expected).abs() < 1.5,
            "light at {theta_deg}°: {centroid:.2} nm, expected {expected} nm"
        );
    }
}

//! The environments' values where the scenes say they are, their sampling against their
//! density, and the map's orientation and checks.

use super::*;

#[test]
fn the_studio_softbox_is_overhead_and_the_table_dark() {
    let env = Environment::new(
        &EnvironmentConfig {
            kind: EnvironmentKind::Studio,
            ..EnvironmentConfig::default()
        },
        0.0,
    )
    .unwrap();
    assert_eq!(env.value(SOFTBOX_AXIS), 1.0);
    assert!(env.value(-Vec3::Z) < 0.01);
}

#[test]
fn the_uniform_environment_is_one_everywhere_and_its_draws_cover_the_sphere() {
    let env = Environment::uniform();
    for dir in [
        Vec3::Z,
        -Vec3::Z,
        Vec3::X,
        Vec3::new(0.3, -0.5, 0.8).normalize(),
    ] {
        assert_eq!(env.value(dir), 1.0, "{dir}");
    }
    assert_eq!(env.peak(), 1.0);
    // E[value / pdf] over stratified draws is the value's integral over the sphere: 4π.
    let n = 128;
    let mut sum = 0.0f64;
    for i in 0..n * n {
        let u = [
            ((i % n) as f32 + 0.5) / n as f32,
            ((i / n) as f32 + 0.5) / n as f32,
        ];
        let draw = env.sample(u);
        sum += f64::from(draw.value / draw.pdf);
    }
    let integral = sum / (n * n) as f64;
    assert!((integral / (4.0 * PI) - 1.0).abs() < 0.01, "{integral}");
}

#[test]
fn the_tent_is_bright_overhead_but_for_the_camera_port() {
    let config = EnvironmentConfig {
        kind: EnvironmentKind::Tent,
        ..Default::default()
    };
    let env = Environment::new(&config, 0.0).unwrap();
    assert_eq!(env.value(Vec3::Z), 0.004);
    assert_eq!(env.value(Vec3::new(0.0, 1.0, 1.0).normalize()), 1.0);
    assert_eq!(env.value(Vec3::new(1.0, 0.0, 0.05).normalize()), 0.3);
    assert_eq!(env.value(-Vec3::Z), 0.0004);
}

#[test]
fn a_posed_environment_turns_with_the_camera() {
    let config = EnvironmentConfig {
        kind: EnvironmentKind::Studio,
        rotation_deg: 20.0,
        ..Default::default()
    };
    let plain = Environment::new(&config, 0.0).unwrap();
    let camera = CameraConfig {
        tilt_deg: 30.0,
        turn_deg: 25.0,
        ..Default::default()
    };
    let tilted = Environment::new(&config, 0.0)
        .unwrap()
        .posed(&config, &camera);
    // The stone turned by 25° and tilted by 30° sees the camera at
    // rot_z(−25°)·rot_x(−30°)·z: the room turns with it.
    let turn = glam::Quat::from_rotation_z(-25f32.to_radians())
        * glam::Quat::from_rotation_x(-30f32.to_radians());
    for k in 0..200 {
        let u = [(k as f32 + 0.5) / 200.0, ((k * 37) % 200) as f32 / 200.0];
        let s = plain.sample(u);
        if s.direction.z.abs() > 0.99 {
            // Near the poles the density's 1/sin θ is too steep to compare in f32.
            continue;
        }
        let d = turn * s.direction;
        assert_eq!(tilted.value(d), plain.value(s.direction), "{d}");
        assert!((tilted.pdf(d) - s.pdf).abs() <= 1e-3 * s.pdf, "{d}");
        let t = tilted.sample(u);
        assert!((t.direction - d).length() < 1e-4, "{} vs {d}", t.direction);
    }
}

#[test]
fn rotation_turns_the_environment_about_z() {
    let config = EnvironmentConfig {
        kind: EnvironmentKind::Window,
        rotation_deg: 90.0,
        ..EnvironmentConfig::default()
    };
    let env = Environment::new(&config, 0.0).unwrap();
    let plain = Environment::new(
        &EnvironmentConfig {
            rotation_deg: 0.0,
            ..config.clone()
        },
        0.0,
    )
    .unwrap();
    let d = Vec3::new(-0.3, 0.7, 0.6).normalize();
    let turned = Vec3::new(-d.y, d.x, d.z);
    assert_eq!(plain.value(d), env.value(turned));
}

#[test]
fn the_square_and_the_sphere_map_into_each_other() {
    // The centre column looks towards +y, the top row at the zenith, u = 0.75 towards +x.
    let d = direction_of([0.5, 0.5]);
    assert!((d - DVec3::Y).length() < 1e-12, "{d}");
    assert!((direction_of([0.75, 0.5]) - DVec3::X).length() < 1e-12);
    assert!((direction_of([0.3, 0.0]) - DVec3::Z).length() < 1e-12);
    for (u, v) in [
        (0.1, 0.2),
        (0.5, 0.5),
        (0.9, 0.7),
        (0.0001, 0.999),
        (0.75, 0.25),
    ] {
        let [u2, v2] = square_of(direction_of([u, v]));
        assert!(
            (u2 - u).abs() < 1e-9 && (v2 - v).abs() < 1e-9,
            "{u} {v}: {u2} {v2}"
        );
    }
}

#[test]
fn a_maps_pixel_is_seen_where_the_convention_says() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("spot.exr");
    // 64 × 32; one bright pixel at column 48 (u ≈ 0.758: towards +x), row 16 (the horizon).
    exr::prelude::write_rgb_file(&path, 64, 32, |x, y| {
        let v = if (x, y) == (48, 16) { 10.0f32 } else { 0.5 };
        (v, v, v)
    })
    .unwrap();
    let config = EnvironmentConfig {
        kind: EnvironmentKind::File,
        path: path.display().to_string(),
        intensity: 2.0,
        rotation_deg: 90.0,
    };
    let env = Environment::new(&config, 0.0).unwrap();
    let spot = direction_of([48.5 / 64.0, 16.5 / 32.0]).as_vec3();
    // Turned by 90° counter-clockwise seen from above: +x goes to +y.
    let turned = Vec3::new(-spot.y, spot.x, spot.z);
    assert!(
        (env.value(turned) - 20.0).abs() < 1e-4,
        "{}",
        env.value(turned)
    );
    assert!((env.value(-turned) - 1.0).abs() < 1e-6);
}

#[test]
fn a_map_not_twice_as_wide_as_high_is_refused_by_name() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("square.exr");
    exr::prelude::write_rgb_file(&path, 16, 16, |_, _| (1.0f32, 1.0f32, 1.0f32)).unwrap();
    let mut config = EnvironmentConfig {
        kind: EnvironmentKind::File,
        path: path.display().to_string(),
        ..EnvironmentConfig::default()
    };
    let err = Environment::new(&config, 0.0).unwrap_err().to_string();
    assert!(
        err.contains("environment.path") && err.contains("equirectangular"),
        "{err}"
    );
    config.path = dir.path().join("missing.hdr").display().to_string();
    let err = Environment::new(&config, 0.0).unwrap_err().to_string();
    assert!(
        err.contains("environment.path") && err.contains("missing.hdr"),
        "{err}"
    );
    assert!(!err.contains('\n'), "{err}");
}

//! Set-ups shared by the integration tests.

// Each test file compiles this module and uses some of it.
#![allow(dead_code)]

use std::path::Path;

use glam::{Quat, Vec3};
use opalray::geometry::Camera;
use opalray::integrator::Passes;
use opalray::lights::Environment;
use opalray::path::{trace_paths, PathSetup, SpectralSampler};
use opalray::path::{PathImage, Sampling};
use opalray::render::prepare;
use opalray::scene::{preset, FamilyChoice, PathConfig, Scene};
use opalray::stone::Stone;

/// A perfect crystal (mosaic 0, one sphere size, the (111) family alone, no haze) whose (111)
/// planes are tilted by `tilt` (radians) from the top towards +x, as one domain filling the
/// default scene's stone; with that scene.
pub fn tilted_crystal(tilt: f32) -> (Scene, Stone) {
    let mut scene = Scene::default();
    scene.domains.mosaic_spread_deg = 0.0;
    scene.domains.sphere_diameter_spread = 0.0;
    scene.domains.families = FamilyChoice::Only111;
    scene.body.domain_haze = 0.0;
    let planes = Vec3::new(tilt.sin(), 0.0, tilt.cos());
    let q = Quat::from_rotation_arc(Vec3::splat(1.0).normalize(), planes);
    let stone = Stone::single_crystal(&scene, q).unwrap();
    (scene, stone)
}

/// The preset `name` rendered at `width × height` pixels, its other fields as they are.
pub fn preset_at(name: &str, width: u32, height: u32) -> Scene {
    let mut scene = preset(name).unwrap();
    scene.render.width = width;
    scene.render.height = height;
    scene
}

/// The path integrator's image of `scene` (a path-traced scene) at its light angle, its
/// samples drawn by `sampling`.
pub fn path_image(scene: &Scene, sampling: Sampling) -> PathImage {
    let prepared = prepare(scene).unwrap();
    let (image, _) = prepared
        .render_path_image(scene.light.angle_deg, &Passes::default(), sampling)
        .expect("a path-traced scene");
    image
}

/// The path tracer looking straight down at `target` from 100 mm above it, `fov_deg` wide,
/// on `n × n` pixels, lit by `environment` alone (no light, no area light): one sample a
/// pixel, the default depth and scatterings, the surface's gloss in full, seed 5. A test
/// sets what it varies over it (`PathSetup { spp, ..view_from_above(..) }`).
pub fn view_from_above(
    sampler: &SpectralSampler,
    environment: Environment,
    target: Vec3,
    n: usize,
    fov_deg: f32,
) -> PathSetup<'_> {
    PathSetup {
        camera: Camera::look_at(target + Vec3::Z * 100.0, target, Vec3::Y, fov_deg, n, n),
        width: n,
        height: n,
        spp: 1,
        max_depth: PathConfig::default().max_depth,
        max_scatterings: PathConfig::default().max_scatterings,
        light: None,
        environment,
        area_light: None,
        gloss: 1.0,
        seed: 5,

        sampling: Sampling::Sobol,
        spectral: sampler,
    }
}

/// The mean Y of the path tracer's image of `stone` under `setup`, and its standard error
/// (from the pixels' variances).
pub fn mean_y(stone: &Stone, setup: &PathSetup) -> (f64, f64) {
    let image = trace_paths(stone, setup);
    let pixels = (setup.width * setup.height) as f64;
    let mean = image.xyz.iter().map(|v| f64::from(v[1])).sum::<f64>() / pixels;
    let variance = image.variance.iter().map(|v| f64::from(v[1])).sum::<f64>() / pixels;
    (mean, (variance / pixels).sqrt())
}

/// `(λ, value, ȳ)` rows of the CIE table `name` in `data/cie` (the third column 0 where there
/// is none; the header, which does not parse, left out).
pub fn cie_table(name: &str) -> Vec<(f64, f64, f64)> {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../data/cie")
        .join(name);
    std::fs::read_to_string(path)
        .unwrap()
        .lines()
        .filter_map(|l| {
            let v: Vec<f64> = l.split(',').filter_map(|x| x.trim().parse().ok()).collect();
            (v.len() >= 2).then(|| (v[0], v[1], *v.get(2).unwrap_or(&0.0)))
        })
        .collect()
}

/// The value of `table` (rows of [`cie_table`]) at `w`, nm, joined linearly between its rows
/// (and along its first or last two rows outside them).
pub fn linear_at(table: &[(f64, f64, f64)], w: f64) -> f64 {
    let i = table
        .iter()
        .position(|r| r.0 > w)
        .unwrap_or(table.len() - 1)
        .max(1);
    let (a, b) = (table[i - 1], table[i]);
    a.1 + (b.1 - a.1) * (w - a.0) / (b.0 - a.0)
}

//! Set-ups shared by the integration tests.

// Each test file compiles this module and uses some of it.
#![allow(dead_code)]

use glam::{Quat, Vec3};
use opalray::path::{Passes, PathImage, Sampling};
use opalray::render::prepare;
use opalray::scene::{preset, FamilyChoice, Scene};
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
    let passes = Passes {
        sampling,
        ..Passes::default()
    };
    let (image, _) = prepared
        .render_path_image(scene.light.angle_deg, &passes)
        .expect("a path-traced scene");
    image
}

//! Set-ups shared by the integration tests.

use glam::{Quat, Vec3};
use opalray::scene::{FamilyChoice, Scene};
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

//! A tiny render of a fuzzed scene: every scene that validates renders without a panic, its
//! sizes cut down first so that one run takes milliseconds.

#![no_main]

use libfuzzer_sys::fuzz_target;
use opalray::scene::IntegratorConfig;
use opalray::Scene;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    let Ok(mut scene) = Scene::from_toml_str(text, "fuzz") else {
        return;
    };
    // Small enough for thousands of runs a minute; every other field as fuzzed.
    for (n, most) in scene.structure.grid.iter_mut().zip([12, 10, 6]) {
        *n = (*n).min(most);
    }
    scene.render.width = scene.render.width.min(8);
    scene.render.height = scene.render.height.min(6);
    scene.spectrum.bins = scene.spectrum.bins.min(8);
    scene.light.rays = scene.light.rays.min(64);
    scene.crystal.angles = scene.crystal.angles.min(181);
    scene.structure.mean_radius_cells = scene.structure.mean_radius_cells.min(4.0);
    if let Some(spp) = scene.integrator.spp() {
        scene.integrator.set_spp(spp.min(2));
    }
    if let IntegratorConfig::Path(path) = &mut scene.integrator {
        path.max_depth = path.max_depth.min(4);
    }
    scene.domains.grain_size_mm = scene.domains.grain_size_mm.max(1.0);
    // What the scene's method refuses is an error, not a panic: not this target's concern.
    if scene.validate().is_err() || opalray::integrator::check(&scene).is_err() {
        return;
    }
    let frame = opalray::render::render(&scene).expect("a valid scene renders");
    let pixels = scene.render.width as usize * scene.render.height as usize;
    assert_eq!(frame.rgb.data.len(), pixels);
});

//! The scene parser and validator: any text is a scene or one error, never a panic; a
//! scene that parses round-trips through TOML.

#![no_main]

use libfuzzer_sys::fuzz_target;
use opalray::Scene;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match Scene::from_toml_str(text, "fuzz") {
        Ok(scene) => {
            let again = Scene::from_toml_str(&scene.to_toml(), "round trip")
                .expect("a valid scene's TOML parses");
            assert_eq!(again, scene, "TOML round trip");
        }
        Err(err) => {
            assert!(!err.to_string().contains('\n'), "one line: {err}");
        }
    }
});

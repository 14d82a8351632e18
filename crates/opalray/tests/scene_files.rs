//! The preset scene files in `scenes/` are exactly the presets, written out in full.

use opalray::scene::{preset, PRESET_NAMES};
use opalray::Scene;

#[test]
fn scene_files_equal_their_presets() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    for name in PRESET_NAMES {
        let path = dir.join(format!("{name}.toml"));
        let text = std::fs::read_to_string(&path).unwrap();
        let scene = preset(name).unwrap();
        assert_eq!(
            text,
            scene.to_toml(),
            "{} differs from the preset",
            path.display()
        );
        assert_eq!(Scene::load(&path).unwrap(), scene);
    }
}

#[test]
fn paper_scene_file_is_the_default_scene() {
    let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/paper.toml");
    let text = std::fs::read_to_string(path).unwrap();
    assert_eq!(text, Scene::default().to_toml());
    assert_eq!(
        Scene::from_toml_str(&text, "paper.toml").unwrap(),
        Scene::default()
    );
}

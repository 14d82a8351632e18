//! The preset scene files in `scenes/` are the presets: complete (every field written out, in
//! the order `opalray scene` prints them), with comments, and the one for `paper` is the
//! default scene.

use opalray::scene::{preset, PRESET_NAMES};
use opalray::Scene;

/// A scene file less its comment lines and the blank line that follows its header.
fn without_comments(text: &str) -> String {
    let kept: Vec<&str> = text.lines().filter(|line| !line.starts_with('#')).collect();
    let joined = kept.join("\n") + "\n";
    joined.trim_start_matches('\n').to_string()
}

fn scene_file(name: &str) -> (std::path::PathBuf, String) {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let path = dir.join(format!("{name}.toml"));
    let text = std::fs::read_to_string(&path).unwrap();
    (path, text)
}

#[test]
fn scene_files_are_their_presets_written_out_in_full() {
    for name in PRESET_NAMES {
        let (path, text) = scene_file(name);
        let scene = preset(name).unwrap();
        assert_eq!(
            without_comments(&text),
            scene.to_toml(),
            "{} is not its preset written out in full",
            path.display()
        );
        assert_eq!(Scene::load(&path).unwrap(), scene);
    }
}

#[test]
fn paper_scene_file_is_the_default_scene() {
    let (_, text) = scene_file("paper");
    assert_eq!(without_comments(&text), Scene::default().to_toml());
    assert_eq!(preset("paper").unwrap(), Scene::default());
}

//! An image carries the scene it was rendered from: `opalray scene --from IMAGE` reads it
//! back, and rendering that scene again gives the same bytes.

mod common;

use common::{opalray, stderr};

/// A small render of the default gem, not face-on and with its own seed, so that the scene
/// read back differs from the preset in more than its size.
const GEM: [&str; 10] = [
    "--width", "24", "--height", "18", "--spp", "2", "--tilt", "-25", "--seed", "7",
];

/// Render with `GEM` to `name`, read its scene back to `scene_name`, render that to
/// `again`, and return the bytes of the first and the second image.
fn round_trip(dir: &std::path::Path, name: &str, again: &str) -> (Vec<u8>, Vec<u8>) {
    let mut args = vec!["render", "-o", name];
    args.extend(GEM);
    let out = opalray(dir, &args);
    assert!(out.status.success(), "{}", stderr(&out));
    let out = opalray(dir, &["scene", "--from", name]);
    assert!(out.status.success(), "{}", stderr(&out));
    let scene = String::from_utf8(out.stdout).unwrap();
    assert!(scene.contains("tilt_deg = -25.0"), "{scene}");
    assert!(scene.contains("seed = 7"), "{scene}");
    let file = format!("{name}.toml");
    std::fs::write(dir.join(&file), scene).unwrap();
    let out = opalray(dir, &["render", &file, "-o", again]);
    assert!(out.status.success(), "{}", stderr(&out));
    let read = |n: &str| std::fs::read(dir.join(n)).unwrap();
    (read(name), read(again))
}

#[test]
fn the_scene_read_back_from_a_png_renders_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let (first, again) = round_trip(dir.path(), "a.png", "b.png");
    assert!(first == again, "a.png and b.png differ");
    // The header says what made it, in text a reader can show.
    for needle in [
        "opalray.scene",
        "opalray.seed",
        "opalray.spp",
        "opalray.method",
        "opalray.version",
    ] {
        assert!(
            first.windows(needle.len()).any(|w| w == needle.as_bytes()),
            "{needle}"
        );
    }
}

#[test]
fn the_scene_read_back_from_an_exr_renders_the_same_bytes() {
    let dir = tempfile::tempdir().unwrap();
    let (first, again) = round_trip(dir.path(), "a.exr", "b.exr");
    assert!(first == again, "a.exr and b.exr differ");
}

#[test]
fn an_image_without_a_scene_is_refused_in_one_line() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    image::RgbImage::new(4, 3)
        .save(d.join("plain.png"))
        .unwrap();
    std::fs::write(d.join("text.png"), "not a png").unwrap();
    for (name, needle) in [
        ("plain.png", "holds no scene"),
        ("text.png", "not a readable PNG"),
        ("missing.png", "no such image"),
    ] {
        let out = opalray(d, &["scene", "--from", name]);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{name}: {err}");
        assert_eq!(err.trim_end().lines().count(), 1, "{name}: {err}");
        assert!(err.contains(name) && err.contains(needle), "{name}: {err}");
        assert!(out.stdout.is_empty());
    }
}

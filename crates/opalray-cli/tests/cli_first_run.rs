//! What a new user meets first: every command starts from the same default scene, and a
//! render whose stderr is not a terminal still says how it is going.

mod common;

use common::{opalray, stderr};

/// The scene a command printed, as TOML text.
fn toml_of(out: &std::process::Output) -> String {
    assert!(out.status.success(), "{}", stderr(out));
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(text.contains("[structure]"), "{text}");
    text
}

#[test]
fn every_command_defaults_to_the_scene_render_renders() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let gem = toml_of(&opalray(d, &["scene", "--preset", "black-opal"]));
    assert_eq!(toml_of(&opalray(d, &["scene"])), gem, "scene");
    for command in ["render", "bench", "structure"] {
        let shown = toml_of(&opalray(d, &[command, "--show-scene"]));
        assert_eq!(shown, gem, "{command}");
    }
    // A sweep's frames are 320 × 240 unless sized; its scene is otherwise the same.
    let shown = toml_of(&opalray(
        d,
        &["sweep", "--show-scene", "--width", "640", "--height", "480"],
    ));
    assert_eq!(shown, gem, "sweep");
    // --show-scene renders and writes nothing.
    assert!(common::files_in(d).is_empty());
}

#[test]
fn progress_goes_to_a_log_one_line_per_pass() {
    let dir = tempfile::tempdir().unwrap();
    let log = std::fs::File::create(dir.path().join("log.txt")).unwrap();
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_opalray"))
        .args([
            "render", "--method", "path", "--width", "16", "--height", "12", "--spp", "4", "-o",
            "a.png",
        ])
        .current_dir(dir.path())
        .stderr(log)
        .status()
        .unwrap();
    assert!(status.success());
    let text = std::fs::read_to_string(dir.path().join("log.txt")).unwrap();
    // Passes of 2 and 2 samples: 2, then 4 spp done.
    assert!(text.contains("stone ready"), "{text}");
    let passes: Vec<&str> = text.lines().filter(|l| l.starts_with("pass ")).collect();
    assert_eq!(passes.len(), 2, "{text}");
    for (line, spp) in passes.iter().zip(["2 of 4 spp", "4 of 4 spp"]) {
        assert!(
            line.contains(spp) && line.contains("noise") && line.contains("elapsed"),
            "{line}"
        );
    }
    assert!(passes[0].ends_with(" left"), "{text}");
    assert!(passes[1].ends_with("done"), "{text}");

    // A sweep: one line per frame.
    let log = std::fs::File::create(dir.path().join("sweep.txt")).unwrap();
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_opalray"))
        .args([
            "sweep", "--preset", "paper", "--frames", "2", "--width", "8", "--height", "6",
            "--rays", "64",
        ])
        .current_dir(dir.path())
        .stderr(log)
        .status()
        .unwrap();
    assert!(status.success());
    let text = std::fs::read_to_string(dir.path().join("sweep.txt")).unwrap();
    assert!(text.contains("frame 1 of 2: light -60.0°"), "{text}");
    assert!(text.contains("frame 2 of 2: light 60.0°"), "{text}");
}

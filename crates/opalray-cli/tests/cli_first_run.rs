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

/// Run `opalray ARGS` in `dir` with its stderr going to the file `log` (not a terminal);
/// the log's text.
fn logged(dir: &std::path::Path, args: &[&str], log: &str) -> String {
    let file = std::fs::File::create(dir.join(log)).unwrap();
    let status = std::process::Command::new(env!("CARGO_BIN_EXE_opalray"))
        .args(args)
        .current_dir(dir)
        .stderr(file)
        .status()
        .unwrap();
    let text = std::fs::read_to_string(dir.join(log)).unwrap();
    assert!(status.success(), "{text}");
    text
}

#[test]
fn the_default_methods_view_pass_reports_its_rows_to_a_log() {
    let dir = tempfile::tempdir().unwrap();
    // The default scene: the black opal by the lobe integrator, its edges with 2 rays.
    let text = logged(
        dir.path(),
        &["render", "--width", "48", "--height", "36", "--spp", "2"],
        "log.txt",
    );
    let rows: Vec<&str> = text
        .lines()
        .filter(|l| l.starts_with("view pass: "))
        .collect();
    assert!(!rows.is_empty(), "no view pass progress: {text}");
    for line in &rows {
        assert!(
            line.contains(" rows, ") && line.contains("elapsed"),
            "{line}"
        );
    }
    // The last says it is done, with every row counted: the centres' sweep, then the edges'.
    let last = rows[rows.len() - 1];
    assert!(last.starts_with("view pass: 72 of 72 rows"), "{text}");
    assert!(last.ends_with("done"), "{text}");
    // Not a flood: a line at most every few seconds, and the last.
    let seconds: f64 = text
        .lines()
        .find_map(|l| l.split("total ").nth(1))
        .and_then(|t| t.trim_end_matches(" ms").parse::<f64>().ok())
        .expect("the stage times")
        / 1e3;
    assert!(rows.len() as f64 <= 2.0 + seconds / 2.0, "{text}");
}

#[test]
fn a_scene_without_a_light_reports_no_light_angle_nor_light_rays() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let small = ["--width", "24", "--height", "18", "--spp", "1"];
    // The gem presets are lit by the studio alone (`light.kind = "none"`).
    let mut render = vec!["render", "-o", "a.png", "--stats", "s.json"];
    render.extend(small);
    let out = opalray(d, &render);
    assert!(out.status.success(), "{}", stderr(&out));
    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("s.json")).unwrap()).unwrap();
    assert!(stats["light_angle_deg"].is_null(), "{stats}");
    assert!(stats["light_rays"].is_null(), "{stats}");
    let mut bench = vec!["bench", "--runs", "1", "--json"];
    bench.extend(small);
    let out = opalray(d, &bench);
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    assert!(v["light_rays"].is_null(), "{v}");
    let out = opalray(d, &bench[..3]);
    let table = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        table.contains("no light") && !table.contains("light rays"),
        "{table}"
    );
    // The paper's scene has its light: its angle and rays are reported.
    let out = opalray(
        d,
        &[
            "render", "--preset", "paper", "--width", "24", "--height", "18", "--rays", "4096",
            "-o", "p.png", "--stats", "p.json",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(d.join("p.json")).unwrap()).unwrap();
    assert_eq!(stats["light_angle_deg"], 30.0);
    assert!(stats["light_rays"].as_u64().unwrap() >= 4096, "{stats}");
}

#[test]
fn the_contact_sheet_labels_each_frame_with_its_value_as_swept() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let out = opalray(
        d,
        &[
            "sweep",
            "--turn-from",
            "0",
            "--turn-to",
            "5",
            "--frames",
            "3",
            "--frames-dir",
            "frames",
            "--sheet",
            "s.png",
            "--width",
            "24",
            "--height",
            "18",
            "--spp",
            "1",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    // The sheet the core lays out from the frames with the labels 0°, 2.5° and 5° (not 2°,
    // the half degree rounded to even).
    let labelled: Vec<(Vec<u8>, String)> = ["0°", "2.5°", "5°"]
        .iter()
        .enumerate()
        .map(|(k, label)| {
            let frame = image::open(d.join(format!("frames/frame-{k:04}.png"))).unwrap();
            (frame.to_rgb8().into_raw(), label.to_string())
        })
        .collect();
    let expected = opalray::output::contact_sheet(&labelled, 24, 18, 3);
    let sheet = image::open(d.join("s.png")).unwrap().to_rgb8();
    assert_eq!(
        (sheet.width() as usize, sheet.height() as usize),
        (expected.width, expected.height)
    );
    assert!(sheet.into_raw() == expected.rgb, "the labels differ");
}

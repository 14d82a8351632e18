//! `opalray sweep` moves what its flags name (the light, the stone's tilt or turn, the
//! environment), and refuses a flag that would move nothing in the scene.

mod common;

use common::{files_in, opalray, stderr};

/// A gem preset at a size that renders in a moment.
const GEM_TINY: [&str; 8] = [
    "--preset",
    "black-opal",
    "--width",
    "24",
    "--height",
    "18",
    "--spp",
    "2",
];

fn rgb8_of(path: &std::path::Path) -> Vec<u8> {
    image::open(path).unwrap().to_rgb8().into_raw()
}

#[test]
fn a_gem_swept_over_its_tilt_gives_frames_that_differ() {
    let dir = tempfile::tempdir().unwrap();
    let mut args = vec![
        "sweep",
        "--tilt-from",
        "-20",
        "--tilt-to",
        "20",
        "--frames",
        "3",
        "--frames-dir",
        "frames",
        "--stats",
        "s.json",
    ];
    args.extend(GEM_TINY);
    let out = opalray(dir.path(), &args);
    assert!(out.status.success(), "{}", stderr(&out));
    let frames: Vec<Vec<u8>> = (0..3)
        .map(|k| rgb8_of(&dir.path().join(format!("frames/frame-{k:04}.png"))))
        .collect();
    assert_ne!(frames[0], frames[1]);
    assert_ne!(frames[1], frames[2]);
    assert_ne!(frames[0], frames[2]);
    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("s.json")).unwrap()).unwrap();
    assert_eq!(stats["moves"], "tilt");
    assert_eq!(stats["angles_deg"], serde_json::json!([-20.0, 0.0, 20.0]));

    // A frame is the picture `render --tilt` gives at its tilt: the stone is prepared once
    // and only posed per frame.
    let mut render = vec!["render", "--tilt", "20", "-o", "r.png"];
    render.extend(GEM_TINY);
    let out = opalray(dir.path(), &render);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(rgb8_of(&dir.path().join("r.png")), frames[2]);
}

#[test]
fn a_gem_turned_matches_the_render_at_that_turn() {
    let dir = tempfile::tempdir().unwrap();
    let mut args = vec![
        "sweep",
        "--turn-from",
        "0",
        "--turn-to",
        "40",
        "--frames",
        "2",
        "--frames-dir",
        "frames",
    ];
    args.extend(GEM_TINY);
    let out = opalray(dir.path(), &args);
    assert!(out.status.success(), "{}", stderr(&out));
    let first = rgb8_of(&dir.path().join("frames/frame-0000.png"));
    let last = rgb8_of(&dir.path().join("frames/frame-0001.png"));
    assert_ne!(first, last);
    // The scene file's turn gives the same picture as the sweep's last frame.
    let scene = opalray(dir.path(), &["scene", "--preset", "black-opal"]);
    let text = String::from_utf8(scene.stdout)
        .unwrap()
        .replace("turn_deg = 0.0", "turn_deg = 40.0");
    std::fs::write(dir.path().join("turned.toml"), text).unwrap();
    let mut render = vec!["render", "turned.toml", "-o", "r.png"];
    render.extend(&GEM_TINY[2..]);
    let out = opalray(dir.path(), &render);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(rgb8_of(&dir.path().join("r.png")), last);
}

#[test]
fn a_flag_that_moves_nothing_is_refused_naming_what_would_move() {
    let cases: &[(&[&str], &str, &str)] = &[
        // Today's gem presets have no light: the light angle moves nothing.
        (
            &["sweep", "--preset", "black-opal", "--light-from", "-45"],
            "no light",
            "--tilt-from/--tilt-to",
        ),
        (
            &[
                "sweep",
                "--preset",
                "harlequin",
                "--from",
                "-45",
                "--to",
                "45",
            ],
            "no light",
            "--turn-from/--turn-to",
        ),
        (
            &["render", "--preset", "black-opal", "--light-angle", "-45"],
            "no light",
            "--tilt",
        ),
        // The paper's two passes see no environment.
        (
            &[
                "sweep",
                "--preset",
                "paper",
                "--env-from",
                "0",
                "--env-to",
                "90",
            ],
            "no environment",
            "--light-from/--light-to",
        ),
        (
            &["sweep", "--tilt-from", "-10", "--turn-to", "10"],
            "moves one thing",
            "--turn-from/--turn-to",
        ),
        (
            &["sweep", "--tilt-from", "-100"],
            "--tilt-from -100",
            "try -30 and 30",
        ),
    ];
    for (argv, why, what) in cases {
        let dir = tempfile::tempdir().unwrap();
        let out = opalray(dir.path(), argv);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{argv:?}: {err}");
        assert_eq!(
            err.trim_end().lines().count(),
            1,
            "{argv:?}: one line: {err}"
        );
        assert!(err.contains(why) && err.contains(what), "{argv:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
        assert!(files_in(dir.path()).is_empty(), "{argv:?} wrote a file");
    }
}

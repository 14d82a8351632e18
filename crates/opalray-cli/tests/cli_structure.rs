//! `opalray structure` as a user runs it: files written, statistics, and one-line errors
//! with exit code 2 and no output left behind for every kind of bad input.

mod common;

use std::path::Path;

use common::{files_in, opalray, opalray_with_threads, stderr};

/// Width and height from a PNG's header (signature, then the IHDR chunk: PNG spec §11.2.2).
fn png_size(path: &Path) -> (u32, u32) {
    let bytes = std::fs::read(path).unwrap();
    assert_eq!(&bytes[..8], b"\x89PNG\r\n\x1a\n");
    assert_eq!(&bytes[12..16], b"IHDR");
    let be = |at: usize| u32::from_be_bytes(bytes[at..at + 4].try_into().unwrap());
    (be(16), be(20))
}

#[test]
fn structure_writes_the_map_and_the_stats() {
    let dir = tempfile::tempdir().unwrap();
    let out = opalray(
        dir.path(),
        &[
            "structure",
            "--preset",
            "paper",
            "--scale",
            "2",
            "--output",
            "map.png",
            "--stats",
            "stats.json",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(
        stdout.contains("map.png") && stdout.contains("stats.json"),
        "{stdout}"
    );

    assert_eq!(png_size(&dir.path().join("map.png")), (200, 150));

    let text = std::fs::read_to_string(dir.path().join("stats.json")).unwrap();
    let stats: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(stats["grid"], serde_json::json!([100, 75, 25]));
    let count = |key: &str| {
        stats[key]
            .as_u64()
            .unwrap_or_else(|| panic!("{key} in {text}"))
    };
    assert_eq!(count("inside_cells"), count("clusters") + count("voids"));
    assert!(count("seeds_placed") > 0);
    let ratio = stats["void_ratio"].as_f64().unwrap();
    assert!(ratio < 0.2 && ratio > 0.05, "{ratio}");
    assert!(stats["mean_radius_cells"].as_f64().unwrap() > 0.0);
    assert!(stats["time_s"]["structure"].as_f64().unwrap() >= 0.0);
    assert_eq!(files_in(dir.path()), ["map.png", "stats.json"]);
}

/// The RGBA pixels of a PNG of 8-bit RGBA.
fn rgba(path: &Path) -> Vec<[u8; 4]> {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut buf = vec![0; reader.output_buffer_size().unwrap()];
    let info = reader.next_frame(&mut buf).unwrap();
    assert_eq!(info.color_type, png::ColorType::Rgba);
    buf[..info.buffer_size()]
        .chunks_exact(4)
        .map(|p| [p[0], p[1], p[2], p[3]])
        .collect()
}

#[test]
fn structure_draws_the_gems_stone_that_is_rendered_not_the_papers_cells() {
    let dir = tempfile::tempdir().unwrap();
    for (preset, name) in [
        ("black-opal", "gem"),
        ("paper", "paper"),
        ("pinfire", "pinfire"),
    ] {
        let out = opalray(
            dir.path(),
            &[
                "structure",
                "--preset",
                preset,
                "--scale",
                "2",
                "--output",
                &format!("{name}.png"),
                "--stats",
                &format!("{name}.json"),
            ],
        );
        assert!(out.status.success(), "{preset}: {}", stderr(&out));
    }
    let stats = |name: &str| -> serde_json::Value {
        serde_json::from_str(&std::fs::read_to_string(dir.path().join(name)).unwrap()).unwrap()
    };
    let gem = stats("gem.json");
    assert_eq!(gem["method"], "lobe", "{gem}");
    assert!(gem["domains_cut"].as_u64().unwrap() > 1, "{gem}");
    assert!(
        gem["domains"].as_u64().unwrap() > gem["domains_cut"].as_u64().unwrap(),
        "{gem}"
    );
    assert!(stats("paper.json")["void_ratio"].as_f64().is_some());
    // The black opal's plates settle within an RMS 20° of the face (scenes/black-opal.toml,
    // `orientation = "settled"`): a (111) normal coloured (|nx|, |ny|, |nz|) is bluest in
    // nearly every domain pixel (black outlines and grey potch left out). The pinfire's
    // grains, oriented at random, are bluest in about a third (|nz| the largest of three).
    let bluest = |name: &str| {
        let pixels = rgba(&dir.path().join(name));
        let domain: Vec<_> = pixels
            .iter()
            .filter(|p| p[3] == 255 && *p != &[0, 0, 0, 255] && !(p[0] == p[1] && p[1] == p[2]))
            .collect();
        // A unit normal: R² + G² + B² = 255² within the rounding.
        for p in &domain {
            let norm = p[..3]
                .iter()
                .map(|&c| f64::from(c).powi(2))
                .sum::<f64>()
                .sqrt();
            assert!((norm - 255.0).abs() < 1.5, "{name}: {p:?}");
        }
        let blue = domain.iter().filter(|p| p[2] > p[0].max(p[1])).count();
        blue as f64 / domain.len() as f64
    };
    let (settled, random) = (bluest("gem.png"), bluest("pinfire.png"));
    assert!(settled > 0.95, "{settled}");
    assert!((0.2..0.5).contains(&random), "{random}");
}

#[test]
fn structure_defaults_to_structure_png_of_the_middle_slice() {
    let dir = tempfile::tempdir().unwrap();
    let out = opalray(dir.path(), &["structure"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(stdout.contains("slice z = 12"), "{stdout}");
    assert_eq!(png_size(&dir.path().join("structure.png")), (600, 450));
}

#[test]
fn same_seed_gives_the_same_bytes_at_any_thread_count() {
    let dir = tempfile::tempdir().unwrap();
    let mut images = Vec::new();
    for threads in ["1", "3"] {
        let name = format!("t{threads}.png");
        let out = opalray_with_threads(
            dir.path(),
            &["structure", "--seed", "42", "--output", &name],
            Some(threads),
        );
        assert!(out.status.success(), "{}", stderr(&out));
        images.push(std::fs::read(dir.path().join(&name)).unwrap());
    }
    assert_eq!(images[0], images[1]);
}

/// Run `structure` with a scene file holding `scene` (if any) and `args`; expect exit code
/// 2, a single error line containing `expected`, and nothing new in the directory.
fn expect_refused(scene: Option<&str>, args: &[&str], expected: &str) {
    let dir = tempfile::tempdir().unwrap();
    let mut all = vec!["structure"];
    if let Some(text) = scene {
        std::fs::write(dir.path().join("s.toml"), text).unwrap();
        all.push("s.toml");
    }
    all.extend_from_slice(args);
    if !args.contains(&"--stats") {
        all.extend_from_slice(&["--stats", "stats.json"]);
    }
    let out = opalray(dir.path(), &all);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{all:?}: {err}");
    assert_eq!(
        err.trim_end().lines().count(),
        1,
        "{all:?}: not one line: {err}"
    );
    assert!(err.starts_with("error: "), "{all:?}: {err}");
    assert!(err.contains(expected), "{all:?}: {err} lacks {expected}");
    assert!(!err.contains("panicked"), "{err}");
    let parts: Vec<&str> = err.trim_end().split(": ").collect();
    for (i, part) in parts.iter().enumerate() {
        assert!(
            !parts[..i].contains(part),
            "{all:?} repeats `{part}`: {err}"
        );
    }
    let expected_files: Vec<String> = scene.iter().map(|_| "s.toml".to_string()).collect();
    assert_eq!(
        files_in(dir.path()),
        expected_files,
        "{all:?} left files behind"
    );
}

#[test]
fn bad_scene_files_are_refused_naming_the_field() {
    for (scene, expected) in [
        ("[structure\ngrid = [1, 2, 3]\n", "line 1"),
        ("[structure]\nvoid_ratoi = 0.3\n", "structure.void_ratoi"),
        ("[structure]\ngrid = [100, 0, 25]\n", "structure.grid"),
        ("[structure]\ngrid = [100, -75, 25]\n", "structure.grid"),
        (
            "[structure]\nsemi_axes_mm = [10.0, 0.0, 2.5]\n",
            "structure.semi_axes_mm",
        ),
        ("[structure]\nvoid_ratio = nan\n", "structure.void_ratio"),
        (
            "[structure]\nmean_radius_cells = nan\n",
            "structure.mean_radius_cells",
        ),
        ("[structure]\nvoid_ratio = 1.5\n", "structure.void_ratio"),
        (
            "[structure]\norientation_jitter_deg = -3.0\n",
            "structure.orientation_jitter_deg",
        ),
        (
            "[structure]\ngrid = [100000, 100000, 100000]\n",
            "structure.grid",
        ),
    ] {
        expect_refused(Some(scene), &[], expected);
    }
}

#[test]
fn bad_flags_are_refused_naming_the_flag() {
    expect_refused(None, &["--output", "/nonexistent/dir/x.png"], "--output");
    expect_refused(None, &["--output", "map.jpg"], "--output");
    expect_refused(None, &["--slice-z", "25"], "--slice-z");
    expect_refused(None, &["--preset", "nonesuch"], "--preset");
    expect_refused(None, &["missing.toml"], "missing.toml");
    expect_refused(
        None,
        &["--output", "m.png", "--stats", "/nonexistent/s.json"],
        "--stats",
    );
}

#[test]
fn flags_clap_refuses_exit_with_code_2() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        &["structure", "--scale", "0"][..],
        &["structure", "--slice-z", "middle"],
        &["structure", "--seed", "18446744073709551615"],
    ] {
        let out = opalray(dir.path(), args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        assert!(stderr(&out).contains(args[1]), "{}", stderr(&out));
    }
    assert!(files_in(dir.path()).is_empty());
}

#[test]
fn help_documents_every_flag_with_an_example() {
    let dir = tempfile::tempdir().unwrap();
    let out = opalray(dir.path(), &["structure", "--help"]);
    let help = String::from_utf8_lossy(&out.stdout);
    for flag in [
        "--preset",
        "--seed",
        "--slice-z",
        "--output",
        "--stats",
        "--scale",
        "Examples",
    ] {
        assert!(help.contains(flag), "help lacks {flag}:\n{help}");
    }
}

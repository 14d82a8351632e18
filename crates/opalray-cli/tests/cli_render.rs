//! `opalray render` as a user runs it: files that open, statistics, identical bytes at any
//! thread count, and one-line errors with exit code 2 and no output left behind for bad input
//! (`sweep` and `bench`: `cli_sweep_bench.rs`).

mod common;

use std::path::Path;
use std::process::Output;

use common::{args, files_in, opalray_with_env, opalray_with_threads, stderr};

fn opalray(dir: &Path, args: &[&str], threads: Option<&str>) -> Output {
    opalray_with_threads(dir, args, threads)
}

/// Small and quick: the renders here take a fraction of a second.
const SMALL: &[&str] = &[
    "--preset", "paper", "--width", "64", "--height", "48", "--bins", "16", "--rays", "20000",
];

#[test]
fn render_writes_an_image_and_its_statistics() {
    let dir = tempfile::tempdir().unwrap();
    let out = opalray(
        dir.path(),
        &args(&["render", "-o", "a.png", "--stats", "s.json"], SMALL),
        None,
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let img = image::open(dir.path().join("a.png")).unwrap();
    assert_eq!((img.width(), img.height()), (64, 48));
    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("s.json")).unwrap()).unwrap();
    for stage in [
        "structure",
        "optics",
        "light_pass",
        "view_pass",
        "color",
        "total",
    ] {
        assert!(
            stats["time_s"][stage].as_f64().unwrap() >= 0.0,
            "time_s.{stage}"
        );
    }
    assert_eq!(stats["image"]["width"], 64);
    assert_eq!(stats["image"]["height"], 48);
    let void_ratio = stats["void_ratio"].as_f64().unwrap();
    assert!(void_ratio > 0.1 && void_ratio < 0.2, "{void_ratio}");
    assert!(stats["light_rays"].as_u64().unwrap() > 19_000);
    assert!(stats["peak_memory_mb"].as_f64().unwrap() > 1.0);
    assert!(
        stats["path"].is_null(),
        "the two passes have no samples per pixel"
    );
    // The stage times are printed, as the paper reported them.
    for stage in ["structure", "optics", "light pass", "view pass", "colour"] {
        assert!(stderr(&out).contains(stage), "{}", stderr(&out));
    }
}

#[test]
fn a_stored_render_reports_its_rays_and_stored_light() {
    let dir = tempfile::tempdir().unwrap();
    let out = opalray(
        dir.path(),
        &[
            "render",
            "--preset",
            "paper-stone",
            "--width",
            "32",
            "--height",
            "24",
            "-o",
            "a.png",
            "--stats",
            "s.json",
        ],
        None,
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let stats: serde_json::Value =
        serde_json::from_slice(&std::fs::read(dir.path().join("s.json")).unwrap()).unwrap();
    assert!(stats["path"].is_null(), "no path samples");
    assert_eq!(stats["stored"]["spp"], 4);
    let light = &stats["stored"]["light"];
    assert_eq!(light["cell_mm"], 0.15);
    // The paper's ellipsoid of 10 × 7.5 × 2.5 mm holds (4π/3 · 187.5 mm³) / 0.15³ ≈ 232 700
    // cell centres.
    let cells = light["cells"].as_f64().unwrap();
    assert!((cells / 232_700.0 - 1.0).abs() < 0.01, "{cells}");
    assert!(light["lit_cells"].as_f64().unwrap() > 0.9 * cells);
    assert!(stderr(&out).contains("rays per pixel"), "{}", stderr(&out));
}

#[test]
fn time_limited_render_is_the_render_with_the_spp_it_reached() {
    // A limit of 8 s (the stone's preparation and the first pass must end within it: under a
    // second each here, a few on a machine shared by many builds) stops after some N samples
    // per pixel short of the 65536 it may reach: its image is the bytes of `--spp N`, and
    // the stats say N and its noise.
    let dir = tempfile::tempdir().unwrap();
    let tiny = [
        "--preset",
        "harlequin",
        "--method",
        "path",
        "--width",
        "32",
        "--height",
        "24",
    ];
    let limited = opalray(
        dir.path(),
        &args(
            &[
                "render",
                "-o",
                "a.png",
                "--stats",
                "a.json",
                "--time-limit",
                "8",
            ],
            &tiny,
        ),
        None,
    );
    assert!(limited.status.success(), "{}", stderr(&limited));
    let read = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    let stats = |name: &str| -> serde_json::Value { serde_json::from_slice(&read(name)).unwrap() };
    let a = stats("a.json");
    let reached = a["path"]["spp"].as_u64().unwrap();
    assert!(reached >= 2, "{a}");
    let spp = reached.to_string();
    let fixed = opalray(
        dir.path(),
        &args(
            &["render", "-o", "b.png", "--stats", "b.json", "--spp", &spp],
            &tiny,
        ),
        Some("3"),
    );
    assert!(fixed.status.success(), "{}", stderr(&fixed));
    assert!(
        read("a.png") == read("b.png"),
        "time-limited vs --spp {spp}"
    );
    let b = stats("b.json");
    assert_eq!(a["path"]["stopped_by_time_limit"], true);
    assert_eq!(a["path"]["time_limit_s"], 8.0);
    assert_eq!(
        a["path"]["same_image_with"],
        format!("--spp {spp} (integrator.spp)")
    );
    assert_eq!(b["path"]["stopped_by_time_limit"], false);
    assert_eq!(b["path"]["target_spp"], reached);
    assert_eq!(a["path"]["noise"], b["path"]["noise"]);
    let noise = &b["path"]["noise"];
    assert!(noise["pixels"].as_u64().unwrap() > 100, "{noise}");
    assert!(noise["relative_rms"].as_f64().unwrap() > 0.0, "{noise}");
    assert_eq!(noise["relative_rms_rgb"].as_array().unwrap().len(), 3);
    // The light by Bragg order too (integer sums: the same whatever the passes and threads);
    // its classes, the gloss and the background hold all of it.
    let orders = &b["path"]["bragg_orders"];
    assert_eq!(a["path"]["bragg_orders"], *orders);
    let share = |v: &serde_json::Value| v["share"].as_f64().unwrap();
    let classes: f64 = orders["classes"]
        .as_array()
        .unwrap()
        .iter()
        .map(share)
        .sum();
    let summary = &orders["summary"];
    let sum = classes + share(&summary["gloss"]) + share(&summary["background"]);
    assert!((sum - 1.0).abs() < 1e-9, "{orders}");
    assert!(share(&summary["bragg_1"]) > 0.0, "{orders}");
    assert!(
        stderr(&limited).contains(&format!("{spp} samples per pixel")),
        "{}",
        stderr(&limited)
    );
}

#[test]
fn render_writes_exr_and_spectral_exr() {
    let dir = tempfile::tempdir().unwrap();
    let out = opalray(
        dir.path(),
        &args(&["render", "-o", "a.exr", "--spectral", "cube.exr"], SMALL),
        None,
    );
    assert!(out.status.success(), "{}", stderr(&out));
    for name in ["a.exr", "cube.exr"] {
        let bytes = std::fs::read(dir.path().join(name)).unwrap();
        // OpenEXR magic number 20000630 (little endian), version 2.
        assert_eq!(&bytes[..5], &[0x76, 0x2f, 0x31, 0x01, 0x02], "{name}");
    }
    let cube = std::fs::read(dir.path().join("cube.exr")).unwrap();
    let header = String::from_utf8_lossy(&cube[..cube.len().min(4096)]);
    assert!(
        header.contains("S0.385,000000nm") || header.contains("S0.392,500000nm"),
        "spectral channels"
    );
}

#[test]
fn render_bytes_do_not_depend_on_threads() {
    let dir = tempfile::tempdir().unwrap();
    for (threads, name) in [("1", "one.png"), ("3", "three.png"), ("2", "two.png")] {
        let out = opalray(
            dir.path(),
            &args(&["render", "-o", name], SMALL),
            Some(threads),
        );
        assert!(out.status.success(), "{}", stderr(&out));
    }
    let read = |n: &str| std::fs::read(dir.path().join(n)).unwrap();
    assert_eq!(read("one.png"), read("three.png"));
    assert_eq!(read("one.png"), read("two.png"));
}

#[test]
fn render_bytes_do_not_depend_on_the_vector_instructions() {
    // The hot loops run in a copy compiled for AVX2 where the processor has it; forcing the
    // portable copy must give the same spectrum, to the bit.
    let dir = tempfile::tempdir().unwrap();
    for (mode, name) in [("portable", "portable.exr"), ("widest", "widest.exr")] {
        let out = opalray_with_env(
            dir.path(),
            &args(
                &["render", "--light-angle", "-20", "--spectral", name],
                SMALL,
            ),
            &[("OPALRAY_SIMD", mode)],
        );
        assert!(out.status.success(), "{}", stderr(&out));
    }
    let read = |n: &str| std::fs::read(dir.path().join(n)).unwrap();
    assert_eq!(read("portable.exr"), read("widest.exr"));
}

#[test]
fn bad_input_is_refused_in_one_line_with_no_file() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("bad.toml"), "[structure\n").unwrap();
    std::fs::write(dir.path().join("unknown.toml"), "[render]\nwidht = 3\n").unwrap();
    std::fs::write(dir.path().join("keep.png"), "old").unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["render", "bad.toml", "-o", "x.png"], "bad.toml"),
        (&["render", "unknown.toml", "-o", "x.png"], "render.widht"),
        (&["render", "--width", "0", "-o", "x.png"], "render.width"),
        (&["render", "--width", "-5", "-o", "x.png"], "--width"),
        (
            &["render", "--light-angle", "nan", "-o", "x.png"],
            "light.angle_deg",
        ),
        (&["render", "--rays", "0", "-o", "x.png"], "light.rays"),
        (&["render", "--cutoff", "0", "-o", "x.png"], "light.cutoff"),
        (
            &["render", "--cutoff", "-0.1", "-o", "x.png"],
            "light.cutoff",
        ),
        (&["render", "-o", "x.jpg"], "--output"),
        (&["render", "-o", "/nonexistent/dir/x.png"], "x.png"),
        (
            &["render", "--spectral", "x.png", "-o", "y.png"],
            "--spectral",
        ),
        (
            &["render", "--diameter", "-250", "-o", "keep.png"],
            "crystal.sphere_diameter_nm",
        ),
        (&["sweep", "--frames", "0", "--sheet", "x.png"], "--frames"),
        (
            &[
                "sweep", "--preset", "paper", "--from", "100", "--sheet", "x.png",
            ],
            "--from 100",
        ),
        (&["sweep", "--sheet", "x.jpg"], "--sheet"),
        (
            &["sweep", "--animation", "x.mp4", "--sheet", "x.png"],
            "--animation",
        ),
        (
            &[
                "render",
                "--stats",
                "/nonexistent/dir/s.json",
                "-o",
                "keep.png",
            ],
            "--stats",
        ),
        (
            &[
                "sweep",
                "--animation",
                "/nonexistent/dir/a.gif",
                "--sheet",
                "keep.png",
            ],
            "--animation",
        ),
        // Two outputs naming one file: the second would replace the first.
        (
            &["sweep", "--sheet", "s.png", "--animation", "./s.png"],
            "the same file as --sheet",
        ),
        (
            &["render", "-o", "x.exr", "--spectral", "x.exr"],
            "the same file as --output",
        ),
        (&["bench", "--runs", "0"], "--runs"),
        (&["bench", "--bins", "0"], "spectrum.bins"),
    ];
    for (argv, needle) in cases {
        let out = opalray(dir.path(), argv, None);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{argv:?}: {err}");
        assert_eq!(
            err.trim_end().lines().count(),
            1,
            "{argv:?}: one line: {err}"
        );
        assert!(err.contains(needle), "{argv:?}: names {needle}: {err}");
        assert!(!err.contains("panicked"), "{argv:?}: {err}");
        assert_eq!(
            files_in(dir.path()),
            ["bad.toml", "keep.png", "unknown.toml"],
            "{argv:?} left a file"
        );
        assert_eq!(std::fs::read(dir.path().join("keep.png")).unwrap(), b"old");
    }
}

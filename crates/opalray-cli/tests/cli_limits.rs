//! Sizes bounded before work: inputs read with a limit, and the whole command's peak memory
//! estimated and refused before anything is allocated, naming the value to lower and the
//! largest that fits.

mod common;

use std::time::{Duration, Instant};

use common::{opalray_with_env, stderr};

/// Run and return (exit code, stderr, seconds).
fn run(args: &[&str], env: &[(&str, &str)]) -> (Option<i32>, String, Duration) {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("big.toml"),
        "[structure]\ngrid = [400, 400, 400]\n",
    )
    .unwrap();
    let start = Instant::now();
    let out = opalray_with_env(dir.path(), args, env);
    (out.status.code(), stderr(&out), start.elapsed())
}

#[test]
fn endless_inputs_are_refused_at_once() {
    for args in [
        &["render", "/dev/zero"][..],
        &["color", "/dev/zero"],
        &["scene", "/dev/urandom"],
    ] {
        let (code, err, took) = run(args, &[]);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        assert!(err.contains("larger than the limit"), "{args:?}: {err}");
        assert!(took < Duration::from_secs(5), "{args:?}: {took:?}");
    }
}

#[test]
fn runs_over_the_memory_limit_are_refused_before_work() {
    let limit = [("OPALRAY_MAX_MEMORY_MB", "512")];
    for (args, names) in [
        (
            &[
                "render", "--preset", "paper", "--width", "4000", "--height", "4000",
            ][..],
            "the largest --width (render.width) that fits is",
        ),
        (
            &["render", "--preset", "paper", "--rays", "100000000"],
            "the largest --rays (light.rays) that fits is",
        ),
        (
            &["bench", "--width", "8000", "--height", "3000"],
            "the largest --width",
        ),
        (
            &[
                "sweep",
                "--frames",
                "1000",
                "--width",
                "640",
                "--height",
                "480",
                "--animation",
                "a.gif",
            ],
            "that fits is",
        ),
        (
            &["render", "big.toml"],
            "the largest structure.grid's z size that fits is",
        ),
        (
            &["structure", "big.toml"],
            "the largest z size that fits is",
        ),
    ] {
        let (code, err, took) = run(args, &limit);
        assert_eq!(code, Some(2), "{args:?}: {err}");
        assert!(err.contains("needs about"), "{args:?}: {err}");
        assert!(err.contains(names), "{args:?}: {err}");
        assert!(took < Duration::from_secs(5), "{args:?}: {took:?}");
    }
}

#[test]
fn the_documented_largest_image_is_refused_at_once_here() {
    // 16384 × 16384 at 40 bins is over the 4 GiB spectral-image limit.
    let (code, err, took) = run(
        &[
            "render", "--preset", "paper", "--width", "16384", "--height", "16384",
        ],
        &[],
    );
    assert_eq!(code, Some(2));
    assert!(err.contains("--width"), "{err}");
    assert!(took < Duration::from_secs(5));
}

/// The user's file the time-limit tests ask to overwrite: it must be left as it is.
const USERS_FILE: &[u8] = b"the user's file";

/// A folder holding `slow.toml`, the black opal with grains near `MAX_GRAINS` (about
/// 240 000 of 0.4 mm: seconds to grow on any machine), and the user's `keep.png`.
fn slow_stone_beside_a_users_file() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    let grains = ("grain_size_mm = 2.0", "grain_size_mm = 0.4");
    common::write_preset_with(dir.path(), "black-opal", grains, "slow.toml");
    std::fs::write(dir.path().join("keep.png"), USERS_FILE).unwrap();
    dir
}

/// Nothing written in `dir` by a command refused in its preparation: `keep.png` as it was,
/// no other file beside `slow.toml`.
fn assert_nothing_written(dir: &std::path::Path) {
    assert_eq!(std::fs::read(dir.join("keep.png")).unwrap(), USERS_FILE);
    assert_eq!(common::files_in(dir), ["keep.png", "slow.toml"]);
}

/// Run `opalray ARGS` (with `--time-limit 0.2`) in `dir`: refused in time during the stone's
/// preparation, nothing written. Returns the error line.
fn refused_in_preparation(dir: &std::path::Path, args: &[&str]) -> String {
    let start = Instant::now();
    let out = common::opalray(dir, args);
    let error = refused_in_time(&out, start.elapsed(), 5);
    assert!(
        error.contains("--time-limit 0.2: the limit passed during the stone's preparation"),
        "{args:?}: {error}"
    );
    assert_nothing_written(dir);
    error
}

#[test]
fn the_time_limit_stops_a_slow_preparation_in_time_and_writes_nothing() {
    let dir = slow_stone_beside_a_users_file();
    for method in ["path", "lobe"] {
        let args = [
            "render",
            "slow.toml",
            "--method",
            method,
            "--width",
            "8",
            "--height",
            "6",
            "--time-limit",
            "0.2",
            "--output",
            "keep.png",
            "--stats",
            "stats.json",
        ];
        refused_in_preparation(dir.path(), &args);
    }
}

/// The first line the command run with `args` (on 2 threads) writes to stderr, the command
/// killed then; and the files it left.
fn first_line(args: &[&str]) -> (String, Vec<String>) {
    use std::io::BufRead;
    let dir = tempfile::tempdir().unwrap();
    let mut child = std::process::Command::new(env!("CARGO_BIN_EXE_opalray"))
        .args(args)
        .current_dir(dir.path())
        .env("RAYON_NUM_THREADS", "2")
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    std::io::BufReader::new(child.stderr.take().unwrap())
        .read_line(&mut first)
        .unwrap();
    child.kill().unwrap();
    child.wait().unwrap();
    (first, common::files_in(dir.path()))
}

#[test]
fn a_render_of_an_hour_says_so_before_any_work() {
    let (first, files) = first_line(&[
        "render",
        "--preset",
        "black-opal",
        "--method",
        "path",
        "--width",
        "2048",
        "--height",
        "1536",
    ]);
    // 2048 × 1536 px × 4 spp at 600 µs a sample on 2 threads: about an hour.
    assert!(first.starts_with("note: about "), "{first}");
    assert!(first.contains(" min of work by the estimate"), "{first}");
    assert!(first.contains("path samples"), "{first}");
    assert!(files.is_empty());
}

#[test]
fn long_renders_of_the_other_methods_say_so_before_any_work() {
    // The lobe integrator: 1.3e7 px at 10 + 3 × 4 µs on 2 threads, about 2.4 min; the
    // stored method: 1.2e7 px at 4 + 63 × 0.5 µs, about 3.7 min; a sweep of 20 such frames
    // of the paper's two passes: 1.3e6 light rays a frame at 2 µs and 1.2e7 px at 0.5 µs,
    // about 1.5 min.
    for (args, rays) in [
        (
            &["render", "--width", "4096", "--height", "3072"][..],
            "camera rays of the lobe",
        ),
        (
            &[
                "render",
                "--preset",
                "paper-stone",
                "--width",
                "4096",
                "--height",
                "3072",
                "--spp",
                "64",
            ],
            "camera rays of the stored",
        ),
        (
            &[
                "sweep", "--preset", "paper", "--frames", "20", "--width", "4096", "--height",
                "3072", "--rays", "1310720",
            ],
            "light rays",
        ),
    ] {
        let (first, files) = first_line(args);
        assert!(first.starts_with("note: about "), "{args:?}: {first}");
        assert!(
            first.contains(" of work by the estimate"),
            "{args:?}: {first}"
        );
        assert!(first.contains(rays), "{args:?}: {first}");
        assert!(
            first.contains("--time-limit SECONDS bounds it"),
            "{args:?}: {first}"
        );
        assert!(files.is_empty(), "{args:?}: {files:?}");
    }
}

/// One `error:` line on stderr, the command's exit 2, within `seconds`.
fn refused_in_time(out: &std::process::Output, took: Duration, seconds: u64) -> String {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "{err}");
    assert!(took < Duration::from_secs(seconds), "took {took:?}: {err}");
    errors[0].to_string()
}

#[test]
fn a_sweeps_time_limit_stops_its_preparation_and_writes_nothing() {
    let dir = slow_stone_beside_a_users_file();
    let args = [
        "sweep",
        "slow.toml",
        "--frames",
        "3",
        "--width",
        "8",
        "--height",
        "6",
        "--time-limit",
        "0.2",
        "--sheet",
        "keep.png",
        "--animation",
        "a.gif",
        "--stats",
        "stats.json",
    ];
    let error = refused_in_preparation(dir.path(), &args);
    assert!(error.contains("nothing was written"), "{error}");
}

#[test]
fn a_sweep_past_its_time_limit_keeps_finished_frames_for_resume_and_writes_no_sheet() {
    // Path-traced frames of about a second each on an idle machine (16 spp took 0.3 s, and
    // all four frames finished within the limit): the limit passes during one of them.
    let dir = tempfile::tempdir().unwrap();
    let sweep = |extra: &[&str]| {
        let mut args = vec![
            "sweep",
            "--method",
            "path",
            "--spp",
            "64",
            "--frames",
            "4",
            "--width",
            "8",
            "--height",
            "6",
            "--frames-dir",
            "frames",
            "--stats",
            "stats.json",
        ];
        args.extend_from_slice(extra);
        let start = Instant::now();
        let out = common::opalray(dir.path(), &args);
        (out, start.elapsed())
    };
    let (out, took) = sweep(&["--time-limit", "1.5"]);
    let error = refused_in_time(&out, took, 5);
    assert!(
        error.contains("--time-limit 1.5: the limit passed during frame ")
            // A machine so busy that the stone (0.4 s of processor time) takes the limit:
            // no frame finished, and the resume below renders them all.
            || error.contains("--time-limit 1.5: the limit passed during the stone's"),
        "{error}"
    );
    assert!(error.contains("--resume renders only the rest"), "{error}");
    // No sheet or stats; the frames folder holds whole frames of this sweep only.
    assert_eq!(common::files_in(dir.path()), ["frames"]);
    let kept = common::files_in(&dir.path().join("frames"));
    assert!(
        kept.len() < 5 && kept.contains(&"sweep.json".to_string()),
        "{kept:?}"
    );
    // Resumed, the sweep gives the bytes of one never stopped.
    let (out, _) = sweep(&["--resume", "--sheet", "resumed.png"]);
    assert!(out.status.success(), "{}", stderr(&out));
    std::fs::remove_dir_all(dir.path().join("frames")).unwrap();
    let (out, _) = sweep(&["--sheet", "whole.png"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let read = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
    assert_eq!(read("resumed.png"), read("whole.png"));
}

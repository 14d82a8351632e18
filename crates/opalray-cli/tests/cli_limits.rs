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

//! Output streams: a full device or a closed pipe on stdout never makes a command panic.
//! A closed pipe ends the command quietly (as `head` expects); a full device is one error
//! line and a non-zero exit.

mod common;

use std::path::Path;
use std::process::{Command, Stdio};

/// One small run of every subcommand (and help), each printing to stdout.
fn commands(dir: &Path) -> Vec<Vec<String>> {
    std::fs::write(dir.join("line.csv"), "400,0\n550,1\n700,0\n").unwrap();
    let tiny = ["--width", "8", "--height", "6", "--rays", "64"];
    let mut render = vec!["render", "--output", "r.png"];
    render.extend(tiny);
    let mut sweep = vec![
        "sweep", "--preset", "paper", "--frames", "2", "--sheet", "s.png",
    ];
    sweep.extend(tiny);
    let mut bench = vec!["bench", "--preset", "paper", "--runs", "1"];
    bench.extend(tiny);
    let lists: Vec<Vec<&str>> = vec![
        vec!["scene"],
        vec!["--help"],
        vec!["render", "--help"],
        vec!["--version"],
        vec!["color", "line.csv"],
        vec!["spectrum", "--step-nm", "1"],
        vec!["structure", "--output", "m.png", "--scale", "1"],
        render,
        sweep,
        bench,
    ];
    lists
        .into_iter()
        .map(|l| l.into_iter().map(String::from).collect())
        .collect()
}

#[test]
fn full_stdout_is_one_error_line_and_no_panic() {
    let dir = tempfile::tempdir().unwrap();
    for args in commands(dir.path()) {
        let out = Command::new(env!("CARGO_BIN_EXE_opalray"))
            .args(&args)
            .current_dir(dir.path())
            .stdout(std::fs::File::create("/dev/full").unwrap())
            .output()
            .unwrap();
        let err = common::stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        let errors = err.lines().filter(|l| l.starts_with("error: ")).count();
        assert_eq!(errors, 1, "{args:?}: {err}");
        assert!(err.contains("No space left on device"), "{args:?}: {err}");
    }
}

#[test]
fn closed_pipe_ends_quietly() {
    let dir = tempfile::tempdir().unwrap();
    for args in commands(dir.path()) {
        let mut child = Command::new(env!("CARGO_BIN_EXE_opalray"))
            .args(&args)
            .current_dir(dir.path())
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .unwrap();
        // The reader goes away before the command writes a byte.
        drop(child.stdout.take());
        let out = child.wait_with_output().unwrap();
        let err = common::stderr(&out);
        assert_eq!(out.status.code(), Some(0), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        assert!(!err.contains("error"), "{args:?}: {err}");
    }
}

#[test]
fn full_stderr_does_not_panic() {
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_opalray"))
        .args(["render", "--width", "0"])
        .current_dir(dir.path())
        .stderr(std::fs::File::create("/dev/full").unwrap())
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(2));
}

//! `kill -9` in the middle of a run leaves no name behind: outputs are written to nameless
//! files (`O_TMPFILE`) and linked into place only when complete.

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::Duration;

/// Start `opalray ARGS` in `dir`, kill it (SIGKILL) after `after`, and return whether it was
/// still running then.
fn kill_after(dir: &Path, args: &[&str], after: Duration) -> bool {
    let mut child = Command::new(env!("CARGO_BIN_EXE_opalray"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .spawn()
        .unwrap();
    std::thread::sleep(after);
    let running = child.try_wait().unwrap().is_none();
    child.kill().unwrap();
    child.wait().unwrap();
    running
}

/// Every name under `dir`, folders walked.
fn names(dir: &Path) -> Vec<String> {
    let mut all = Vec::new();
    for entry in std::fs::read_dir(dir).unwrap() {
        let path = entry.unwrap().path();
        all.push(path.display().to_string());
        if path.is_dir() {
            all.extend(names(&path));
        }
    }
    all
}

#[test]
fn a_killed_run_leaves_no_temporary_name() {
    let tiny = ["--width", "64", "--height", "48"];
    let runs: Vec<Vec<&str>> = vec![
        // The two passes, 25 frames of a sweep, a sweep into a frames folder, a path-traced
        // render: each takes seconds, and is killed at 1.5 s.
        [
            "render", "--preset", "paper", "--rays", "4000000", "-o", "r.png",
        ]
        .into(),
        [
            "sweep", "--preset", "paper", "--frames", "25", "--sheet", "s.png",
        ]
        .into(),
        [
            "sweep",
            "--preset",
            "paper",
            "--frames",
            "25",
            "--sheet",
            "f.png",
            "--frames-dir",
            "frames",
            "--animation",
            "f.gif",
            "--stats",
            "f.json",
        ]
        .into(),
        [
            "render",
            "--preset",
            "black-opal",
            "--spp",
            "4096",
            "-o",
            "p.png",
        ]
        .into(),
    ];
    let dir = tempfile::tempdir().unwrap();
    let mut ran = 0;
    for run in &runs {
        let mut args = run.clone();
        args.extend(tiny);
        if !kill_after(dir.path(), &args, Duration::from_millis(1500)) {
            continue; // It finished first: nothing was killed.
        }
        ran += 1;
        let left: Vec<String> = names(dir.path())
            .into_iter()
            .filter(|n| n.contains(".opalray-") || n.ends_with(".tmp"))
            .collect();
        assert!(left.is_empty(), "{args:?} left {left:?}");
    }
    assert!(
        ran >= 3,
        "only {ran} of {} runs were still going when killed",
        runs.len()
    );
}

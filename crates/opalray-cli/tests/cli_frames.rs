//! The frames folder of a sweep (`--frames-dir`): a frame is reused only when its bytes match
//! the checksum in our manifest; a damaged manifest or a frame that is not a regular file
//! means rendering again, never mixing in or blocking.

mod common;

use std::path::Path;
use std::process::{Command, Output, Stdio};
use std::time::{Duration, Instant};

use common::stderr;

/// Run `opalray ARGS` in `dir`, killed after `limit` (then `None`).
fn opalray_within(dir: &Path, args: &[&str], limit: Duration) -> Option<Output> {
    let mut child = Command::new(env!("CARGO_BIN_EXE_opalray"))
        .args(args)
        .current_dir(dir)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    let deadline = Instant::now() + limit;
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            return None;
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    Some(child.wait_with_output().unwrap())
}

/// A four-frame sweep of the paper's stone at 8 × 6 px into `sheet`, with `extra` flags.
fn sweep(dir: &Path, sheet: &str, extra: &[&str]) -> String {
    let mut args = vec![
        "sweep", "--preset", "paper", "--width", "8", "--height", "6", "--rays", "64", "--frames",
        "4", "--sheet", sheet,
    ];
    args.extend(extra);
    let out = opalray_within(dir, &args, Duration::from_secs(120)).expect("the sweep blocked");
    assert!(out.status.success(), "{args:?}: {}", stderr(&out));
    String::from_utf8_lossy(&out.stdout).into_owned()
}

fn read(dir: &Path, name: &str) -> Vec<u8> {
    std::fs::read(dir.join(name)).unwrap()
}

#[test]
fn a_frame_whose_bytes_do_not_match_its_checksum_is_rendered_again() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    sweep(d, "whole.png", &[]);
    sweep(d, "first.png", &["--frames-dir", "f"]);
    // Another frame of the same size in frame 1's place: a whole PNG, the wrong picture.
    std::fs::copy(d.join("f/frame-0002.png"), d.join("f/frame-0001.png")).unwrap();
    let said = sweep(d, "again.png", &["--frames-dir", "f"]);
    assert!(said.contains("4 frames, 1 rendered"), "{said}");
    assert!(
        read(d, "whole.png") == read(d, "again.png"),
        "a wrong frame was mixed in"
    );
}

#[test]
fn under_a_damaged_manifest_every_frame_is_rendered_again() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Another sweep's frames (other spheres) under a manifest cut short.
    sweep(d, "other.png", &["--frames-dir", "f", "--diameter", "200"]);
    let manifest = read(d, "f/sweep.json");
    std::fs::write(d.join("f/sweep.json"), &manifest[..manifest.len() / 2]).unwrap();
    sweep(d, "whole.png", &[]);
    let said = sweep(d, "again.png", &["--frames-dir", "f"]);
    assert!(said.contains("4 frames, 4 rendered"), "{said}");
    assert!(
        read(d, "whole.png") == read(d, "again.png"),
        "another sweep's frames were mixed in"
    );
    // The manifest is whole again: the next run reuses every frame.
    let said = sweep(d, "third.png", &["--frames-dir", "f"]);
    assert!(said.contains("4 frames, 0 rendered"), "{said}");
    assert!(read(d, "whole.png") == read(d, "third.png"));
}

#[test]
fn a_named_pipe_in_place_of_a_frame_is_replaced_without_blocking() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    sweep(d, "whole.png", &[]);
    sweep(d, "first.png", &["--frames-dir", "f"]);
    std::fs::remove_file(d.join("f/frame-0003.png")).unwrap();
    let made = Command::new("mkfifo")
        .arg(d.join("f/frame-0003.png"))
        .status()
        .unwrap();
    assert!(made.success());
    let said = sweep(d, "again.png", &["--frames-dir", "f"]);
    assert!(said.contains("4 frames, 1 rendered"), "{said}");
    assert!(read(d, "whole.png") == read(d, "again.png"));
    assert!(d.join("f/frame-0003.png").is_file());
}

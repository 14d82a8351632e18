//! Output files: a failed run clobbers nothing, temporary files of killed runs are cleaned up,
//! long legal names work, and a sweep killed half-way resumes to the same bytes.

mod common;

use common::{files_in, opalray, stderr};

const TINY: [&str; 8] = [
    "--preset", "paper", "--width", "8", "--height", "6", "--rays", "64",
];

fn with_tiny<'a>(first: &[&'a str]) -> Vec<&'a str> {
    first.iter().copied().chain(TINY).collect()
}

#[test]
fn a_bad_later_output_clobbers_no_earlier_one() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("keep.png"), "old image").unwrap();
    std::fs::write(d.join("keep.exr"), "old cube").unwrap();
    std::fs::create_dir(d.join("stats.json")).unwrap();
    std::fs::create_dir(d.join("anim.gif")).unwrap();
    std::fs::write(d.join("file"), "x").unwrap();
    let cases: Vec<(Vec<&str>, &str)> = vec![
        (
            with_tiny(&["render", "-o", "keep.png", "--stats", "stats.json"]),
            "--stats stats.json: is a directory",
        ),
        (
            with_tiny(&[
                "render",
                "-o",
                "keep.png",
                "--spectral",
                "keep.exr",
                "--stats",
                "file/s.json",
            ]),
            "file is a file, not a directory",
        ),
        (
            with_tiny(&["render", "-o", "keep.png", "--stats", "/proc/s.json"]),
            "system folder",
        ),
        (
            with_tiny(&[
                "sweep",
                "--frames",
                "2",
                "--sheet",
                "keep.png",
                "--animation",
                "anim.gif",
            ]),
            "--animation anim.gif: is a directory",
        ),
        (
            with_tiny(&["structure", "-o", "keep.png", "--stats", "stats.json"]),
            "--stats stats.json: is a directory",
        ),
        (
            with_tiny(&["render", "-o", "keep.png", "--spectral", "s.exr/"]),
            "names a directory, not a file",
        ),
    ];
    for (args, expected) in cases {
        // `structure` takes no look flags.
        let args: Vec<&str> = if args[0] == "structure" {
            args[..5].to_vec()
        } else {
            args
        };
        let out = opalray(d, &args);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(expected), "{args:?}: {err}");
        assert_eq!(std::fs::read(d.join("keep.png")).unwrap(), b"old image");
        assert_eq!(std::fs::read(d.join("keep.exr")).unwrap(), b"old cube");
        assert_eq!(
            files_in(d),
            ["anim.gif", "file", "keep.exr", "keep.png", "stats.json"],
            "{args:?}"
        );
    }
}

#[test]
fn a_255_byte_name_is_written() {
    let dir = tempfile::tempdir().unwrap();
    let name = format!("{}.png", "n".repeat(251));
    let out = opalray(dir.path(), &with_tiny(&["render", "-o", &name]));
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(files_in(dir.path()), [name]);
}

#[test]
fn temporary_files_of_a_killed_run_are_removed_by_the_next() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // Where there are no nameless files, a killed run leaves its named ones: this scheme's
    // `.opalray-HASH.PID.tmp` (HASH: FNV-1a of the target's name) and the earlier
    // `.NAME.PID.tmp`, of a process that no longer runs. (`cli_kill`: with nameless files a
    // kill leaves no name at all.)
    let fnv = |name: &str| {
        name.bytes().fold(0xcbf2_9ce4_8422_2325u64, |h, b| {
            (h ^ u64::from(b)).wrapping_mul(0x0100_0000_01b3)
        })
    };
    for target in ["a.png", "a.json"] {
        let name = format!(".opalray-{:016x}.4999999.tmp", fnv(target));
        std::fs::write(d.join(name), "staged").unwrap();
    }
    std::fs::write(d.join(".a.png.4999999.tmp"), "").unwrap();
    assert_eq!(files_in(d).len(), 3);
    let out = opalray(
        d,
        &with_tiny(&["render", "-o", "a.png", "--stats", "a.json"]),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(files_in(d), ["a.json", "a.png"]);
}

#[test]
fn a_resumed_sweep_gives_the_bytes_of_an_uninterrupted_one() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let sweep = |sheet: &str, anim: &str, extra: &[&str]| {
        let mut args = with_tiny(&[
            "sweep",
            "--frames",
            "4",
            "--sheet",
            sheet,
            "--animation",
            anim,
        ]);
        args.extend(extra);
        let out = opalray(d, &args);
        assert!(out.status.success(), "{}", stderr(&out));
        String::from_utf8_lossy(&out.stdout).into_owned()
    };
    sweep("whole.png", "whole.gif", &[]);
    sweep("first.png", "first.gif", &["--frames-dir", "frames"]);
    // As if killed after two frames: the last two never written.
    for k in [2, 3] {
        std::fs::remove_file(d.join(format!("frames/frame-{k:04}.png"))).unwrap();
    }
    let said = sweep(
        "again.png",
        "again.gif",
        &["--frames-dir", "frames", "--resume"],
    );
    assert!(said.contains("4 frames, 2 rendered"), "{said}");
    let read = |n: &str| std::fs::read(d.join(n)).unwrap();
    for (a, b) in [
        ("whole.png", "again.png"),
        ("whole.gif", "again.gif"),
        ("whole.png", "first.png"),
    ] {
        assert!(read(a) == read(b), "{a} and {b} differ");
    }
    // Frames of another sweep are never mixed in.
    let mut args = with_tiny(&["sweep", "--frames", "3", "--frames-dir", "frames"]);
    args.extend(["--sheet", "other.png"]);
    let out = opalray(d, &args);
    assert_eq!(out.status.code(), Some(2));
    assert!(stderr(&out).contains("another sweep"), "{}", stderr(&out));
}

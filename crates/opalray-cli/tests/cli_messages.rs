//! Messages: a flag typed with a word processor's dash is named as such, `opalray` alone
//! prints its usage to stderr, clap's tip for a mistyped flag is kept, and a scene file over
//! the size limit names its first problem; `--help` names the memory limit's variable.

mod common;

use common::{opalray, stderr};

/// The one error line of a refused run (exit 2, no panic, nothing on stdout).
fn refused(args: &[&str]) -> String {
    let dir = tempfile::tempdir().unwrap();
    let out = opalray(dir.path(), args);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {err}");
    assert!(out.stdout.is_empty(), "{args:?}: stdout {:?}", out.stdout);
    assert!(!err.contains("panicked"), "{args:?}: {err}");
    assert_eq!(err.lines().count(), 1, "{args:?}: {err}");
    err
}

#[test]
fn a_flag_typed_with_an_em_dash_is_named_as_such() {
    for (args, fix) in [
        (vec!["render", "\u{2014}width", "64"], "--width"),
        (vec!["sweep", "\u{2013}frames", "3"], "--frames"),
        (vec!["render", "--light-angle", "\u{2212}30"], "-30"),
    ] {
        let err = refused(&args);
        assert!(err.contains(&format!("write {fix}")), "{args:?}: {err}");
        assert!(!err.contains("'64'"), "{err}");
    }
}

#[test]
fn no_subcommand_prints_the_usage_to_stderr_and_fails() {
    let dir = tempfile::tempdir().unwrap();
    let out = opalray(dir.path(), &[]);
    assert_eq!(out.status.code(), Some(2));
    assert!(
        out.stdout.is_empty(),
        "{:?}",
        String::from_utf8_lossy(&out.stdout)
    );
    let err = stderr(&out);
    assert!(err.contains("Usage: opalray"), "{err}");
    assert!(err.contains("render"), "{err}");
}

#[test]
fn a_mistyped_flag_keeps_the_similar_argument_tip() {
    let err = refused(&["render", "--widht", "8"]);
    assert!(err.contains("--widht"), "{err}");
    assert!(err.contains("similar argument exists: '--width'"), "{err}");
}

#[test]
fn an_oversized_scene_file_names_its_first_problem() {
    let dir = tempfile::tempdir().unwrap();
    let mut text = String::from("[render]\nwidht = 8\n");
    while text.len() <= 1 << 20 {
        text.push_str("# a long comment to pass the size limit of one mebibyte\n");
    }
    std::fs::write(dir.path().join("big.toml"), text).unwrap();
    let out = opalray(dir.path(), &["render", "big.toml"]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert!(err.contains("larger than the limit"), "{err}");
    assert!(err.contains("widht"), "{err}");
    assert_eq!(err.lines().count(), 1, "{err}");
}

#[test]
fn the_memory_limit_is_found_in_the_help() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        vec!["--help"],
        vec!["-h"],
        vec!["render", "--help"],
        vec!["sweep", "--help"],
    ] {
        let out = opalray(dir.path(), &args);
        assert!(out.status.success());
        let text = String::from_utf8_lossy(&out.stdout).replace("\n  ", " ");
        assert!(text.contains("OPALRAY_MAX_MEMORY_MB"), "{args:?}: {text}");
        assert!(text.contains("80 % of this machine's memory"), "{text}");
    }
}

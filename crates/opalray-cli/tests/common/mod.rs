//! What the command-line tests share: running the built `opalray` and reading what it left.

#![allow(dead_code)]

use std::path::Path;
use std::process::{Command, Output};

/// Run `opalray ARGS` in `dir`, with `RAYON_NUM_THREADS` set when `threads` is given.
pub fn opalray_with_threads(dir: &Path, args: &[&str], threads: Option<&str>) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_opalray"));
    cmd.args(args).current_dir(dir);
    if let Some(n) = threads {
        cmd.env("RAYON_NUM_THREADS", n);
    }
    cmd.output().expect("the opalray binary runs")
}

/// Run `opalray ARGS` in `dir` with the environment variables `env` set.
pub fn opalray_with_env(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_opalray"));
    cmd.args(args).current_dir(dir).envs(env.iter().copied());
    cmd.output().expect("the opalray binary runs")
}

/// Run `opalray ARGS` in `dir`.
pub fn opalray(dir: &Path, args: &[&str]) -> Output {
    opalray_with_threads(dir, args, None)
}

/// The command's standard error as text.
pub fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// The names of the files in `dir`, sorted.
pub fn files_in(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

/// Write the complete scene of preset `name` (as `--show-scene` prints it) into `dir/file`,
/// with the text `from` (which it must hold) replaced by `to`.
pub fn write_preset_with(dir: &Path, name: &str, (from, to): (&str, &str), file: &str) {
    let out = opalray(dir, &["render", "--preset", name, "--show-scene"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let text = String::from_utf8(out.stdout).unwrap();
    assert!(text.contains(from), "{text}");
    std::fs::write(dir.join(file), text.replace(from, to)).unwrap();
}

/// The arguments `first` followed by `rest`.
pub fn args<'a>(first: &[&'a str], rest: &[&'a str]) -> Vec<&'a str> {
    first.iter().chain(rest).copied().collect()
}

//! The bad-input corpus (`tests/bad_inputs/cases.txt`, written by `generate.py` there): each
//! case runs `opalray` in a folder holding the user's files and asserts the exit code, one
//! error line holding the expected text (a field or flag), no panic, and every file of the
//! user's untouched, none added, within a time limit (a command that blocks fails).

use std::collections::BTreeMap;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// One line of the corpus.
struct Case {
    line: usize,
    code: i32,
    env: Vec<(String, String)>,
    args: Vec<String>,
    /// Files written beside the fixtures: `NAME:TEXT`, several joined by ` & `; a TEXT of
    /// `@fifo` makes a named pipe.
    files: Vec<(String, Vec<u8>)>,
    expected: String,
}

/// `\n`, `\xHH`, `\"` and `\\` of a corpus field.
fn unescape(text: &str) -> Vec<u8> {
    let mut out = Vec::new();
    let bytes = text.as_bytes();
    let mut i = 0;
    while i < bytes.len() {
        if bytes[i] == b'\\' && i + 1 < bytes.len() {
            match bytes[i + 1] {
                b'n' => out.push(b'\n'),
                b'x' => {
                    out.push(u8::from_str_radix(&text[i + 2..i + 4], 16).unwrap());
                    i += 2;
                }
                other => out.push(other),
            }
            i += 2;
        } else {
            out.push(bytes[i]);
            i += 1;
        }
    }
    out
}

fn cases() -> Vec<Case> {
    let text = include_str!("bad_inputs/cases.txt");
    text.lines()
        .enumerate()
        .filter(|(_, l)| !l.trim().is_empty() && !l.starts_with('#'))
        .map(|(i, l)| {
            let cols: Vec<&str> = l.splitn(5, " | ").collect();
            assert_eq!(cols.len(), 5, "line {}: {l}", i + 1);
            let env = match cols[1] {
                "-" => vec![],
                list => list
                    .split(',')
                    .map(|kv| {
                        let (k, v) = kv.split_once('=').unwrap();
                        (k.to_string(), v.to_string())
                    })
                    .collect(),
            };
            let args = cols[2]
                .split(' ')
                .map(|a| {
                    if a == "''" {
                        String::new()
                    } else {
                        a.to_string()
                    }
                })
                .collect();
            let files = match cols[3] {
                "-" => vec![],
                specs => specs
                    .split(" & ")
                    .map(|spec| {
                        let (name, body) = spec.split_once(':').unwrap();
                        (name.to_string(), unescape(body))
                    })
                    .collect(),
            };
            Case {
                line: i + 1,
                code: cols[0].parse().unwrap(),
                env,
                args,
                files,
                expected: cols[4].to_string(),
            }
        })
        .collect()
}

/// Every path under `dir` with its bytes (folders as empty, named pipes as `<fifo>`).
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut all = BTreeMap::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            let name = path.strip_prefix(dir).unwrap().display().to_string();
            if path.is_dir() {
                all.insert(format!("{name}/"), Vec::new());
                stack.push(path);
            } else if !path.is_file() {
                all.insert(name, b"<fifo>".to_vec());
            } else {
                all.insert(name, std::fs::read(&path).unwrap());
            }
        }
    }
    all
}

/// Run one case; the reason it failed, if it did.
fn check(case: &Case) -> Option<String> {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    std::fs::write(d.join("keep.png"), "the user's image").unwrap();
    std::fs::write(d.join("keep.exr"), "the user's cube").unwrap();
    std::fs::write(d.join("afile"), "a file").unwrap();
    std::fs::create_dir(d.join("sub")).unwrap();
    std::fs::create_dir(d.join("adir.json")).unwrap();
    for (name, body) in &case.files {
        std::fs::create_dir_all(d.join(name).parent().unwrap()).unwrap();
        if body == b"@fifo" {
            let made = Command::new("mkfifo").arg(d.join(name)).status().unwrap();
            assert!(made.success(), "mkfifo {name}");
        } else {
            std::fs::write(d.join(name), body).unwrap();
        }
    }
    let before = snapshot(d);
    let mut child = Command::new(env!("CARGO_BIN_EXE_opalray"))
        .args(&case.args)
        .current_dir(d)
        .env_remove("RAYON_NUM_THREADS")
        .env_remove("OPALRAY_SIMD")
        .envs(case.env.iter().map(|(k, v)| (k, v)))
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap();
    // A bad input is refused at once: a run still going after this long is blocked.
    let deadline = Instant::now() + Duration::from_secs(60);
    while child.try_wait().unwrap().is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            let _ = child.wait();
            return Some(format!(
                "still running after 60 s: line {}: {:?}",
                case.line, case.args
            ));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    let what = format!("line {}: {:?} {:?}: {err}", case.line, case.env, case.args);
    if out.status.code() != Some(case.code) {
        return Some(format!(
            "exit {:?}, expected {}: {what}",
            out.status.code(),
            case.code
        ));
    }
    if err.contains("panicked") {
        return Some(format!("panicked: {what}"));
    }
    if err.lines().count() != 1 || !err.starts_with("error: ") {
        return Some(format!("not one error line: {what}"));
    }
    if !err.contains(&case.expected) {
        return Some(format!("no `{}`: {what}", case.expected));
    }
    if snapshot(d) != before {
        return Some(format!("files changed: {what}"));
    }
    None
}

#[test]
fn every_bad_input_is_one_clear_line_and_touches_nothing() {
    let cases = cases();
    assert!(cases.len() >= 200, "{} cases", cases.len());
    let next = std::sync::atomic::AtomicUsize::new(0);
    let failures = std::sync::Mutex::new(Vec::new());
    std::thread::scope(|s| {
        for _ in 0..4 {
            s.spawn(|| loop {
                let k = next.fetch_add(1, std::sync::atomic::Ordering::Relaxed);
                let Some(case) = cases.get(k) else { break };
                if let Some(why) = check(case) {
                    failures.lock().unwrap().push(why);
                }
            });
        }
    });
    let failures = failures.into_inner().unwrap();
    assert!(
        failures.is_empty(),
        "{} of {} cases failed:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

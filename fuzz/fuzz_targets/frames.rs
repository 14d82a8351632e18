//! The frames folder's resume logic (`opalray sweep --frames-dir DIR [--resume]`, the CLI's
//! `cmd/frames.rs`, compiled in here as it is): whatever a folder holds, opening it never
//! panics; a refused folder is left byte for byte as it was; an accepted one holds our
//! manifest afterwards (it opens again with `--resume`), and a frame is reused only when its
//! bytes match the checksum the manifest kept for it.
//!
//! The input: a first byte of switches (resume; a manifest and whether it is built as ours
//! with the fuzzed checksums, as ours with the frames' true checksums, or taken raw; frames
//! written as valid PNGs or raw; a named pipe in place of the manifest or a frame; a file
//! of the user's), then segments separated by `0xFF`: the manifest text, then each frame's
//! bytes (or, for a valid PNG, its pixels).

#![no_main]

#[allow(dead_code)]
#[path = "../../crates/opalray-cli/src/anonymous.rs"]
mod anonymous;
#[allow(dead_code)]
#[path = "../../crates/opalray-cli/src/cmd/frames.rs"]
mod frames;
/// The one item of the CLI's `outputs` that the frames folder uses (the rest needs the
/// whole command).
mod outputs {
    pub fn plain_io(err: &std::io::Error) -> String {
        err.to_string()
    }
}

use std::collections::BTreeMap;
use std::path::Path;

use libfuzzer_sys::fuzz_target;

/// The sweep: its key, three angles, frames of 3 × 2 pixels.
const KEY: &str = "0123456789abcdef";
const ANGLES: [f64; 3] = [-60.0, 0.0, 60.0];
const W: usize = 3;
const H: usize = 2;

/// Every file under `dir`: name → bytes (a pipe or folder as a marker, never opened).
fn snapshot(dir: &Path) -> BTreeMap<String, Vec<u8>> {
    let mut files = BTreeMap::new();
    if let Ok(entries) = std::fs::read_dir(dir) {
        for entry in entries.flatten() {
            let name = entry.file_name().to_string_lossy().into_owned();
            let kind = entry.file_type().ok();
            let bytes = if kind.is_some_and(|k| k.is_file()) {
                std::fs::read(entry.path()).unwrap_or_default()
            } else {
                b"<not a regular file>".to_vec()
            };
            files.insert(name, bytes);
        }
    }
    files
}

fn make_fifo(path: &Path) {
    let _ = std::process::Command::new("mkfifo").arg(path).status();
}

fuzz_target!(|data: &[u8]| {
    let Some((&switches, rest)) = data.split_first() else {
        return;
    };
    let resume = switches & 1 != 0;
    let manifest_mode = (switches >> 1) & 3; // 0 none, 1 raw, 2 ours (fuzzed sums), 3 ours (true sums)
    let valid_png = switches & 8 != 0;
    let pipe = (switches >> 4) & 3; // 0 none, 1 the manifest, 2 frame 0, 3 a user's file
    let mut segments = rest.split(|&b| b == 0xFF);
    let manifest_text = segments.next().unwrap_or_default();

    let dir = std::env::temp_dir().join(format!("opalray-fuzz-frames-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();

    // The frames: raw bytes, or valid PNGs of the fuzzed pixels.
    let mut sums = Vec::new();
    for (k, segment) in segments.take(ANGLES.len()).enumerate() {
        let path = dir.join(format!("frame-{k:04}.png"));
        if valid_png {
            let mut rgb = segment.to_vec();
            rgb.resize(W * H * 3, 0);
            opalray::output::write_png_rgb8(&path, W as u32, H as u32, &rgb).unwrap();
        } else {
            std::fs::write(&path, segment).unwrap();
        }
        sums.push(frames::checksum(&std::fs::read(&path).unwrap()));
    }
    let manifest = dir.join(frames::MANIFEST);
    match manifest_mode {
        1 => std::fs::write(&manifest, manifest_text).unwrap(),
        2 | 3 => {
            let fuzzed = String::from_utf8_lossy(manifest_text);
            let checksums: Vec<serde_json::Value> = (0..ANGLES.len())
                .map(|k| match (manifest_mode, sums.get(k)) {
                    (3, Some(sum)) => sum.clone().into(),
                    _ if k % 2 == 0 => fuzzed.to_string().into(),
                    _ => serde_json::Value::Null,
                })
                .collect();
            let text = serde_json::json!({
                "format": "opalray-frames-1",
                "sweep": KEY,
                "frames": ANGLES.len(),
                "angles_deg": ANGLES,
                "checksums": checksums,
            });
            std::fs::write(&manifest, text.to_string()).unwrap();
        }
        _ => {}
    }
    match pipe {
        1 => {
            let _ = std::fs::remove_file(&manifest);
            make_fifo(&manifest);
        }
        2 => {
            let _ = std::fs::remove_file(dir.join("frame-0000.png"));
            make_fifo(&dir.join("frame-0000.png"));
        }
        3 => std::fs::write(dir.join("notes.txt"), b"the user's").unwrap(),
        _ => {}
    }

    let before = snapshot(&dir);
    match frames::FramesDir::open(&dir, KEY.to_string(), &ANGLES, resume) {
        Err(err) => {
            let message = err.to_string();
            assert!(!message.contains('\n'), "one line: {message}");
            assert_eq!(snapshot(&dir), before, "a refused folder is left as it was");
        }
        Ok(opened) => {
            // A folder not ours (files but no manifest naming our format) is never taken.
            let ours_before = before
                .get(frames::MANIFEST)
                .is_some_and(|m| String::from_utf8_lossy(m).contains("opalray-frames-1"));
            let others = before.keys().any(|n| !n.starts_with(".opalray-"));
            assert!(ours_before || !others, "took a folder not ours: {before:?}");
            for k in 0..ANGLES.len() {
                if let Some(rgb) = opened.finished(k, W, H) {
                    assert_eq!(rgb.len(), W * H * 3);
                    let bytes = std::fs::read(dir.join(format!("frame-{k:04}.png"))).unwrap();
                    let manifest = std::fs::read_to_string(&manifest).unwrap();
                    assert!(
                        manifest.contains(&frames::checksum(&bytes)),
                        "frame {k} reused without its checksum in the manifest"
                    );
                }
            }
            // Opened, the folder is ours: it opens again, with --resume.
            let again = frames::FramesDir::open(&dir, KEY.to_string(), &ANGLES, true);
            if let Err(err) = again {
                // Only a fresh folder with no frames of this sweep is refused under --resume.
                assert!(err.to_string().contains("--resume"), "{err}");
            }
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
});

//! `opalray sweep --video`: an MP4 or WebM through ffmpeg where it is installed, and a clear
//! refusal, before any work, where it is not.

mod common;

use std::process::Command;

use common::{files_in, opalray_with_env, stderr};

const SMALL: [&str; 9] = [
    "sweep", "--preset", "paper", "--frames", "3", "--width", "33", "--height", "25",
];

fn ffmpeg_present() -> bool {
    Command::new("ffmpeg")
        .arg("-version")
        .output()
        .is_ok_and(|o| o.status.success())
}

#[test]
fn without_ffmpeg_a_video_is_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    let empty = tempfile::tempdir().unwrap();
    let path = empty.path().to_str().unwrap();
    let mut args = SMALL.to_vec();
    args.extend(["--video", "play.mp4", "--sheet", "s.png"]);
    let out = opalray_with_env(dir.path(), &args, &[("PATH", path)]);
    let err = stderr(&out);
    assert_eq!(out.status.code(), Some(2), "{err}");
    assert_eq!(err.trim_end().lines().count(), 1, "{err}");
    assert!(err.contains("--video") && err.contains("ffmpeg"), "{err}");
    assert!(
        files_in(dir.path()).is_empty(),
        "{:?}",
        files_in(dir.path())
    );
}

#[test]
fn with_ffmpeg_the_sweep_is_an_mp4_of_every_frame() {
    if !ffmpeg_present() {
        eprintln!("ffmpeg is not installed: the MP4 is not checked here");
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let mut args = SMALL.to_vec();
    args.extend(["--video", "play.mp4", "--sheet", "s.png"]);
    let out = opalray_with_env(dir.path(), &args, &[]);
    assert!(out.status.success(), "{}", stderr(&out));
    let mp4 = std::fs::read(dir.path().join("play.mp4")).unwrap();
    assert_eq!(&mp4[4..8], b"ftyp", "an MP4 file");
    assert_eq!(files_in(dir.path()), ["play.mp4", "s.png"]);
    // Every frame, the odd size padded to an even one for 4:2:0 colour.
    let probe = Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-show_entries"])
        .args([
            "stream=codec_name,width,height,nb_read_frames",
            "-of",
            "csv=p=0",
        ])
        .arg(dir.path().join("play.mp4"))
        .output()
        .unwrap();
    let said = String::from_utf8_lossy(&probe.stdout);
    assert_eq!(said.trim(), "h264,34,26,3", "{said}");
}

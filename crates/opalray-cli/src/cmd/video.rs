//! A sweep as a video (MP4: H.264, WebM: VP9) through the `ffmpeg` program: its frames are
//! streamed to ffmpeg's standard input as they complete, none kept.

use std::io::Write;
use std::path::Path;
use std::process::{Child, ChildStdin, Command, Stdio};

use anyhow::{bail, Context, Result};

/// The program run, looked up on PATH.
const FFMPEG: &str = "ffmpeg";

/// Refuse `--video` before any work where ffmpeg cannot be run.
pub fn check_ffmpeg() -> Result<()> {
    let found = Command::new(FFMPEG)
        .arg("-version")
        .stdout(Stdio::null())
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !found {
        bail!(
            "--video: needs the ffmpeg program on PATH, which was not found; install it \
             (e.g. apt install ffmpeg, brew install ffmpeg) or write --animation play.png"
        );
    }
    Ok(())
}

/// An ffmpeg process encoding the frames pushed to it into one file.
pub struct VideoWriter {
    child: Option<Child>,
    stdin: Option<ChildStdin>,
}

/// `path` as another process opens it: a nameless staged file's `/proc/self/fd/N` is this
/// process's descriptor, `/proc/PID/fd/N` to ffmpeg.
fn for_child(path: &Path) -> std::path::PathBuf {
    match path.strip_prefix("/proc/self") {
        Ok(rest) => Path::new("/proc")
            .join(std::process::id().to_string())
            .join(rest),
        Err(_) => path.to_path_buf(),
    }
}

impl VideoWriter {
    /// Start ffmpeg writing `width` × `height` RGB frames, `delay_ms` each, to `temp` (the
    /// staged file of `target`, whose extension, .mp4 or .webm, chooses the format). An odd
    /// size is padded by a black pixel: the players' 4:2:0 colour needs an even one.
    pub fn create(
        temp: &Path,
        target: &Path,
        width: usize,
        height: usize,
        delay_ms: u32,
    ) -> Result<Self> {
        let webm = target
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("webm"));
        let (format, codec) = if webm {
            ("webm", ["-c:v", "libvpx-vp9", "-b:v", "0", "-crf", "24"])
        } else {
            (
                "mp4",
                ["-c:v", "libx264", "-crf", "16", "-preset", "medium"],
            )
        };
        let rate = format!("1000/{}", delay_ms.max(1));
        let mut child = Command::new(FFMPEG)
            .args(["-hide_banner", "-loglevel", "error", "-y", "-f", "rawvideo"])
            .args(["-pix_fmt", "rgb24", "-s", &format!("{width}x{height}")])
            .args(["-framerate", &rate, "-i", "-"])
            .args([
                "-vf",
                "pad=ceil(iw/2)*2:ceil(ih/2)*2",
                "-pix_fmt",
                "yuv420p",
            ])
            .args(codec)
            .args(["-f", format])
            .arg(for_child(temp))
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .context("starting ffmpeg")?;
        let stdin = child.stdin.take();
        Ok(VideoWriter {
            child: Some(child),
            stdin,
        })
    }

    /// Stream one frame of RGB8 pixels, rows top to bottom.
    pub fn push(&mut self, rgb8: &[u8]) -> Result<()> {
        let stdin = self.stdin.as_mut().context("--video: ffmpeg has closed")?;
        if stdin.write_all(rgb8).is_err() {
            // ffmpeg stopped reading: its own message says why.
            return self.finish();
        }
        Ok(())
    }

    /// Close the stream and wait for ffmpeg; its error, if it failed, on one line.
    pub fn finish(&mut self) -> Result<()> {
        drop(self.stdin.take());
        let child = self.child.take().context("--video: ffmpeg has finished")?;
        let output = child
            .wait_with_output()
            .context("--video: waiting for ffmpeg")?;
        if !output.status.success() {
            let said = String::from_utf8_lossy(&output.stderr);
            let said = said
                .lines()
                .find(|l| !l.trim().is_empty())
                .unwrap_or("no message");
            bail!("--video: ffmpeg failed ({}): {said}", output.status);
        }
        Ok(())
    }
}

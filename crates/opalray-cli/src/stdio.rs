//! The command's two streams, written without panicking.
//!
//! `println!` and `eprintln!` panic when the stream fails (a full device, a pipe whose
//! reader has gone). Every line of output goes through [`out`] instead, whose failure is an
//! error like any other: a closed pipe ends the command quietly (as `head` expects), a full
//! device is one error line and a non-zero exit. Messages on stderr go through [`note`],
//! which ignores a failed stderr: there is nowhere left to report it.

use std::fmt::Display;
use std::io::Write;

/// Stdout failed: the pipe's reader has gone, or the device is full.
#[derive(Debug)]
pub struct StdoutFailed(pub std::io::Error);

impl Display for StdoutFailed {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        let text = self.0.to_string();
        let text = text.split(" (os error").next().unwrap_or_default();
        write!(f, "writing to stdout: {text}")
    }
}

impl std::error::Error for StdoutFailed {}

impl StdoutFailed {
    /// A reader that went away is no error of ours: end quietly.
    pub fn is_closed_pipe(&self) -> bool {
        self.0.kind() == std::io::ErrorKind::BrokenPipe
    }
}

/// Write `text` and a newline to stdout, flushed.
pub fn out(text: impl Display) -> Result<(), StdoutFailed> {
    let mut stdout = std::io::stdout().lock();
    writeln!(stdout, "{text}")
        .and_then(|()| stdout.flush())
        .map_err(StdoutFailed)
}

/// Write `text` to stdout as it is (no newline added), flushed.
pub fn out_raw(text: &str) -> Result<(), StdoutFailed> {
    let mut stdout = std::io::stdout().lock();
    stdout
        .write_all(text.as_bytes())
        .and_then(|()| stdout.flush())
        .map_err(StdoutFailed)
}

/// Write `text` and a newline to stderr; a failed stderr is ignored.
pub fn note(text: impl Display) {
    let mut stderr = std::io::stderr().lock();
    let _ = writeln!(stderr, "{text}");
    let _ = stderr.flush();
}

//! Waiting for the core without the GIL, within Python's `time_limit`: every stage of a
//! render bounded, the stone's preparation included, as `opalray render --time-limit` does.
//!
//! The work runs on its own thread; the calling thread waits for it without the GIL, looking
//! for Ctrl-C every 50 ms and at most until the deadline. The work says which stage it is in
//! ([`Stage::enter`]) and when what is left keeps to the limit itself ([`Stage::release`]: the
//! path tracer's passes after the first). A stage not done by the deadline raises
//! `TimeoutError` naming the stage and the fix. An abandoned work (the deadline, or Ctrl-C)
//! is stopped: the work runs under the call's [`Cancel`] flag, set when the caller gives up,
//! and the core's stages look at it per grain, row or tile, so the work returns within a
//! fraction of a second and frees its cores; its result is dropped, and it calls back into
//! Python no more ([`Stage::abandoned`]).

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{channel, RecvTimeoutError};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use opalray::cancel::Cancel;
use pyo3::exceptions::{PyRuntimeError, PyTimeoutError, PyValueError};
use pyo3::prelude::*;

/// How often a waiting call looks for Ctrl-C (and other signals).
const SIGNAL_POLL: Duration = Duration::from_millis(50);

/// Longest `time_limit`, seconds (a week, as the command's `--time-limit`).
const MAX_TIME_LIMIT_S: f64 = 7.0 * 24.0 * 3600.0;

/// The first stage of every render.
pub(crate) const PREPARATION: &str = "the stone's preparation";
/// The stage of a prepared scene's render.
pub(crate) const FRAME: &str = "the frame's render";

/// What to do when a stage overruns `time_limit`.
const FIX: &str = "raise time_limit, or render a lighter scene: fewer grains (a larger \
     domains.grain_size_mm), a smaller image (render.width, render.height), fewer light.rays";

/// A time limit counted from the start of a call.
#[derive(Clone, Copy, Debug)]
pub(crate) struct TimeLimit {
    /// The user's `time_limit`, seconds.
    pub seconds: f64,
    /// When the call began.
    pub started: Instant,
}

impl TimeLimit {
    /// `time_limit_s` checked (more than 0, at most a week), counted from now; `None` for no
    /// limit.
    pub fn checked(time_limit_s: Option<f64>) -> PyResult<Option<TimeLimit>> {
        match time_limit_s {
            None => Ok(None),
            Some(t) if t.is_finite() && t > 0.0 && t <= MAX_TIME_LIMIT_S => Ok(Some(TimeLimit {
                seconds: t,
                started: Instant::now(),
            })),
            Some(t) => Err(PyValueError::new_err(format!(
                "time_limit {t}: must be a number of seconds above 0 and at most \
                 {MAX_TIME_LIMIT_S}; try 60"
            ))),
        }
    }

    /// The time left of the limit now (zero once it has passed).
    pub fn left(&self) -> Duration {
        Duration::from_secs_f64(self.seconds).saturating_sub(self.started.elapsed())
    }
}

/// What the work and the waiting thread share.
struct Shared {
    /// The stage the work is in, as the error would name it.
    stage: Mutex<&'static str>,
    /// The rest of the work keeps to the limit itself.
    released: AtomicBool,
    /// The caller has stopped waiting: the result will be dropped.
    abandoned: AtomicBool,
    /// Set with `abandoned`: stops the core's stages.
    cancel: Cancel,
}

/// The work's side: tells the waiting thread where the work stands.
#[derive(Clone)]
pub(crate) struct Stage(Arc<Shared>);

impl Stage {
    /// The work enters `stage` (e.g. "the light and view passes").
    pub fn enter(&self, stage: &'static str) {
        *self.0.stage.lock().unwrap_or_else(|e| e.into_inner()) = stage;
    }

    /// From here the work keeps to the limit itself: the deadline no longer stops it.
    pub fn release(&self) {
        self.0.released.store(true, Ordering::SeqCst);
    }

    /// Whether the caller has stopped waiting (a time limit passed, or Ctrl-C): the work
    /// must not call back into Python.
    pub fn abandoned(&self) -> bool {
        self.0.abandoned.load(Ordering::SeqCst)
    }

    /// The flag that stops the work (set when the caller stops waiting); the work already
    /// runs under it on its own thread, a pool it hands work to must [scope](Cancel::scope) it.
    pub fn cancel(&self) -> &Cancel {
        &self.0.cancel
    }

    /// The caller stops waiting: the work calls back no more and its stages stop.
    fn abandon(&self) {
        self.0.abandoned.store(true, Ordering::SeqCst);
        self.0.cancel.cancel();
    }

    fn name(&self) -> &'static str {
        *self.0.stage.lock().unwrap_or_else(|e| e.into_inner())
    }
}

/// Run `job` on a new thread and wait for it without the GIL, checking for signals: a
/// `KeyboardInterrupt` returns at once (the job's stages are [cancelled](Stage::cancel) and it
/// is dropped).
pub(crate) fn run_detached<T: Send + 'static>(
    py: Python<'_>,
    job: impl FnOnce() -> T + Send + 'static,
) -> PyResult<T> {
    run_within(py, None, PREPARATION, move |_| job())
}

/// Run `job` as [`run_detached`] does, and, under `limit`, raise `TimeoutError` naming the
/// stage `job` is in when the limit passes (unless it has [released](Stage::release) it);
/// it begins in stage `first`.
pub(crate) fn run_within<T: Send + 'static>(
    py: Python<'_>,
    limit: Option<TimeLimit>,
    first: &'static str,
    job: impl FnOnce(&Stage) -> T + Send + 'static,
) -> PyResult<T> {
    let stage = Stage(Arc::new(Shared {
        stage: Mutex::new(first),
        released: AtomicBool::new(false),
        abandoned: AtomicBool::new(false),
        cancel: Cancel::new(),
    }));
    let (tx, rx) = channel();
    let worker = stage.clone();
    std::thread::spawn(move || {
        // The receiver is gone only if the caller stopped waiting: nothing to report to.
        let cancel = worker.cancel().clone();
        let _ = tx.send(cancel.scope(|| job(&worker)));
    });
    let mut rx = rx;
    loop {
        let bounded = limit.filter(|_| !stage.0.released.load(Ordering::SeqCst));
        let wait = bounded.map_or(SIGNAL_POLL, |l| SIGNAL_POLL.min(l.left()));
        // The receiver moves into the GIL-free closure and back (it is `Send`, not `Sync`).
        let (received, back) = py.detach(move || (rx.recv_timeout(wait), rx));
        rx = back;
        match received {
            Ok(value) => return Ok(value),
            Err(RecvTimeoutError::Timeout) => {
                if let Err(interrupt) = py.check_signals() {
                    stage.abandon();
                    return Err(interrupt);
                }
                let released = stage.0.released.load(Ordering::SeqCst);
                if let Some(l) = bounded.filter(|l| !released && l.left().is_zero()) {
                    stage.abandon();
                    return Err(PyTimeoutError::new_err(format!(
                        "time_limit {}: the limit passed during {} (it counts from the call, \
                         the stone's preparation included); {FIX}",
                        l.seconds,
                        stage.name()
                    )));
                }
            }
            Err(RecvTimeoutError::Disconnected) => {
                return Err(PyRuntimeError::new_err("the render thread panicked"))
            }
        }
    }
}

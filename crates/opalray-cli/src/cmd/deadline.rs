//! `--time-limit` over every stage of a command, the stone's preparation included.
//!
//! The work runs on a worker thread while the command's thread waits for it, at most until
//! the deadline. The worker says which stage it is in ([`Stage::enter`]) and when what is left
//! bounds itself ([`Stage::release`]: the path tracer's passes, cut to the time left). A stage
//! not done by the deadline ends the command at once: one error line naming the stage and the
//! fix, exit 2, no output (every output is staged until the end). The worker runs under a
//! [`Cancel`] flag set at the deadline, which the core's stages look at per grain, row or
//! tile: it stops within a fraction of a second even where the process goes on. No stage
//! needs to look at a clock for this, however long its inner loops.

use std::sync::mpsc;
use std::time::{Duration, Instant};

use anyhow::{bail, Result};
use opalray::cancel::Cancel;

/// Longest `--time-limit`, seconds (a week).
const MAX_TIME_LIMIT_S: f64 = 7.0 * 24.0 * 3600.0;

/// The stage every command's work begins with.
const PREPARATION: &str = "the stone's preparation";

/// `--time-limit SECONDS` checked: more than 0 and at most a week.
pub fn checked(limit: Option<f64>) -> Result<Option<Duration>> {
    match limit {
        None => Ok(None),
        Some(s) if s.is_finite() && s > 0.0 && s <= MAX_TIME_LIMIT_S => {
            Ok(Some(Duration::from_secs_f64(s)))
        }
        Some(s) => bail!(
            "--time-limit {s}: must be more than 0 and at most {MAX_TIME_LIMIT_S} seconds; \
             try 60"
        ),
    }
}

/// What the worker tells the waiting thread.
enum Event {
    /// A stage begins (its name as the error would say it).
    Enter(String),
    /// The rest bounds itself: wait without a deadline.
    Release,
    /// The work is over (its result is the worker's return value).
    Done,
}

/// The worker's side: tells the waiting thread where the work stands.
pub struct Stage(Option<mpsc::Sender<Event>>);

impl Stage {
    /// A stage with no deadline over it (nothing listens).
    pub fn unbounded() -> Stage {
        Stage(None)
    }

    /// The work enters `stage` (e.g. "the first pass of paths").
    pub fn enter(&self, stage: impl Into<String>) {
        self.send(Event::Enter(stage.into()));
    }

    /// From here the work keeps to the limit itself (a time-limited path tracer after its
    /// first pass): the deadline no longer stops it.
    pub fn release(&self) {
        self.send(Event::Release);
    }

    fn send(&self, event: Event) {
        if let Some(tx) = &self.0 {
            // The waiting thread has gone only when the command is ending.
            let _ = tx.send(event);
        }
    }
}

/// Run `work` within `limit` counted from `started`: its result, or, if the stage it is in
/// has not ended by then (and the work has not [released](Stage::release) the deadline),
/// an error naming that stage and `fix`. Without a limit `work` runs on this thread.
pub fn within<T, F>(limit: Option<Duration>, started: Instant, fix: &str, work: F) -> Result<T>
where
    T: Send + 'static,
    F: FnOnce(&Stage) -> Result<T> + Send + 'static,
{
    within_stage(limit, started, PREPARATION, fix, work)
}

/// [`within`], the work beginning in stage `first` (e.g. "frame 3 of 9") rather than the
/// stone's preparation.
pub fn within_stage<T, F>(
    limit: Option<Duration>,
    started: Instant,
    first: &str,
    fix: &str,
    work: F,
) -> Result<T>
where
    T: Send + 'static,
    F: FnOnce(&Stage) -> Result<T> + Send + 'static,
{
    let Some(limit) = limit else {
        return work(&Stage::unbounded());
    };
    let (tx, rx) = mpsc::channel();
    let cancel = Cancel::new();
    let scoped = cancel.clone();
    let worker = std::thread::Builder::new()
        .name("opalray-work".into())
        .spawn(move || {
            let stage = Stage(Some(tx));
            let result = scoped.scope(|| work(&stage));
            stage.send(Event::Done);
            result
        })?;
    let deadline = started + limit;
    let mut stage = first.to_string();
    let mut bounded = true;
    loop {
        let event = if bounded {
            let left = deadline.saturating_duration_since(Instant::now());
            match rx.recv_timeout(left) {
                Ok(event) => event,
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    cancel.cancel();
                    bail!(
                        "--time-limit {}: the limit passed during {stage} (it counts from the \
                         start, the stone's preparation included); {fix}",
                        limit.as_secs_f64()
                    )
                }
                Err(mpsc::RecvTimeoutError::Disconnected) => Event::Done,
            }
        } else {
            rx.recv().unwrap_or(Event::Done)
        };
        match event {
            Event::Enter(name) => stage = name,
            Event::Release => bounded = false,
            Event::Done => {
                return worker
                    .join()
                    .unwrap_or_else(|panic| std::panic::resume_unwind(panic))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_stage_past_the_limit_is_named_and_stops_the_wait_in_time() {
        let started = Instant::now();
        let err = within(
            Some(Duration::from_millis(100)),
            started,
            "nothing was written; raise it",
            |stage| {
                stage.enter("the slow stage");
                std::thread::sleep(Duration::from_secs(5));
                Ok(())
            },
        )
        .unwrap_err()
        .to_string();
        assert!(started.elapsed() < Duration::from_secs(2), "{err}");
        assert!(
            err.contains("--time-limit 0.1: the limit passed during the slow stage"),
            "{err}"
        );
        assert!(err.ends_with("; nothing was written; raise it"), "{err}");
    }

    #[test]
    fn a_stage_past_the_limit_is_cancelled_and_stops_soon_after() {
        use std::sync::atomic::{AtomicBool, Ordering};
        use std::sync::Arc;
        let stopped = Arc::new(AtomicBool::new(false));
        let seen = stopped.clone();
        let err = within(
            Some(Duration::from_millis(100)),
            Instant::now(),
            "",
            move |_| {
                // A stage's driver: its loop looks at the token of its thread.
                let cancel = Cancel::current();
                let begun = Instant::now();
                while !cancel.is_cancelled() && begun.elapsed() < Duration::from_secs(10) {
                    std::thread::sleep(Duration::from_millis(5));
                }
                seen.store(cancel.is_cancelled(), Ordering::SeqCst);
                Ok(())
            },
        );
        assert!(err.is_err());
        let waited = Instant::now();
        while !stopped.load(Ordering::SeqCst) && waited.elapsed() < Duration::from_secs(2) {
            std::thread::sleep(Duration::from_millis(5));
        }
        assert!(
            stopped.load(Ordering::SeqCst),
            "the stage ran on after the limit"
        );
        assert!(waited.elapsed() < Duration::from_millis(500));
    }

    #[test]
    fn released_work_runs_past_the_limit_and_gives_its_result() {
        let value = within(
            Some(Duration::from_millis(50)),
            Instant::now(),
            "",
            |stage| {
                stage.release();
                std::thread::sleep(Duration::from_millis(200));
                Ok(7)
            },
        )
        .unwrap();
        assert_eq!(value, 7);
    }

    #[test]
    fn work_in_time_gives_its_result_and_its_error() {
        let ok = within(Some(Duration::from_secs(60)), Instant::now(), "", |_| Ok(3));
        assert_eq!(ok.unwrap(), 3);
        let err = within(Some(Duration::from_secs(60)), Instant::now(), "", |_| {
            Err::<(), _>(anyhow::anyhow!("bad field"))
        });
        assert_eq!(err.unwrap_err().to_string(), "bad field");
    }
}

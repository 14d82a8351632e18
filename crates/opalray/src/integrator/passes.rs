//! What a render is told and tells as it goes: input [`Passes`] (a time limit, the most
//! samples per pixel in one pass, what to call after each pass or row) → output the reports
//! it calls them with ([`PassReport`], [`RowsReport`]). A method that renders in passes
//! ([`Integrator::renders_in_passes`](super::Integrator::renders_in_passes): the path
//! tracer) reports each pass; one that renders row by row (the lobe integrator) counts its
//! rows with a [`RowCounter`]; the others ignore `Passes`. None of it changes an image but
//! where a time limit stops it.

use std::sync::Mutex;
use std::time::{Duration, Instant};

/// How a render's passes run: when to stop early, and what to tell after each pass or row.
#[derive(Clone, Copy, Default)]
pub struct Passes<'a> {
    /// Stop after the pass in which this much time has passed since the render began, even
    /// short of `spp` (`None`: render all `spp`).
    pub time_limit: Option<Duration>,
    /// Most samples per pixel in one pass (`None`: no limit but the doubling; more passes
    /// mean more reports, not another image).
    pub max_pass_spp: Option<u32>,
    /// Called after every pass (on the calling thread).
    pub on_pass: Option<&'a (dyn Fn(&PassReport) + Sync)>,
    /// Called after every row of a method that renders row by row instead of in passes (the
    /// lobe integrator's view pass), from the thread that rendered it; the calls come one at
    /// a time, `rows` rising by one each.
    pub on_rows: Option<&'a (dyn Fn(&RowsReport) + Sync)>,
}

/// Where a render done row by row stands after a row.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RowsReport {
    /// Rows done, counted over every sweep of the image (the lobe integrator: every pixel's
    /// centre, then the pixels at an edge again).
    pub rows: u32,
    /// Rows in all, over every sweep.
    pub total_rows: u32,
    /// Seconds since the first row began.
    pub elapsed_s: f64,
}

/// The rows of a render done row by row, in parallel, counted and reported to
/// [`Passes::on_rows`]; the image does not depend on it.
pub(crate) struct RowCounter<'a> {
    on_rows: Option<&'a (dyn Fn(&RowsReport) + Sync)>,
    /// Rows done so far; held while a row is reported, so that reports come in order.
    done: Mutex<u32>,
    total_rows: u32,
    start: Instant,
}

impl<'a> RowCounter<'a> {
    /// A count of `total_rows` rows, starting now, reported as `passes` says.
    pub(crate) fn new(passes: &Passes<'a>, total_rows: usize) -> Self {
        RowCounter {
            on_rows: passes.on_rows,
            done: Mutex::new(0),
            total_rows: u32::try_from(total_rows).unwrap_or(u32::MAX),
            start: Instant::now(),
        }
    }

    /// One more row done.
    pub(crate) fn row_done(&self) {
        let Some(report) = self.on_rows else { return };
        let mut done = self.done.lock().unwrap_or_else(|e| e.into_inner());
        *done += 1;
        report(&RowsReport {
            rows: *done,
            total_rows: self.total_rows,
            elapsed_s: self.start.elapsed().as_secs_f64(),
        });
    }
}

/// Where a render stands after a pass.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PassReport {
    /// Passes done.
    pub passes: u32,
    /// Samples per pixel done.
    pub spp: u32,
    /// Samples per pixel asked for (the most a time-limited render renders).
    pub target_spp: u32,
    /// Seconds since the render began.
    pub elapsed_s: f64,
    /// The relative RMS noise of the luminance over the stone so far
    /// ([`Noise`](crate::film::Noise)); `None` before two samples per pixel or without stone
    /// pixels.
    pub noise: Option<f64>,
}

//! `render(scene)`: the whole chain for a scene dict in one call, as `opalray render` runs it,
//! with the path tracer's passes, the stages and the lobe integrator's rows reported to Python
//! callbacks as they go.

use std::sync::Mutex;

use pyo3::prelude::*;

use crate::deadline::{run_within, Stage, TimeLimit, PREPARATION};
use crate::frame::Frame;
use crate::scene::{scene_of, to_py_err};

/// `render(scene, time_limit_s=None, on_pass=None, on_stage=None, on_rows=None) -> Frame`:
/// the whole chain for a scene dict, as `opalray render` runs it. `time_limit_s` bounds every
/// stage, counted from the call, the stone's preparation included: a stage not done in time
/// raises `TimeoutError` naming it, except the path tracer's passes after the first, which
/// stop after the pass in which the time has passed. `on_pass(passes, spp, target_spp,
/// elapsed_s, noise)` is called after every pass of the path tracer (noise `None` before two
/// samples per pixel), `on_stage(stage)` as the stone is ready and the passes begin,
/// `on_rows(rows, total_rows, elapsed_s)` as the lobe integrator's view pass goes (at its
/// first row, then at most every 0.2 s, and at its last).
#[pyfunction]
#[pyo3(signature = (scene, time_limit_s=None, on_pass=None, on_stage=None, on_rows=None))]
pub fn render(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    time_limit_s: Option<f64>,
    on_pass: Option<Py<PyAny>>,
    on_stage: Option<Py<PyAny>>,
    on_rows: Option<Py<PyAny>>,
) -> PyResult<Frame> {
    let limit = TimeLimit::checked(time_limit_s)?;
    let scene = scene_of(scene)?;
    let result = run_within(py, limit, PREPARATION, move |stage| {
        let prepared = opalray::prepare(&scene)?;
        let in_passes = opalray::integrator::of(scene.integrator.method()).renders_in_passes();
        let passes_stage = if in_passes {
            "the first pass of paths (2 samples per pixel)"
        } else {
            "the light and view passes"
        };
        stage.enter(passes_stage);
        if let (Some(callback), false) = (&on_stage, stage.abandoned()) {
            Python::attach(|py| {
                if let Err(err) = callback.call1(py, (passes_stage,)) {
                    err.print(py);
                }
            });
        }
        let report = |r: &opalray::integrator::PassReport| {
            if r.passes == 1 {
                stage.release();
            }
            let Some(callback) = &on_pass else { return };
            if stage.abandoned() {
                return;
            }
            Python::attach(|py| {
                let args = (r.passes, r.spp, r.target_spp, r.elapsed_s, r.noise);
                if let Err(err) = callback.call1(py, args) {
                    err.print(py);
                }
            });
        };
        let last_rows = Mutex::new(0.0);
        let rows = rows_reporter(on_rows.as_ref(), stage, &last_rows);
        let passes = opalray::integrator::Passes {
            // The passes get what the preparation left of the limit.
            time_limit: limit.map(|l| l.left()),
            on_pass: Some(&report),
            on_rows: Some(&rows),
            ..Default::default()
        };
        let mut frame = prepared.render_progressive(scene.light.angle_deg, &passes);
        if let Some(report) = &mut frame.report {
            // The passes had what the preparation left of it; the limit is the caller's.
            report.set_time_limit(time_limit_s);
        }
        Ok(Frame::new(&scene, frame, scene.light.angle_deg))
    })?;
    result.map_err(to_py_err)
}

/// Seconds between two calls of Python's `on_rows` (and the last row's).
const ROWS_EVERY_S: f64 = 0.2;

/// A rows report for the core that calls `on_rows(rows, total_rows, elapsed_s)` at the
/// first row, then at most every [`ROWS_EVERY_S`] (`last` holds the time of the last call,
/// seconds) and at the last row; never once `stage` is abandoned.
fn rows_reporter<'a>(
    on_rows: Option<&'a Py<PyAny>>,
    stage: &'a Stage,
    last: &'a Mutex<f64>,
) -> impl Fn(&opalray::integrator::RowsReport) + Sync + 'a {
    move |r| {
        let Some(callback) = on_rows else { return };
        let mut last = last.lock().unwrap_or_else(|e| e.into_inner());
        let due = r.rows == 1 || r.rows >= r.total_rows || r.elapsed_s - *last >= ROWS_EVERY_S;
        if !due || stage.abandoned() {
            return;
        }
        *last = r.elapsed_s;
        Python::attach(|py| {
            if let Err(err) = callback.call1(py, (r.rows, r.total_rows, r.elapsed_s)) {
                err.print(py);
            }
        });
    }
}

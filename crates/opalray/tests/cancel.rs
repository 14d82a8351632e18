//! Cooperative cancellation: a stage whose caller has given up stops within a fraction of a
//! second, with `Error::Cancelled`, and frees its cores; a token never set changes nothing.

use std::time::Duration;

use opalray::cancel::Cancel;
use opalray::error::Error;
use opalray::integrator::Passes;
use opalray::scene::{preset, Scene};

/// The harlequin with grains small enough that growing them takes seconds (about 60 000).
fn many_grains() -> Scene {
    let mut scene = preset("harlequin").unwrap();
    scene.domains.grain_size_mm = 0.25;
    scene.render.width = 8;
    scene.render.height = 6;
    scene
}

/// The tests of this file one at a time: each measures the whole process's processor time.
static SERIAL: std::sync::Mutex<()> = std::sync::Mutex::new(());

/// Processor seconds this process has spent (user + system, `/proc/self/stat` in clock ticks
/// of 1/100 s): a measure of the work after a cancel that a busy machine does not stretch.
fn cpu_s() -> f64 {
    let stat = std::fs::read_to_string("/proc/self/stat").unwrap();
    // The fields after the command name (which ends with the last ')'): utime and stime are
    // the 14th and 15th of the line, the 12th and 13th after it.
    let rest = &stat[stat.rfind(')').unwrap() + 2..];
    let fields: Vec<&str> = rest.split_whitespace().collect();
    let ticks: u64 = fields[11].parse::<u64>().unwrap() + fields[12].parse::<u64>().unwrap();
    ticks as f64 / 100.0
}

/// Set `cancel` after `after` from another thread; the processor seconds spent then.
fn cancel_after(cancel: &Cancel, after: Duration) -> std::thread::JoinHandle<f64> {
    let cancel = cancel.clone();
    std::thread::spawn(move || {
        std::thread::sleep(after);
        cancel.cancel();
        cpu_s()
    })
}

/// The work between the cancel and the return, processor seconds: under 0.25 s (about 100 ms
/// on each of two cores, plus the ticks' rounding).
fn assert_stopped_soon(cpu_at_cancel: f64, cpu_at_return: f64) {
    let late = cpu_at_return - cpu_at_cancel;
    assert!(
        late < 0.25,
        "{late:.2} s of processor time after the cancel"
    );
}

#[test]
fn a_cancelled_preparation_of_many_grains_stops_within_a_second() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let scene = many_grains();
    let cancel = Cancel::new();
    let setter = cancel_after(&cancel, Duration::from_millis(300));
    let result = cancel.scope(|| opalray::prepare(&scene));
    let returned = cpu_s();
    let cancelled_at = setter.join().unwrap();
    assert!(
        matches!(result, Err(Error::Cancelled)),
        "the preparation ran to its end: {:?}",
        result.map(|_| ())
    );
    assert_stopped_soon(cancelled_at, returned);
}

#[test]
fn a_cancelled_render_returns_cancelled_promptly() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mut scene = preset("black-opal").unwrap();
    scene.render.width = 320;
    scene.render.height = 240;
    let prepared = opalray::prepare(&scene).unwrap();
    let cancel = Cancel::new();
    let setter = cancel_after(&cancel, Duration::from_millis(50));
    let result = prepared.render_cancellable(scene.light.angle_deg, &Passes::default(), &cancel);
    let returned = cpu_s();
    let cancelled_at = setter.join().unwrap();
    assert!(
        matches!(result, Err(Error::Cancelled)),
        "the render ran to its end"
    );
    assert_stopped_soon(cancelled_at, returned);
}

#[test]
fn a_token_never_set_changes_no_byte_of_the_frame() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let mut scene = preset("harlequin").unwrap();
    scene.render.width = 32;
    scene.render.height = 24;
    let prepared = opalray::prepare(&scene).unwrap();
    let plain = prepared.render(scene.light.angle_deg);
    let cancel = Cancel::new();
    let scoped = prepared
        .render_cancellable(scene.light.angle_deg, &Passes::default(), &cancel)
        .unwrap();
    assert_eq!(plain.spectral.data, scoped.spectral.data);
}

//! Cooperative cancellation: a stage whose caller has given up stops within a fraction of a
//! second, with `Error::Cancelled`, and frees its cores; a token never set changes nothing.

use std::time::{Duration, Instant};

use opalray::cancel::Cancel;
use opalray::error::Error;
use opalray::path::Passes;
use opalray::scene::{preset, Scene};

/// The harlequin with grains small enough that growing them takes seconds (about 60 000).
fn many_grains() -> Scene {
    let mut scene = preset("harlequin").unwrap();
    scene.domains.grain_size_mm = 0.25;
    scene.render.width = 8;
    scene.render.height = 6;
    scene
}

/// Set `cancel` after `after` from another thread.
fn cancel_after(cancel: &Cancel, after: Duration) -> std::thread::JoinHandle<Instant> {
    let cancel = cancel.clone();
    std::thread::spawn(move || {
        std::thread::sleep(after);
        cancel.cancel();
        Instant::now()
    })
}

#[test]
fn a_cancelled_preparation_of_many_grains_stops_within_a_second() {
    let scene = many_grains();
    let cancel = Cancel::new();
    let setter = cancel_after(&cancel, Duration::from_millis(300));
    let result = cancel.scope(|| opalray::prepare(&scene));
    let returned = Instant::now();
    let cancelled_at = setter.join().unwrap();
    assert!(
        matches!(result, Err(Error::Cancelled)),
        "the preparation ran to its end: {:?}",
        result.map(|_| ())
    );
    let late = returned.saturating_duration_since(cancelled_at);
    assert!(
        late < Duration::from_secs(1),
        "stopped {late:?} after the cancel"
    );
}

#[test]
fn a_cancelled_render_returns_cancelled_promptly() {
    let mut scene = preset("black-opal").unwrap();
    scene.render.width = 320;
    scene.render.height = 240;
    let prepared = opalray::prepare(&scene).unwrap();
    let cancel = Cancel::new();
    let setter = cancel_after(&cancel, Duration::from_millis(50));
    let result = prepared.render_cancellable(scene.light.angle_deg, &Passes::default(), &cancel);
    let returned = Instant::now();
    let cancelled_at = setter.join().unwrap();
    assert!(
        matches!(result, Err(Error::Cancelled)),
        "the render ran to its end"
    );
    let late = returned.saturating_duration_since(cancelled_at);
    assert!(
        late < Duration::from_millis(500),
        "stopped {late:?} after the cancel"
    );
}

#[test]
fn a_token_never_set_changes_no_byte_of_the_frame() {
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

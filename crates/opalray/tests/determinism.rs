//! Same scene and seed → identical bits, at any thread count; another seed → another stone.

use opalray::render::{prepare, Frame};
use opalray::Scene;

fn small_scene(seed: u64) -> Scene {
    let mut s = Scene::default();
    s.render.width = 64;
    s.render.height = 48;
    s.spectrum.bins = 16;
    s.light.rays = 20_000;
    s.structure.seed = seed;
    s
}

fn with_threads<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(f)
}

fn bits(frame: &Frame) -> (Vec<u32>, Vec<u8>) {
    let spectral = frame.spectral.data.iter().map(|v| v.to_bits()).collect();
    let display = opalray::color::to_display_rgb8(&frame.rgb, &Scene::default().color);
    (spectral, display)
}

#[test]
fn render_is_identical_at_one_two_and_three_threads() {
    let scene = small_scene(1);
    let runs: Vec<_> = [1, 2, 3]
        .into_iter()
        .map(|n| with_threads(n, || bits(&opalray::render(&scene).unwrap())))
        .collect();
    assert!(runs[0].0.iter().any(|&v| v != 0), "the image is not black");
    assert_eq!(runs[0], runs[1], "1 vs 2 threads");
    assert_eq!(runs[0], runs[2], "1 vs 3 threads");
}

#[test]
fn energy_ledger_is_identical_at_one_two_and_three_threads() {
    // The `--stats` file's energy figures: each tile's ledger is added in tile order, not per
    // thread, so not even the last digit depends on the threads.
    let scene = small_scene(1);
    let ledgers: Vec<_> = [1, 2, 3]
        .into_iter()
        .map(|n| with_threads(n, || opalray::render(&scene).unwrap().ledger()))
        .collect();
    let bits = |l: &opalray::light_pass::EnergyLedger| {
        [
            l.emitted,
            l.reflected,
            l.escaped,
            l.stored,
            l.absorbed,
            l.truncated,
        ]
        .map(f64::to_bits)
    };
    assert!(ledgers[0].stored > 0.0 && ledgers[0].cells_crossed > 0);
    assert_eq!(bits(&ledgers[0]), bits(&ledgers[1]), "1 vs 2 threads");
    assert_eq!(bits(&ledgers[0]), bits(&ledgers[2]), "1 vs 3 threads");
    assert_eq!(ledgers[0], ledgers[2]);
}

#[test]
fn roulette_is_identical_at_one_two_and_three_threads() {
    // Roulette draws from each ray's own stream, so its choices do not depend on the threads.
    let mut scene = small_scene(1);
    scene.light.roulette = true;
    let runs: Vec<_> = [1, 2, 3]
        .into_iter()
        .map(|n| with_threads(n, || bits(&opalray::render(&scene).unwrap())))
        .collect();
    assert_eq!(runs[0], runs[1], "1 vs 2 threads");
    assert_eq!(runs[0], runs[2], "1 vs 3 threads");
    let cut = bits(&opalray::render(&small_scene(1)).unwrap());
    assert_ne!(runs[0].0, cut.0, "roulette changes the image");
}

#[test]
fn sweep_frames_are_identical_at_one_and_three_threads() {
    let scene = small_scene(1);
    let sweep = |threads| {
        with_threads(threads, || {
            let prepared = prepare(&scene).unwrap();
            [-40.0, 25.0].map(|angle| bits(&prepared.render(angle)))
        })
    };
    assert_eq!(sweep(1), sweep(3));
}

#[test]
fn another_seed_grows_another_stone() {
    let a = bits(&opalray::render(&small_scene(1)).unwrap());
    let b = bits(&opalray::render(&small_scene(2)).unwrap());
    assert_ne!(a.1, b.1);
}

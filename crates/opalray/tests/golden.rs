//! Golden images: small renders compared with stored references, statistically.
//!
//! A reference may differ from a new render by floating-point detail, not by look: the mean
//! absolute difference must stay within 1 code value and 99 % of the channel values within 8.
//! On failure the actual, reference and (×8) difference images are written next to the test
//! binary's target directory and their paths printed. `OPALRAY_BLESS=1 cargo test --test
//! golden` rewrites the references (look at them before committing).

use std::path::{Path, PathBuf};

use opalray::scene::LightKind;
use opalray::Scene;

const MAX_MEAN_ABS: f64 = 1.0;
const MAX_P99: u8 = 8;

fn base() -> Scene {
    let mut s = Scene::default();
    s.render.width = 64;
    s.render.height = 48;
    s.spectrum.bins = 16;
    s.light.rays = 40_000;
    s
}

fn reference_dir() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/golden")
}

fn check(name: &str, scene: &Scene) {
    let frame = opalray::render(scene).unwrap();
    let actual = opalray::color::to_display_rgb8(&frame.rgb, &scene.color);
    let (w, h) = (scene.render.width, scene.render.height);
    let path = reference_dir().join(format!("{name}.png"));
    if std::env::var_os("OPALRAY_BLESS").is_some() {
        opalray::output::write_png_rgb8(&path, w, h, &actual).unwrap();
        return;
    }
    let reference = image::open(&path)
        .unwrap_or_else(|e| panic!("{}: {e}; run with OPALRAY_BLESS=1", path.display()))
        .to_rgb8();
    assert_eq!(reference.dimensions(), (w, h), "{name}: size");
    let mut diffs: Vec<u8> = actual
        .iter()
        .zip(reference.as_raw())
        .map(|(&a, &b)| a.abs_diff(b))
        .collect();
    let mean = diffs.iter().map(|&d| f64::from(d)).sum::<f64>() / diffs.len() as f64;
    let amplified: Vec<u8> = diffs.iter().map(|&d| d.saturating_mul(8)).collect();
    diffs.sort_unstable();
    let p99 = diffs[diffs.len() * 99 / 100];
    if mean > MAX_MEAN_ABS || p99 > MAX_P99 {
        let out = Path::new(env!("CARGO_TARGET_TMPDIR")).join("golden");
        std::fs::create_dir_all(&out).unwrap();
        let write = |suffix: &str, data: &[u8]| {
            let p = out.join(format!("{name}-{suffix}.png"));
            opalray::output::write_png_rgb8(&p, w, h, data).unwrap();
            p
        };
        let a = write("actual", &actual);
        let r = write("reference", reference.as_raw());
        let d = write("difference", &amplified);
        panic!(
            "{name}: mean |Δ| {mean:.2}, 99th percentile {p99} (limits {MAX_MEAN_ABS}, {MAX_P99})\n\
             actual {}\nreference {}\ndifference ×8 {}",
            a.display(),
            r.display(),
            d.display()
        );
    }
}

#[test]
fn golden_default_light_at_30_degrees() {
    check("default-30", &base());
}

#[test]
fn golden_white_body_light_at_minus_45_degrees() {
    let mut s = base();
    s.light.angle_deg = -45.0;
    s.render.body_tone = 8;
    check("white-body-minus-45", &s);
}

#[test]
fn golden_point_light() {
    let mut s = base();
    s.light.kind = LightKind::Point;
    s.light.distance_mm = 60.0;
    s.light.angle_deg = 20.0;
    check("point-light-20", &s);
}

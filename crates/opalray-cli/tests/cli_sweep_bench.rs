//! `opalray sweep` and `opalray bench` as a user runs them: a contact sheet and animations
//! that open with their frames, and the bench's medians as JSON.

mod common;

use common::{args, opalray, stderr};

#[test]
fn sweep_writes_a_sheet_and_animations() {
    let dir = tempfile::tempdir().unwrap();
    let small = [
        "--preset", "paper", "--frames", "3", "--width", "48", "--height", "36", "--bins", "16",
        "--rays", "10000",
    ];
    let out = opalray(
        dir.path(),
        &args(
            &["sweep", "--sheet", "s.png", "--animation", "a.gif"],
            &small,
        ),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let sheet = image::open(dir.path().join("s.png")).unwrap();
    assert!(sheet.width() > 3 * 48 && sheet.height() > 36);
    use image::AnimationDecoder;
    let gif = std::io::BufReader::new(std::fs::File::open(dir.path().join("a.gif")).unwrap());
    let frames = image::codecs::gif::GifDecoder::new(gif)
        .unwrap()
        .into_frames();
    assert_eq!(frames.count(), 3);
    let out = opalray(
        dir.path(),
        &args(
            &["sweep", "--sheet", "t.png", "--animation", "a.png"],
            &small,
        ),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let apng = std::fs::read(dir.path().join("a.png")).unwrap();
    let actl = apng
        .windows(4)
        .position(|w| w == b"acTL")
        .expect("an APNG acTL chunk");
    let frames = u32::from_be_bytes(apng[actl + 4..actl + 8].try_into().unwrap());
    assert_eq!(frames, 3);
}

#[test]
fn bench_prints_json_medians() {
    let dir = tempfile::tempdir().unwrap();
    let out = opalray(
        dir.path(),
        &[
            "bench", "--preset", "paper", "--runs", "1", "--json", "--width", "32", "--height",
            "24", "--rays", "5000",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let v: serde_json::Value = serde_json::from_slice(&out.stdout).unwrap();
    for stage in [
        "structure",
        "optics",
        "light_pass",
        "view_pass",
        "color",
        "total",
    ] {
        let median = v["median_s"][stage].as_f64().expect("median_s");
        let fastest = v["min_s"][stage].as_f64().expect("min_s");
        assert!(
            fastest <= median && fastest >= 0.0,
            "{stage}: {fastest} > {median}"
        );
    }
    // Linux reports the processor time stolen by a hypervisor: a share, or null elsewhere.
    let stolen = &v["cpu_stolen_fraction"];
    match stolen.as_f64() {
        Some(share) => assert!((0.0..=1.0).contains(&share), "{share}"),
        None => assert!(
            stolen.is_null() && !cfg!(target_os = "linux"),
            "cpu_stolen_fraction: {stolen}"
        ),
    }
}

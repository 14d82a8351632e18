//! `opalray color` as a user runs it: JSON for emission and reflectance spectra, and one-line
//! errors with exit code 2 for every kind of bad input.

mod common;

use common::opalray;

/// Run `opalray color` on a CSV with `text` and return the parsed JSON.
fn color_json(text: &str, extra: &[&str]) -> serde_json::Value {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.csv"), text).unwrap();
    let mut args = vec!["color", "s.csv"];
    args.extend_from_slice(extra);
    let out = opalray(dir.path(), &args);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_slice(&out.stdout).expect("stdout is JSON")
}

fn xy(v: &serde_json::Value) -> (f64, f64) {
    (v["xy"][0].as_f64().unwrap(), v["xy"][1].as_f64().unwrap())
}

#[test]
fn equal_energy_emission_is_one_third_and_near_white() {
    // Equal energy over the CMF table's range: (1/3, 1/3) (CIE 15:2004 §3.1), a slightly
    // pink white on a D65 display (E lies towards red from D65).
    let v = color_json("wavelength_nm,value\n360,1\n830,1\n", &[]);
    let (x, y) = xy(&v);
    assert!(
        (x - 1.0 / 3.0).abs() < 1e-4 && (y - 1.0 / 3.0).abs() < 1e-4,
        "{v}"
    );
    assert_eq!(v["mode"], "emission");
    let codes: Vec<u64> = (0..3).map(|i| v["srgb8"][i].as_u64().unwrap()).collect();
    assert_eq!(codes[0], 255, "{v}");
    assert!(
        codes[1] > 215 && codes[2] > 215 && codes[2] <= codes[1],
        "{v}"
    );
}

#[test]
fn line_at_700_nm_is_on_the_spectral_locus_and_red() {
    // CIE 1931 spectral locus at 700 nm: (0.73469, 0.26531) (CIE 15:2004 Table T.4).
    let v = color_json("699.9,0\n700,1\n700.1,0\n", &[]);
    let (x, y) = xy(&v);
    assert!(
        (x - 0.73469).abs() < 1e-4 && (y - 0.26531).abs() < 1e-4,
        "{v}"
    );
    assert_eq!(v["in_gamut"], false);
    // Its dominant wavelength leaves the sRGB gamut on the red–blue edge (700 nm lies below
    // the red primary's y = 0.33): full red, no green, a little blue — saturated, not bleached.
    let codes: Vec<u64> = (0..3).map(|i| v["srgb8"][i].as_u64().unwrap()).collect();
    assert_eq!(codes[..2], [255, 0], "{v}");
    assert!(codes[2] < 100, "{v}");
}

#[test]
fn white_reflectance_is_white_under_every_illuminant() {
    for illuminant in ["D65", "A", "C", "E"] {
        let v = color_json(
            "300,1\n900,1\n",
            &["--reflectance", "--illuminant", illuminant],
        );
        assert_eq!(v["hex"], "#ffffff", "{illuminant}: {v}");
        assert!((v["xyz"][1].as_f64().unwrap() - 1.0).abs() < 1e-6);
        assert_eq!(v["illuminant"], illuminant);
    }
}

#[test]
fn white_reflectance_under_d65_has_the_d65_chromaticity() {
    // D65 (0.31272, 0.32903), CIE 15:2004 Table T.3.
    let v = color_json("300,1\n900,1\n", &["--reflectance"]);
    let (x, y) = xy(&v);
    assert!(
        (x - 0.31272).abs() < 2e-5 && (y - 0.32903).abs() < 2e-5,
        "{v}"
    );
}

#[test]
fn bad_input_is_one_line_naming_the_file_and_exit_code_2() {
    let dir = tempfile::tempdir().unwrap();
    let cases = [
        ("empty.csv", "", "empty.csv: found 0 data rows"),
        (
            "down.csv",
            "500,1\n400,1\n",
            "down.csv: line 2: wavelength 400 nm",
        ),
        (
            "nan.csv",
            "400,1\n500,nan\n",
            "nan.csv: line 2: value `nan`",
        ),
        (
            "text.csv",
            "400,1\n500,bright\n",
            "text.csv: line 2: value `bright`",
        ),
        ("cols.csv", "400;1\n500;1\n", "cols.csv: line 1: expected 2"),
        (
            "one.csv",
            "# x\nwavelength_nm,value\n550,1\n",
            "one.csv: found 1 data rows",
        ),
    ];
    for (name, text, expected) in cases {
        std::fs::write(dir.path().join(name), text).unwrap();
        let out = opalray(dir.path(), &["color", name]);
        let err = String::from_utf8_lossy(&out.stderr);
        assert_eq!(out.status.code(), Some(2), "{name}: {err}");
        assert!(err.contains(expected), "{name}: {err}");
        assert_eq!(err.trim().lines().count(), 1, "{name}: {err}");
        assert!(out.stdout.is_empty(), "{name}");
    }
    let out = opalray(dir.path(), &["color", "missing.csv"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2));
    assert!(err.contains("missing.csv"), "{err}");
    assert_eq!(err.trim().lines().count(), 1, "{err}");
}

#[test]
fn illuminant_without_reflectance_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("s.csv"), "400,1\n500,1\n").unwrap();
    let out = opalray(dir.path(), &["color", "s.csv", "--illuminant", "A"]);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2));
    assert!(err.contains("--reflectance"), "{err}");
}

//! `opalray spectrum` end to end: the printed peaks, the CSV, and refusals of bad input.

use std::path::Path;
use std::process::{Command, Output};

fn opalray(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_opalray"))
        .arg("spectrum")
        .args(args)
        .output()
        .expect("the opalray binary runs")
}

/// `(angle, peak nm, peak R, Bragg–Snell nm)` of each row of the printed table.
fn peaks(stdout: &str) -> Vec<(f64, f64, f64, f64)> {
    stdout
        .lines()
        .filter(|l| l.contains('°'))
        .map(|l| {
            let v: Vec<f64> = l
                .split_whitespace()
                .filter_map(|w| w.trim_end_matches('°').parse().ok())
                .collect();
            (v[0], v[2], v[3], v[4])
        })
        .collect()
}

#[test]
fn default_run_prints_peaks_on_the_bragg_snell_law() {
    // DESIGN §4: D = 250 nm flashes orange (~590 nm) face-on and shifts to blue when tilted;
    // λ = 2 d √(n_eff² − sin² θ₀).
    let out = opalray(&[]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8(out.stdout).unwrap();
    let rows = peaks(&stdout);
    assert_eq!(rows.len(), 3, "{stdout}");
    assert_eq!(
        rows.iter().map(|r| r.0).collect::<Vec<_>>(),
        [0.0, 30.0, 60.0]
    );
    for &(angle, peak_nm, peak_r, bragg_nm) in &rows {
        assert!(
            (peak_nm - bragg_nm).abs() < 0.005 * bragg_nm,
            "{angle}°: {stdout}"
        );
        assert!(peak_r > 0.5 && peak_r <= 1.0, "{angle}°: {stdout}");
    }
    assert!((rows[0].1 - 590.0).abs() < 5.0, "{stdout}");
    assert!(rows[0].1 > rows[1].1 && rows[1].1 > rows[2].1, "{stdout}");
}

#[test]
fn csv_has_the_documented_columns_and_samples() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.csv");
    let out = opalray(&[
        "--angles",
        "0,45",
        "--inside",
        "--from-nm",
        "500",
        "--to-nm",
        "600",
        "--step-nm",
        "0.25",
        "--output",
        path.to_str().unwrap(),
    ]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let text = std::fs::read_to_string(&path).unwrap();
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("wavelength_nm,angle_deg,reflectance,transmittance")
    );
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 2 * 401);
    assert_eq!(
        (rows[0][0], rows[400][0], rows[401][1]),
        (500.0, 600.0, 45.0)
    );
    for row in &rows {
        let (r, t) = (row[2], row[3]);
        assert!((0.0..=1.0).contains(&r) && (0.0..=1.0).contains(&t));
        assert!((r + t - 1.0).abs() < 1e-9, "R + T = {}", r + t);
    }
    // Face-on the CSV's brightest sample is the printed peak.
    let best = rows[..401]
        .iter()
        .max_by(|a, b| a[2].total_cmp(&b[2]))
        .unwrap();
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!((best[0] - peaks(&stdout)[0].1).abs() < 1e-9, "{stdout}");
}

#[test]
fn inside_angles_skip_the_refraction() {
    // At 30° inside, λ = 2 d n_eff cos 30°, bluer than 30° in air (20.3° inside).
    let air = peaks(&String::from_utf8(opalray(&["--angles", "30"]).stdout).unwrap());
    let inside =
        peaks(&String::from_utf8(opalray(&["--angles", "30", "--inside"]).stdout).unwrap());
    let face_on = peaks(&String::from_utf8(opalray(&["--angles", "0"]).stdout).unwrap());
    let expect = face_on[0].3 * 30f64.to_radians().cos();
    assert!(
        (inside[0].3 - expect).abs() < 1e-2,
        "{inside:?} vs {expect}"
    );
    assert!(inside[0].1 < air[0].1);
}

fn assert_refused(args: &[&str], flag: &str, output: &Path) {
    let out = opalray(args);
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{args:?}: {stderr}");
    assert!(stderr.contains(flag), "{args:?}: {stderr}");
    assert_eq!(stderr.trim_end().lines().count(), 1, "one line: {stderr}");
    assert!(!output.exists(), "{args:?} wrote {}", output.display());
}

#[test]
fn bad_input_is_refused_with_the_flag_and_no_file() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.csv");
    let csv = path.to_str().unwrap();
    for (bad, flag) in [
        (&["--diameter", "-250"][..], "--diameter"),
        (&["--diameter", "nan"], "--diameter"),
        (&["--n-sphere", "0.9"], "--n-sphere"),
        (&["--n-matrix", "0.5"], "--n-matrix"),
        (&["--n-matrix", "NaN"], "--n-matrix"),
        (&["--layers", "0"], "--layers"),
        (&["--layers", "-3"], "--layers"),
        (&["--angles", "90"], "--angles"),
        (&["--angles", "0,nan"], "--angles"),
        (&["--angles", "-10"], "--angles"),
        (&["--step-nm", "0"], "--step-nm"),
        (&["--step-nm", "-0.5"], "--step-nm"),
        (&["--step-nm", "1e-9"], "--step-nm"),
        (&["--from-nm", "700", "--to-nm", "500"], "--to-nm"),
        (&["--from-nm", "-5"], "--from-nm"),
    ] {
        let args: Vec<&str> = bad.iter().copied().chain(["--output", csv]).collect();
        assert_refused(&args, flag, &path);
    }
}

#[test]
fn unwritable_output_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let missing = dir.path().join("no/such/dir/s.csv");
    assert_refused(
        &["--output", missing.to_str().unwrap()],
        "--output",
        &missing,
    );
    let png = dir.path().join("s.png");
    assert_refused(&["--output", png.to_str().unwrap()], "--output", &png);
}

#[test]
fn help_names_every_flag() {
    let out = opalray(&["--help"]);
    let help = String::from_utf8(out.stdout).unwrap();
    for flag in [
        "--diameter",
        "--n-sphere",
        "--n-matrix",
        "--layers",
        "--angles",
        "--inside",
        "--from-nm",
        "--to-nm",
        "--step-nm",
        "--output",
        "Bragg",
    ] {
        assert!(help.contains(flag), "{flag} missing from:\n{help}");
    }
}

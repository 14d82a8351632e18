//! `opalray spectrum` end to end: the printed peaks and colours, the CSV, the plot, and
//! refusals of bad input.

use std::path::Path;
use std::process::{Command, Output};

use opalray::color::SpectrumColor;
use opalray::scene::Illuminant;

/// The plot's layout, as documented in `opalray spectrum --help` and `spectrum/plot.rs`:
/// a 904 × 432 image whose 800 × 360 data area starts at (80, 12), wavelength across and
/// angle up from 0° (bottom row) to the largest angle (top row).
const PLOT_SIZE: (u32, u32) = (904, 432);
const DATA_LEFT: u32 = 80;
const DATA_TOP: u32 = 12;
const DATA_COLUMNS: u32 = 800;
const DATA_ROWS: u32 = 360;

fn opalray(args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_opalray"))
        .arg("spectrum")
        .args(args)
        .output()
        .expect("the opalray binary runs")
}

/// The `#rrggbb` colour of each row of the printed table, as 8-bit codes.
fn hex_colours(stdout: &str) -> Vec<(String, [u8; 3])> {
    stdout
        .lines()
        .filter(|l| l.contains('°'))
        .map(|l| {
            let hex = l
                .split_whitespace()
                .find(|w| w.starts_with('#'))
                .unwrap_or_else(|| panic!("no #rrggbb in {l:?}"));
            assert_eq!(hex.len(), 7, "{hex}");
            let code = |i: usize| u8::from_str_radix(&hex[i..i + 2], 16).unwrap();
            (hex.to_string(), [code(1), code(3), code(5)])
        })
        .collect()
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

#[test]
fn silica_dispersion_moves_the_face_on_peak_by_the_fixed_points_shift() {
    // docs/model.md's table (scripts/dispersion.py, Malitson's law in Python): the face-on
    // (111) line of D = 350 nm moves from 824.32 to 821.21 nm (−3.11 nm), of D = 200 nm from
    // 471.04 to 472.85 nm (+1.81 nm). The scan's peak (0.01 nm step) moves by as much, and
    // the Bragg–Snell column names the new centre.
    for (diameter, from, to, constant, silica) in [
        ("350", "810", "835", 824.32, 821.21),
        ("200", "462", "480", 471.04, 472.85),
    ] {
        let run = |law: &str| {
            let out = opalray(&[
                "--diameter",
                diameter,
                "--angles",
                "0",
                "--from-nm",
                from,
                "--to-nm",
                to,
                "--step-nm",
                "0.01",
                "--dispersion",
                law,
            ]);
            let stdout = String::from_utf8_lossy(&out.stdout).into_owned();
            assert!(
                out.status.success(),
                "{}",
                String::from_utf8_lossy(&out.stderr)
            );
            assert!(stdout.contains(&format!("dispersion {law}")), "{stdout}");
            peaks(&stdout)[0]
        };
        let (none, with) = (run("none"), run("silica"));
        let shift = with.1 - none.1;
        assert!(
            (shift - (silica - constant)).abs() < 0.025,
            "D {diameter}: {none:?} → {with:?}"
        );
        assert!((none.3 - constant).abs() < 0.006, "D {diameter}: {none:?}");
        assert!((with.3 - silica).abs() < 0.006, "D {diameter}: {with:?}");
    }
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
        (&["--dispersion", "glass"], "--dispersion"),
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
        "--plot",
        "--dispersion",
        "Bragg",
    ] {
        assert!(help.contains(flag), "{flag} missing from:\n{help}");
    }
}

#[test]
fn hex_is_the_d65_colour_of_each_angles_curve() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("s.csv");
    let out = opalray(&["--step-nm", "0.5", "--output", path.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8(out.stdout).unwrap();
    let printed = hex_colours(&stdout);
    assert_eq!(printed.len(), 3, "{stdout}");
    // Each angle's curve from the CSV, as a reflectance lit by D65.
    let text = std::fs::read_to_string(&path).unwrap();
    for ((hex, _), angle) in printed.iter().zip(["0", "30", "60"]) {
        let curve: Vec<(f64, f64)> = text
            .lines()
            .skip(1)
            .map(|l| l.split(',').collect::<Vec<_>>())
            .filter(|v| v[1] == angle)
            .map(|v| (v[0].parse().unwrap(), v[2].parse().unwrap()))
            .collect();
        assert_eq!(curve.len(), 801);
        let expect = SpectrumColor::of_reflectance(&curve, Illuminant::D65).hex();
        assert_eq!(hex, &expect, "{angle}°: {stdout}");
    }
    // Hue: the 589 nm line face-on is orange (red > green > blue), the 552 nm line at 30° is
    // green, the 471 nm line at 60° blue (CIE 1931 dominant wavelengths of sRGB hues).
    let [r, g, b] = printed[0].1;
    assert!(r > g && g > b, "0°: {stdout}");
    let [r, g, b] = printed[1].1;
    assert!(g > r && g > b, "30°: {stdout}");
    let [r, g, b] = printed[2].1;
    assert!(b > r && b > g, "60°: {stdout}");
}

/// Wavelength (nm) at the centre of the brightest data column of image row `y`, and that
/// pixel; brightness is the sum of the 8-bit codes.
fn brightest_in_row(img: &image::RgbImage, y: u32, from_nm: f64, to_nm: f64) -> (f64, [u8; 3]) {
    let (x, px) = (DATA_LEFT..DATA_LEFT + DATA_COLUMNS)
        .map(|x| (x, img.get_pixel(x, y).0))
        .max_by_key(|(_, p)| p.iter().map(|&c| u32::from(c)).sum::<u32>())
        .unwrap();
    let column_nm = (to_nm - from_nm) / f64::from(DATA_COLUMNS);
    (from_nm + (f64::from(x - DATA_LEFT) + 0.5) * column_nm, px)
}

#[test]
fn plot_shows_the_band_bending_to_blue_with_angle() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("plot.png");
    let out = opalray(&["--angles", "0,60", "--plot", path.to_str().unwrap()]);
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    let stdout = String::from_utf8(out.stdout).unwrap();
    assert!(stdout.contains("904 × 432 px"), "{stdout}");
    let img = image::open(&path).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), PLOT_SIZE);
    // Bragg–Snell in air, λ = 2 d111 √(n_eff² − sin²θ₀) with d111 = 204.12 nm and
    // n_eff = 1.4423 (printed above): 588.8 nm at 0°, 470.8 nm at 60°. A column is 0.5 nm.
    let bottom = DATA_TOP + DATA_ROWS - 1;
    let (face_on_nm, face_on) = brightest_in_row(&img, bottom, 380.0, 780.0);
    let (tilted_nm, tilted) = brightest_in_row(&img, DATA_TOP, 380.0, 780.0);
    assert!((face_on_nm - 588.8).abs() < 1.5, "0°: {face_on_nm} nm");
    assert!((tilted_nm - 470.8).abs() < 1.5, "60°: {tilted_nm} nm");
    // Drawn in the colour of the wavelength: orange face-on, blue at 60°.
    assert!(
        face_on[0] > face_on[1] && face_on[1] > face_on[2],
        "{face_on:?}"
    );
    assert!(tilted[2] > tilted[0] && tilted[2] > tilted[1], "{tilted:?}");
    // The band moves monotonically to the blue row by row (every 10 rows, 1.67°).
    let mut last = f64::INFINITY;
    for y in (DATA_TOP..=bottom).rev().step_by(10) {
        let (nm, _) = brightest_in_row(&img, y, 380.0, 780.0);
        assert!(nm <= last + 0.5, "row {y}: {nm} nm after {last} nm");
        last = nm;
    }
    // Far from the band the plot is dark.
    assert_eq!(img.get_pixel(DATA_LEFT + 700, bottom).0, [0, 0, 0]);
}

#[test]
fn plot_columns_follow_the_wavelength_range() {
    // 560–620 nm over 800 columns: 0.075 nm each; the face-on line still lands at 588.8 nm.
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("zoom.png");
    let out = opalray(&[
        "--angles",
        "0",
        "--from-nm",
        "560",
        "--to-nm",
        "620",
        "--plot",
        path.to_str().unwrap(),
    ]);
    assert!(out.status.success());
    let img = image::open(&path).unwrap().to_rgb8();
    assert_eq!(img.dimensions(), PLOT_SIZE);
    let (nm, _) = brightest_in_row(&img, DATA_TOP + DATA_ROWS - 1, 560.0, 620.0);
    // Inside the stop band 587.72–589.88 nm printed for this crystal.
    assert!((587.7..=589.9).contains(&nm), "{nm} nm");
}

#[test]
fn bad_plot_paths_are_refused_before_any_work() {
    let dir = tempfile::tempdir().unwrap();
    for name in ["p.csv", "p.txt", "p", "no/such/dir/p.png"] {
        let path = dir.path().join(name);
        assert_refused(&["--plot", path.to_str().unwrap()], "--plot", &path);
    }
    // Bad crystal flags are refused before the plot is drawn.
    let png = dir.path().join("p.png");
    assert_refused(
        &["--diameter", "-250", "--plot", png.to_str().unwrap()],
        "--diameter",
        &png,
    );
    assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
}

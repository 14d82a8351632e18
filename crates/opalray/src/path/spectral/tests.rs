//! Tests of the path's spectrum: its draws, reflections, notches and deposits.

use super::*;
use crate::scene::Illuminant;
use crate::spectrum::WavelengthGrid;

#[test]
fn a_white_path_adds_the_lights_white() {
    let s = SpectralSampler::new(Illuminant::D65, &WavelengthGrid::default(), 4);
    let (mut xyz, mut bins) = ([0.0; 3], vec![0.0; 40]);
    s.add_path(&PathSpectrum::default(), 2.0, &mut xyz, &mut bins);
    assert!((xyz[1] - 2.0).abs() < 1e-9);
}

#[test]
fn a_white_path_loses_the_notches_it_passed() {
    // Independent: 1 − ∫ R S ȳ by brute force, for a path that passed a line and has not
    // been reflected: the light its line reflects is not in the light going on.
    let s = SpectralSampler::new(Illuminant::D65, &WavelengthGrid::default(), 4);
    let line = BraggLine::new(0.0037, 589.0, 1.0, 400.0);
    let mut passed = PathSpectrum::default();
    passed.transmit(line, &s);
    let (mut xyz, mut bins) = ([0.0; 3], vec![0.0; 40]);
    s.add_path(&passed, 2.0, &mut xyz, &mut bins);
    let expected = 2.0 * (1.0 - brute_y(&s, |w| reflectance_within(&line, line.window_nm(), w)));
    assert!(xyz[1] < 1.999, "the notch takes light: {}", xyz[1]);
    assert!((xyz[1] - expected).abs() < 1e-4, "{} vs {expected}", xyz[1]);
}

/// The mean over `n` stratification offsets of `add_path`'s Y for the path `build` makes
/// with the offset it is given.
fn mean_y(s: &SpectralSampler, n: usize, build: impl Fn(f64) -> PathSpectrum) -> f64 {
    (0..n)
        .map(|k| {
            let path = build((k as f64 + 0.5) / n as f64);
            let (mut xyz, mut bins) = ([0.0; 3], vec![0.0; 40]);
            s.add_path(&path, 1.0, &mut xyz, &mut bins);
            xyz[1] / n as f64
        })
        .sum()
}

/// `∫ f(λ) S(λ) ȳ(λ) dλ` by the midpoint rule at 0.002 nm.
fn brute_y(s: &SpectralSampler, f: impl Fn(f64) -> f64) -> f64 {
    let step = 0.002;
    (0..200_000)
        .map(|i| {
            let w = 380.0 + (i as f64 + 0.5) * step;
            f(w) * f64::from(s.at(w)[1]) * step
        })
        .sum()
}

#[test]
fn a_reflected_line_is_integrated_without_bias() {
    // Independent: brute-force quadrature of R(λ)·S·ȳ.
    let s = SpectralSampler::new(Illuminant::E, &WavelengthGrid::default(), 8);
    let line = BraggLine::new(0.0037, 589.0, 1.0, 400.0);
    let brute = brute_y(&s, |w| reflectance_within(&line, line.window_nm(), w));
    let mean = mean_y(&s, 4000, |u| {
        let mut path = PathSpectrum::default();
        path.reflect(line, &s, u);
        path
    });
    assert!((mean / brute - 1.0).abs() < 0.01, "{mean} vs {brute}");
}

#[test]
fn the_lines_around_a_reflection_multiply_it_at_every_wavelength() {
    // Independent: the product R · Π (1 − R) summed at 0.002 nm, for a path that passes a
    // notch and a thin stack's broad line before its reflection and a notch half a
    // line-width off after it.
    let s = SpectralSampler::new(Illuminant::D65, &WavelengthGrid::default(), 4);
    let line = BraggLine::new(0.0037, 589.0, 1.0, 400.0);
    let notch = BraggLine::new(0.0037, 590.0, 1.0, 300.0);
    let before = BraggLine::new(0.0037, 588.0, 1.0, 300.0);
    let broad = BraggLine::new(0.0037, 585.0, 1.0, 20.0);
    // A notch is 1 − R within its window, 1 outside ([`BraggLine::window_nm`]).
    let pass = |l: &BraggLine, w: f64| 1.0 - reflectance_within(l, l.window_nm(), w);
    let brute = brute_y(&s, |w| {
        reflectance_within(&line, line.window_nm(), w)
            * pass(&before, w)
            * pass(&broad, w)
            * pass(&notch, w)
    });
    let mean = mean_y(&s, 4000, |u| {
        let mut path = PathSpectrum::default();
        path.transmit(before, &s);
        path.transmit(broad, &s);
        path.reflect(line, &s, u);
        path.transmit(notch, &s);
        path
    });
    assert!((mean / brute - 1.0).abs() < 0.01, "{mean} vs {brute}");
}

#[test]
fn a_path_keeps_every_line_it_passes_after_its_reflection() {
    // A reflected path passing 60 alike plates (a settled bar seen edge-on) carries
    // (1 − R)⁶⁰ of them: its light falls to the line's wings. Independent: brute force.
    // A list of the lines met, held to a fixed length, would drop the later notches.
    let s = SpectralSampler::new(Illuminant::E, &WavelengthGrid::default(), 8);
    let line = BraggLine::new(0.0037, 589.0, 1.0, 400.0);
    let plate = BraggLine::new(0.0037, 589.3, 1.0, 200.0);
    let plates = 60;
    let window = plate.window_nm();
    let within = |w: f64| reflectance_within(&line, line.window_nm(), w);
    let brute = brute_y(&s, |w| {
        within(w) * (1.0 - reflectance_within(&plate, window, w)).powi(plates)
    });
    let alone = brute_y(&s, within);
    assert!(brute < 0.5 * alone, "the plates matter: {brute} vs {alone}");
    let mean = mean_y(&s, 4000, |u| {
        let mut path = PathSpectrum::default();
        path.reflect(line, &s, u);
        for _ in 0..plates {
            path.transmit(plate, &s);
        }
        path
    });
    assert!((mean / brute - 1.0).abs() < 0.02, "{mean} vs {brute}");
}

#[test]
fn a_lines_share_of_a_reflected_paths_light_is_what_it_reflects_there() {
    // Independent: ∫ R² S / ∫ R S by brute force (E: S flat), for the line itself and for
    // one 30 half-widths away, whose share is about nothing.
    let s = SpectralSampler::new(Illuminant::E, &WavelengthGrid::default(), 64);
    let line = BraggLine::new(0.0037, 589.0, 1.0, 400.0);
    let far = BraggLine::new(0.0037, 589.0 + 30.0 * line.half_width_nm(), 1.0, 400.0);
    let step = 0.002;
    let (mut r1, mut r2) = (0.0, 0.0);
    for i in 0..200_000 {
        let r = line.reflectance(380.0 + (f64::from(i) + 0.5) * step);
        r1 += r;
        r2 += r * r;
    }
    let share_of =
        |path: &PathSpectrum, l: &BraggLine| path.reflectances(l, &mut [[0.0; 2]; MAX_DRAWS]);
    let mut path = PathSpectrum::default();
    path.reflect(line, &s, 0.5);
    let share = share_of(&path, &line);
    assert!(
        (share / (r2 / r1) - 1.0).abs() < 0.05,
        "{share} vs {}",
        r2 / r1
    );
    assert!(share_of(&path, &far) < 0.01 * share);
    assert_eq!(share_of(&PathSpectrum::default(), &line), 0.0);
}

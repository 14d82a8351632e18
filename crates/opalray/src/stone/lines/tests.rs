//! Tests of the stone's lines.

use super::*;
use crate::sampling::{stage, Rng};
use crate::stone::tests::grains_scene;

#[test]
fn face_on_111_line_of_a_250_nm_domain_is_at_588_8_nm() {
    let mut scene = grains_scene();
    scene.domains.sphere_diameter_spread = 0.0;
    let stone = Stone::new(&scene).unwrap();
    let dm = stone.domains[0];
    let n111 = dm.orientation * Vec3::splat(1.0).normalize();
    let mut lines = Vec::new();
    stone.lines(0, -n111, 1.0, &mut lines);
    let face_on = lines
        .iter()
        .find(|l| l.kind == 0 && l.line.center_nm > 580.0)
        .unwrap();
    // DESIGN §4: 588.8 nm for D = 250 nm in cement 1.42.
    assert!(
        (face_on.line.center_nm - 588.8).abs() < 0.2,
        "{}",
        face_on.line.center_nm
    );
    assert!(face_on.normal.dot(-n111) < 0.0);
}

#[test]
fn a_corner_chord_meets_few_layers() {
    let stone = Stone::new(&grains_scene()).unwrap();
    let n = stone.domains[0].orientation * Vec3::splat(1.0).normalize();
    let (mut thick, mut thin) = (Vec::new(), Vec::new());
    stone.lines(0, -n, 1.0, &mut thick);
    stone.lines(0, -n, 0.004, &mut thin);
    let peak = |v: &Vec<ActiveLine>| v.iter().map(|l| l.line.peak()).fold(0.0, f64::max);
    assert!(
        peak(&thick) > 0.9 && peak(&thin) < 0.2,
        "{} {}",
        peak(&thick),
        peak(&thin)
    );
}

#[test]
fn lines_at_a_wavelength_are_the_lines_whose_window_holds_it() {
    // The default stone (all families), with silica's dispersion and without: random
    // domains, directions and chords (corner chords of a few layers to a colour bar's
    // width), at the centres of the lines met and at wavelengths over the range, against
    // `lines` filtered by the window.
    let mut scene = crate::scene::preset("black-opal").unwrap();
    assert!(scene.crystal.dispersion == crate::scene::Dispersion::Silica);
    lines_at_agree(&Stone::new(&scene).unwrap());
    scene.crystal.dispersion = crate::scene::Dispersion::None;
    lines_at_agree(&Stone::new(&scene).unwrap());
}

fn lines_at_agree(stone: &Stone) {
    let mut rng = Rng::new(11, stage::STONE, 96);
    let (mut kept, mut checked) = (0, 0);
    let (mut all, mut at) = (Vec::new(), Vec::new());
    for _ in 0..4000 {
        let domain = (rng.uniform_f32() * stone.domains.len() as f32) as u32;
        let domain = domain.min(stone.domains.len() as u32 - 1);
        let dir = Vec3::new(
            rng.uniform_f32() - 0.5,
            rng.uniform_f32() - 0.5,
            rng.uniform_f32() - 0.5,
        )
        .normalize();
        let chord_mm = 10f32.powf(-3.0 + 3.5 * rng.uniform_f32());
        all.clear();
        stone.lines(domain, dir, chord_mm, &mut all);
        let mut wavelengths: Vec<f64> = all.iter().map(|l| l.line.center_nm).collect();
        wavelengths.extend((0..4).map(|_| 350.0 + 450.0 * rng.uniform()));
        for w in wavelengths {
            let expected: Vec<ActiveLine> = all
                .iter()
                .filter(|l| {
                    let (lo, hi) = l.line.window_nm();
                    !(w <= lo || w >= hi)
                })
                .copied()
                .collect();
            at.clear();
            stone.lines_at(domain, dir, chord_mm, w, &mut at);
            assert_eq!(
                at, expected,
                "domain {domain}, {dir}, {chord_mm} mm, {w} nm"
            );
            kept += expected.len();
            checked += 1;
        }
    }
    assert!(kept > checked, "{kept} lines kept at {checked} wavelengths");
}

//! Tests of the stone as a whole: the settled orientations its layout gives its grains.

use super::*;
use crate::scene::{OrientationLaw, Pattern};
use crate::structure::AXIS_111;

/// The default scene with its domains as grains.
pub(crate) fn grains_scene() -> Scene {
    let mut scene = Scene::default();
    scene.domains.pattern = Pattern::Grains;
    scene
}

#[test]
fn settled_layers_tilt_from_the_face_by_the_spread_in_every_direction() {
    let mut scene = grains_scene();
    scene.domains.orientation = OrientationLaw::Settled;
    scene.domains.orientation_spread_deg = 15.0;
    scene.domains.void_fraction = 0.0;
    scene.domains.grain_size_mm = 0.8;
    let stone = Stone::new(&scene).unwrap();
    let n = stone.domains.len() as f64;
    assert!(n > 2000.0, "{n} grains");
    let (mut tilt2, mut sx, mut sy, mut spin) = (0.0f64, 0.0f64, 0.0f64, 0.0f64);
    for dm in &stone.domains {
        let layers = dm.orientation * AXIS_111;
        let tilt = f64::from(layers.z.clamp(-1.0, 1.0)).acos();
        tilt2 += tilt * tilt;
        sx += f64::from(layers.x);
        sy += f64::from(layers.y);
        // Another {111} family's normal, projected on the face: its azimuth is uniform.
        let other = dm.orientation * Vec3::new(1.0, -1.0, -1.0).normalize();
        spin += f64::from(other.y.atan2(other.x).cos());
    }
    let rms = (tilt2 / n).sqrt().to_degrees();
    assert!((rms - 15.0).abs() < 0.6, "RMS tilt {rms}°");
    // No preferred direction of tilt, nor of the lattice's turn about the layers' normal
    // (each mean of a unit-variance-ish cosine within 4 standard errors of 0).
    let bound = 4.0 / n.sqrt();
    assert!(
        (sx / n).abs() < bound && (sy / n).abs() < bound,
        "{sx} {sy}"
    );
    assert!((spin / n).abs() < 4.0 * (0.5 / n).sqrt(), "{spin}");
}

/// Settled grains of 0.8 mm, no potch, with tilt fields of `length` mm and `jitter`°:
/// each grain's seed (mm) and its layers' tilt vector (radians, towards its direction by
/// its angle from z) and another {111} family's azimuth on the face.
fn settled_tilts(length: f64, jitter: f64, seed: u64) -> Vec<(Vec3, [f64; 2], f64)> {
    let mut scene = grains_scene();
    scene.structure.seed = seed;
    scene.domains.orientation = OrientationLaw::Settled;
    scene.domains.orientation_spread_deg = 20.0;
    scene.domains.tilt_correlation_mm = length;
    scene.domains.tilt_jitter_deg = jitter;
    scene.domains.void_fraction = 0.0;
    scene.domains.grain_size_mm = 0.8;
    let stone = Stone::new(&scene).unwrap();
    let Layout::Grains {
        grains, domain_of, ..
    } = &stone.layout
    else {
        panic!("grains")
    };
    grains
        .seeds
        .iter()
        .zip(domain_of)
        .map(|(p, k)| {
            let q = stone.domains[k.unwrap() as usize].orientation;
            let n = q * AXIS_111;
            let tilt = f64::from(n.z.clamp(-1.0, 1.0)).acos();
            let across = f64::from(n.x.hypot(n.y)).max(1e-12);
            let other = q * Vec3::new(1.0, -1.0, -1.0).normalize();
            let t = [
                tilt * f64::from(n.x) / across,
                tilt * f64::from(n.y) / across,
            ];
            (*p, t, f64::from(other.y.atan2(other.x)))
        })
        .collect()
}

/// Mean of `|t_a − t_b|²` (deg²) over pairs of grains whose seeds lie in `range` (mm).
fn tilt_difference(grains: &[(Vec3, [f64; 2], f64)], range: std::ops::Range<f32>) -> f64 {
    let (mut sum, mut pairs) = (0.0, 0usize);
    for (i, a) in grains.iter().enumerate() {
        for b in &grains[i + 1..] {
            if range.contains(&a.0.distance(b.0)) {
                let d = [a.1[0] - b.1[0], a.1[1] - b.1[1]];
                sum += (d[0] * d[0] + d[1] * d[1]).to_degrees().to_degrees();
                pairs += 1;
            }
        }
    }
    assert!(pairs > 500, "{pairs} pairs");
    sum / pairs as f64
}

#[test]
fn tilt_fields_keep_the_spread_and_leave_near_grains_their_jitter() {
    // Fields far longer than the stone: two near grains differ by their own parts only,
    // E|t_a − t_b|² = 2 jitter² (two independent Gaussian vectors of RMS `jitter`).
    let long = settled_tilts(100.0, 4.0, 3);
    let near = tilt_difference(&long, 0.0..1.0);
    assert!((near / (2.0 * 16.0) - 1.0).abs() < 0.1, "{near} deg² near");
    // Fields much shorter than the grains: the tilts' RMS over the stone is the spread,
    // the lattice's turn uniform (another {111} family's azimuth: mean cosine 0).
    let short = settled_tilts(0.3, 4.0, 3);
    let n = short.len() as f64;
    let rms = (short
        .iter()
        .map(|g| g.1[0] * g.1[0] + g.1[1] * g.1[1])
        .sum::<f64>()
        / n)
        .sqrt()
        .to_degrees();
    assert!((rms - 20.0).abs() < 1.0, "RMS tilt {rms}° over {n} grains");
    let spin = short.iter().map(|g| g.2.cos()).sum::<f64>() / n;
    assert!(spin.abs() < 4.0 * (0.5 / n).sqrt(), "{spin}");
    // Fields of 3 mm: near grains alike, grains a stone apart as unlike as independent
    // ones (2 × 20² = 800 deg²); without fields near grains are as unlike as far ones.
    let mid = settled_tilts(3.0, 4.0, 3);
    let near = tilt_difference(&mid, 0.0..0.9);
    let far = tilt_difference(&mid, 12.0..30.0);
    assert!(near < 0.25 * far, "near {near}, far {far} deg²");
    assert!(far > 400.0, "far {far} deg²");
    let own = settled_tilts(0.0, 4.0, 3);
    let near = tilt_difference(&own, 0.0..0.9);
    assert!(
        (near / 800.0 - 1.0).abs() < 0.15,
        "{near} deg² near, own tilts"
    );
}

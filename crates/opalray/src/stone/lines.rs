//! The Bragg lines a ray meets crossing a domain: input a domain, a direction and the chord's
//! length → output the [`ActiveLine`] of every family slot whose first-order line falls in the
//! spectral range (`docs/model.md`, the lines and their widths), or only those whose window
//! holds one wavelength.
//!
//! Every crossing of every domain by the eye ray and by the reflections the lobe integrator
//! follows comes here, 25 slots a domain for all families: the per-slot constants are read
//! from one flat array, and a wavelength's test rejects a slot before the line is built.

use glam::Vec3;

use super::{ActiveLine, Stone, LINE_REACH};
use crate::optics::{BraggLine, Families};

/// What [`Stone::lines`] reads of one family slot (a normal of one family kind), the same for
/// every domain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(super) struct SlotOptics {
    /// The family kind (index into [`Families::kinds`]).
    pub kind: u8,
    /// The kind's plane spacing over the sphere diameter, `d / D`.
    pub spacing_over_diameter: f64,
    /// The kind's relative coupling `g`.
    pub coupling: f64,
    /// Coherent layers of the kind (the (111) `crystal.layers`, as a thickness).
    pub layer_cap: f64,
}

/// Every slot of `families` in order (kind by kind, each kind's normals in turn), for
/// `layers_111` coherent (111) layers.
pub(super) fn slot_optics(families: &Families, layers_111: f64) -> Vec<SlotOptics> {
    let d111 = families.kinds[0].spacing_over_diameter;
    families
        .kinds
        .iter()
        .enumerate()
        .flat_map(|(k, f)| {
            let slot = SlotOptics {
                kind: k as u8,
                spacing_over_diameter: f.spacing_over_diameter,
                coupling: f.coupling,
                layer_cap: layers_111 * d111 / f.spacing_over_diameter,
            };
            std::iter::repeat_n(slot, f.normals.len())
        })
        .collect()
}

impl Stone {
    /// The lines of domain `domain` that a ray along `dir` (unit) crossing it over `chord_mm`
    /// meets within the spectral range, pushed onto `out` in slot order.
    pub fn lines(&self, domain: u32, dir: Vec3, chord_mm: f32, out: &mut Vec<ActiveLine>) {
        self.push_lines(domain, dir, chord_mm, None, out);
    }

    /// The lines of [`Stone::lines`] whose window ([`BraggLine::window_nm`]) holds
    /// `wavelength_nm` (strictly inside it), pushed onto `out`: the same lines in the same
    /// order as filtering `lines`' output, at a fraction of its cost (most slots are rejected
    /// before their line is built).
    pub fn lines_at(
        &self,
        domain: u32,
        dir: Vec3,
        chord_mm: f32,
        wavelength_nm: f64,
        out: &mut Vec<ActiveLine>,
    ) {
        self.push_lines(domain, dir, chord_mm, Some(wavelength_nm), out);
    }

    /// [`Stone::lines`], keeping only the lines whose window holds `wavelength_nm` if given.
    #[inline(always)]
    fn push_lines(
        &self,
        domain: u32,
        dir: Vec3,
        chord_mm: f32,
        wavelength_nm: Option<f64>,
        out: &mut Vec<ActiveLine>,
    ) {
        let slots = &self.slot_optics;
        let normals = &self.normals[domain as usize * slots.len()..][..slots.len()];
        let diameter_nm = f64::from(self.domains[domain as usize].sphere_diameter_nm);
        let two_n = 2.0 * f64::from(self.n_eff) * diameter_nm;
        let chord_nm = f64::from(chord_mm) * 1e6;
        let (range_lo, range_hi) = self.range_nm;
        let (reach_lo, reach_hi) = (LINE_REACH * range_lo, 1.05 * range_hi);
        for (slot, &n) in slots.iter().zip(normals) {
            let dot = n.dot(dir);
            let c = f64::from(dot.abs());
            // 2 d n̄: the line's centre face-on.
            let normal_center_nm = two_n * slot.spacing_over_diameter;
            let center = normal_center_nm * c;
            if center < reach_lo || center > reach_hi {
                continue;
            }
            let spacing_nm = slot.spacing_over_diameter * diameter_nm;
            let layers = (chord_nm * c / spacing_nm).min(slot.layer_cap).max(1.0);
            if let Some(w) = wavelength_nm {
                if !BraggLine::window_may_hold(slot.coupling, normal_center_nm, c, layers, w) {
                    continue;
                }
            }
            let line = BraggLine::new(slot.coupling, normal_center_nm, c, layers);
            let (lo, hi) = line.window_nm();
            if hi < range_lo || lo > range_hi {
                continue;
            }
            if let Some(w) = wavelength_nm {
                if w <= lo || w >= hi {
                    continue;
                }
            }
            out.push(ActiveLine {
                normal: if dot > 0.0 { -n } else { n },
                kind: slot.kind,
                line,
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::{stage, Rng};
    use crate::scene::{Pattern, Scene};

    fn grains_scene() -> Scene {
        let mut scene = Scene::default();
        scene.domains.pattern = Pattern::Grains;
        scene
    }

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
        // The default stone (all families): random domains, directions and chords (corner
        // chords of a few layers to a colour bar's width), at the centres of the lines met
        // and at wavelengths over the range, against `lines` filtered by the window.
        let stone = Stone::new(&crate::scene::preset("black-opal").unwrap()).unwrap();
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
}

//! Every plane family of the FCC sphere lattice that can reflect visible light, and the
//! strength of each from the crystal's structure (DESIGN §4).
//!
//! Input: a [`CrystalConfig`] → output: [`Families`], one [`FamilyOptics`] per family kind
//! ({111}, {220}, {311}, {200}) with its spacing, its coupling and its plane normals in the
//! lattice frame.
//!
//! The cubic cell of an FCC lattice of touching spheres of diameter D has edge `a = √2·D`.
//! A family (hkl) has spacing `d = a / √(h² + k² + l²)`: `d₁₁₁ = D·√(2/3)`, `d₂₀₀ = D/√2`,
//! `d₂₂₀ = D/2`, `d₃₁₁ = D·√(2/11)`. All four are allowed reflections of FCC (h, k, l all odd
//! or all even), where
//! the four spheres of the cubic cell scatter in phase, so the Fourier coefficient of the
//! permittivity for the reciprocal vector `G = 2π/d` is that of one sphere, as for (111):
//! `ε_G = f (ε_s − ε_m) F(G r)`, `F(x) = 3 (sin x − x cos x)/x³`. The relative coupling
//! `g = |ε_G| / ε̄` is the relative width of the family's stop band at normal incidence. For the
//! default crystal (r = D/2): `x₁₁₁ = π√(3/2) = 3.85` (F = 0.120), `x₂₀₀ = π√2 = 4.44`
//! (F = 0.0075), `x₂₂₀ = 2π` (|F| = 0.076), `x₃₁₁ = π√(11/2) = 7.37` (|F| = 0.0193, 16 % of
//! (111)'s coupling). A thick domain's integrated reflectance (over
//! wavelength) grows as `g·λ_B`, so {220} reflects `0.633 × 0.612 = 0.39` of (111)'s and {200}
//! has 0.06 of (111)'s coupling, too weak to saturate: about 1 % of its reflectance at 400 layers.
//! {311}'s line, `2 d₃₁₁ n̄ cos θ = 1.23 D cos θ`, reaches the visible only for D ≳ 310 nm.

use std::f64::consts::PI;

use glam::Vec3;

use super::dispersion::CrystalIndex;
use super::fcc::sphere_form_factor;
use crate::scene::CrystalConfig;

/// A family of lattice planes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FamilyKind {
    /// {111}: four families, normals along the cube's body diagonals.
    F111,
    /// {200}: three families, normals along the cube's axes.
    F200,
    /// {220}: six families, normals along the cube's face diagonals.
    F220,
    /// {311}: twelve families.
    F311,
}

impl FamilyKind {
    /// All kinds, strongest first.
    pub const ALL: [FamilyKind; 4] = [
        FamilyKind::F111,
        FamilyKind::F220,
        FamilyKind::F311,
        FamilyKind::F200,
    ];

    /// Miller indices of one member.
    pub fn miller(self) -> [i32; 3] {
        match self {
            FamilyKind::F111 => [1, 1, 1],
            FamilyKind::F200 => [2, 0, 0],
            FamilyKind::F220 => [2, 2, 0],
            FamilyKind::F311 => [3, 1, 1],
        }
    }

    /// Plane spacing over the sphere diameter, `√2 / √(h² + k² + l²)`.
    pub fn spacing_over_diameter(self) -> f64 {
        let [h, k, l] = self.miller();
        std::f64::consts::SQRT_2 / ((h * h + k * k + l * l) as f64).sqrt()
    }

    /// The families' unit normals in the lattice frame, one per family (`n` and `−n` are the
    /// same planes).
    pub fn normals(self) -> Vec<Vec3> {
        self.directions()
            .iter()
            .map(|v| Vec3::from_array(*v).normalize())
            .collect()
    }

    /// The families' normals as the smallest integer vectors along them (the Miller indices
    /// or half of them), in the order of [`FamilyKind::normals`].
    pub fn directions(self) -> &'static [[f32; 3]] {
        match self {
            FamilyKind::F111 => &[[1., 1., 1.], [-1., 1., 1.], [1., -1., 1.], [1., 1., -1.]],
            FamilyKind::F200 => &[[1., 0., 0.], [0., 1., 0.], [0., 0., 1.]],
            FamilyKind::F220 => &[
                [1., 1., 0.],
                [1., -1., 0.],
                [1., 0., 1.],
                [1., 0., -1.],
                [0., 1., 1.],
                [0., 1., -1.],
            ],
            FamilyKind::F311 => &[
                [3., 1., 1.],
                [3., -1., 1.],
                [3., 1., -1.],
                [3., -1., -1.],
                [1., 3., 1.],
                [-1., 3., 1.],
                [1., 3., -1.],
                [-1., 3., -1.],
                [1., 1., 3.],
                [-1., 1., 3.],
                [1., -1., 3.],
                [-1., -1., 3.],
            ],
        }
    }

    /// Whether the reflection of the member along `direction` (one of
    /// [`FamilyKind::directions`]) stays sharp when the close-packed layers normal to [111]
    /// are stacked at random: its Miller indices (h, k, l) have `h + k + l ≡ 0 (mod 3)`
    /// (the direction is the indices or half of them, which leaves that unchanged). A stacking fault shifts the layers above it
    /// within their plane by a third of a row, which multiplies a reflection's amplitude by
    /// `e^{2πi(h+k+l)/3}`: 1 for these, so faults leave them as sharp as in a perfect
    /// crystal; the others are smeared into streaks along the stacking axis (Warren,
    /// *X-ray Diffraction*, 1969, ch. 13: faulting in close-packed structures).
    pub fn sharp_when_stacked(direction: [f32; 3]) -> bool {
        let sum = direction.iter().sum::<f32>().round() as i32;
        sum.rem_euclid(3) == 0
    }

    /// Name as in the scene file and the docs.
    pub fn name(self) -> &'static str {
        match self {
            FamilyKind::F111 => "111",
            FamilyKind::F200 => "200",
            FamilyKind::F220 => "220",
            FamilyKind::F311 => "311",
        }
    }
}

/// The optics of one family kind in the crystal of a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct FamilyOptics {
    /// Which family.
    pub kind: FamilyKind,
    /// Spacing over sphere diameter, `d / D`.
    pub spacing_over_diameter: f64,
    /// Relative coupling `g = |ε_G| / ε̄`: the stop band's relative width at normal incidence
    /// (at the sodium d line).
    pub coupling: f64,
    /// Unit normals of its families in the lattice frame.
    pub normals: Vec<Vec3>,
}

/// The families of one crystal and what they share.
#[derive(Clone, Debug, PartialEq)]
pub struct Families {
    /// Effective index `√ε̄` of the domains (and the stone), at the sodium d line.
    pub n_eff: f64,
    /// The indices over wavelength: each line's centre and coupling at its own wavelength
    /// ([`CrystalIndex::line_args`]; `n_eff` and the couplings here are the d line's).
    pub index: CrystalIndex,
    /// One entry per family kind, strongest first.
    pub kinds: Vec<FamilyOptics>,
}

impl Families {
    /// The families of `crystal`: all four kinds, or {111} alone when `only_111`.
    pub fn new(crystal: &CrystalConfig, only_111: bool) -> Families {
        let f = crystal.filling_fraction;
        let eps_s = crystal.n_sphere * crystal.n_sphere;
        let eps_m = crystal.n_matrix * crystal.n_matrix;
        let eps_mean = f * eps_s + (1.0 - f) * eps_m;
        // Sphere radius over D from the filling fraction on the lattice of edge √2·D.
        let radius_over_d = std::f64::consts::SQRT_2 * (3.0 * f / (16.0 * PI)).cbrt();
        let kinds = FamilyKind::ALL
            .into_iter()
            .filter(|&k| !only_111 || k == FamilyKind::F111)
            .map(|kind| {
                let spacing = kind.spacing_over_diameter();
                let x = 2.0 * PI * radius_over_d / spacing;
                let eps_g = f * (eps_s - eps_m) * sphere_form_factor(x);
                FamilyOptics {
                    kind,
                    spacing_over_diameter: spacing,
                    coupling: eps_g.abs() / eps_mean,
                    normals: kind.normals(),
                }
            })
            .collect();
        Families {
            n_eff: eps_mean.sqrt(),
            index: CrystalIndex::new(crystal),
            kinds,
        }
    }

    /// These families in a randomly stacked crystal (stacking axis [111]): only the members
    /// that stay sharp ([`FamilyKind::sharp_when_stacked`]); a kind left with none (the
    /// {200}) is dropped. The streaks of the others are left out.
    pub fn stacked(mut self) -> Families {
        for f in &mut self.kinds {
            f.normals = f
                .kind
                .directions()
                .iter()
                .filter(|d| FamilyKind::sharp_when_stacked(**d))
                .map(|d| Vec3::from_array(*d).normalize())
                .collect();
        }
        self.kinds.retain(|f| !f.normals.is_empty());
        self
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optics::ClusterStack;

    #[test]
    fn random_stacking_keeps_the_reflections_a_layer_shift_leaves_in_phase() {
        // Independently of the rule h + k + l ≡ 0 (mod 3): a stacking fault moves the layers
        // above it from A to B sites, by s = a(1, 1, −2)/6 within the (111) plane (A + s plus
        // one layer spacing along [111] is a(1, 1, 0)/2, a lattice vector of the FCC cell). A
        // reflection G = (h, k, l)·2π/a is unchanged by it when G·s is a multiple of 2π:
        // (h + k − 2l)/6 an integer. The Miller indices of each member: {200} and {220} are
        // twice their directions.
        let stacked = Families::new(&CrystalConfig::default(), false).stacked();
        let mut kept = Vec::new();
        for kind in FamilyKind::ALL {
            let scale = match kind {
                FamilyKind::F200 | FamilyKind::F220 => 2,
                FamilyKind::F111 | FamilyKind::F311 => 1,
            };
            for d in kind.directions() {
                let [h, k, l] = d.map(|c| c as i32 * scale);
                let in_phase = (h + k - 2 * l).rem_euclid(6) == 0;
                let n = Vec3::from_array(*d).normalize();
                let has = stacked
                    .kinds
                    .iter()
                    .any(|f| f.kind == kind && f.normals.contains(&n));
                assert_eq!(has, in_phase, "{kind:?} {d:?}");
                if has {
                    kept.push(kind);
                }
            }
        }
        // The stacking (111), the three in-layer {220} (normal to [111]) and six {311}; no {200}.
        let count = |k| kept.iter().filter(|&&x| x == k).count();
        assert_eq!(
            [
                FamilyKind::F111,
                FamilyKind::F220,
                FamilyKind::F311,
                FamilyKind::F200
            ]
            .map(count),
            [1, 3, 6, 0]
        );
        let axis = Vec3::ONE.normalize();
        let f220 = stacked
            .kinds
            .iter()
            .find(|f| f.kind == FamilyKind::F220)
            .unwrap();
        assert!(f220.normals.iter().all(|n| n.dot(axis).abs() < 1e-6));
        assert_eq!(stacked.kinds[0].normals, vec![axis]);
    }

    #[test]
    fn the_111_coupling_is_the_stacks_relative_gap() {
        let crystal = CrystalConfig::default();
        let families = Families::new(&crystal, false);
        let stack = ClusterStack::new(&crystal).unwrap();
        let g = families.kinds[0].coupling;
        assert!((g - stack.relative_gap()).abs() < 1e-12, "{g}");
        assert!((families.n_eff - stack.n_eff).abs() < 1e-12);
    }

    #[test]
    fn the_220_family_reflects_about_39_percent_of_the_111() {
        // DESIGN §4: {220} about 39 % of the (111) integrated reflectance; for saturated
        // stacks that is the ratio of g·λ_B, i.e. g·d.
        let families = Families::new(&CrystalConfig::default(), false);
        let f111 = &families.kinds[0];
        let f220 = &families.kinds[1];
        assert_eq!(f220.kind, FamilyKind::F220);
        let ratio = (f220.coupling * f220.spacing_over_diameter)
            / (f111.coupling * f111.spacing_over_diameter);
        assert!((ratio - 0.39).abs() < 0.01, "{ratio}");
    }

    #[test]
    fn the_311_coupling_is_16_percent_of_the_111() {
        // DESIGN §4: {311} about 16 % of the (111) coupling. Independently: x = G r with
        // r = D/2 (touching spheres; the default filling fraction 0.74 gives r within 10⁻⁴), d₃₁₁ = D √(2/11), so x = π √(11/2); F(x) = 3(sin x − x cos x)/x³.
        let families = Families::new(&CrystalConfig::default(), false);
        let f311 = families
            .kinds
            .iter()
            .find(|k| k.kind == FamilyKind::F311)
            .unwrap();
        let form = |x: f64| 3.0 * (x.sin() - x * x.cos()) / x.powi(3);
        let (x111, x311) = (PI * 1.5f64.sqrt(), PI * 5.5f64.sqrt());
        let expected = (form(x311) / form(x111)).abs();
        let ratio = f311.coupling / families.kinds[0].coupling;
        assert!(
            (ratio - expected).abs() < 0.01 * expected,
            "{ratio} vs {expected}"
        );
        assert!((ratio - 0.16).abs() < 0.01, "{ratio}");
        assert!((f311.spacing_over_diameter - (2.0f64 / 11.0).sqrt()).abs() < 1e-12);
    }

    #[test]
    fn normals_at_70_5_degrees_for_111_and_counts_4_6_12_3() {
        let n = FamilyKind::F111.normals();
        assert_eq!(n.len(), 4);
        let angle = n[0].dot(n[1]).abs().acos().to_degrees();
        assert!((angle - 70.53).abs() < 0.01, "{angle}");
        assert_eq!(FamilyKind::F220.normals().len(), 6);
        assert_eq!(FamilyKind::F200.normals().len(), 3);
        // The twelve {311} normals: no two alike (nor opposite).
        let n = FamilyKind::F311.normals();
        assert_eq!(n.len(), 12);
        for (i, a) in n.iter().enumerate() {
            for b in &n[i + 1..] {
                assert!(a.dot(*b).abs() < 0.99, "{a} {b}");
            }
        }
    }
}

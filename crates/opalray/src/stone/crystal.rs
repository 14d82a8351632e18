//! What the domains reflect by, the second of [`Stone::new`](super::Stone::new)'s builders:
//! the crystal's plane families that can reach the spectral range, every domain's family
//! normals in the stone's frame, the coherent layers of each family and the spread of its
//! reflection over directions (the mosaic and the diffraction of the domain's width).
//!
//! Input: the scene and the domains → output: a [`Crystal`].

use glam::Vec3;

use super::lines::SlotTable;
use super::widths::{lobe_sigmas, WIDTH_ROWS};
use super::{Domain, LINE_REACH};
use crate::optics::{Families, FamilyKind};
use crate::scene::{FamilyChoice, Scene};

/// The domains' plane families, as the stone reads them.
pub(super) struct Crystal {
    /// The families kept.
    pub families: Families,
    /// Per domain, every family normal in the stone frame (one per slot).
    pub normals: Vec<Vec3>,
    /// Each slot's family kind and what its lines read of it.
    pub slots: SlotTable,
    /// Per kind, the lobe's standard deviation (rad) over cos θ.
    pub lobe_sigma: Vec<[f32; WIDTH_ROWS]>,
}

impl Crystal {
    /// The crystal of `scene` in each of `domains`.
    pub fn new(scene: &Scene, domains: &[Domain]) -> Crystal {
        let families = kept_families(scene);
        Crystal {
            normals: domain_normals(&families, domains),
            slots: SlotTable::new(
                &families,
                families.n_eff as f32,
                reach_nm(scene, &families),
                f64::from(scene.crystal.layers),
            ),
            lobe_sigma: lobe_sigmas(scene, &families),
            families,
        }
    }
}

/// The crystal's families (`domains.families`), less those whose line cannot reach the
/// spectral range in any domain ({311} below D ≈ 250 nm), by the test `Stone::lines` makes of
/// each line first: they would only cost every crossing its test.
fn kept_families(scene: &Scene) -> Families {
    let d = &scene.domains;
    let mut families = Families::new(&scene.crystal, d.families == FamilyChoice::Only111);
    if d.families == FamilyChoice::Stacked {
        families = families.stacked();
    }
    let largest_nm = scene.crystal.sphere_diameter_nm * (1.0 + 3.0 * d.sphere_diameter_spread);
    let two_n = 2.0 * families.n_eff;
    let reach = reach_nm(scene, &families);
    families.kinds.retain(|f| {
        f.kind == FamilyKind::F111 || two_n * f.spacing_over_diameter * largest_nm >= reach
    });
    families
}

/// The shortest centre at the constant index (`2 d n̄_d cos θ`) of a line kept: the one whose
/// centre with the dispersion is [`LINE_REACH`] × the range's short end (the centre grows
/// with the constant one, so the test in either is the same).
fn reach_nm(scene: &Scene, families: &Families) -> f64 {
    families
        .index
        .constant_centre_nm(LINE_REACH * scene.spectrum.min_nm)
}

/// Every family normal of every domain of `domains`, in the stone frame (domain by domain,
/// each in the order of `families`).
pub(super) fn domain_normals(families: &Families, domains: &[Domain]) -> Vec<Vec3> {
    let lattice: Vec<Vec3> = families
        .kinds
        .iter()
        .flat_map(|f| f.normals.clone())
        .collect();
    domains
        .iter()
        .flat_map(|dm| {
            lattice
                .iter()
                .map(move |&n| (dm.orientation * n).normalize())
        })
        .collect()
}

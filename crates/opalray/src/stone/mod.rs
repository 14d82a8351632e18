//! The stone model every renderer shares: the shape and its surface, the domains as geometry
//! and what finds them, and what a ray segment meets inside (potch, or a domain's plane
//! families with their Bragg lines and rocking widths).
//!
//! Input: a [`Scene`] → output: a [`Stone`]. Domains are the paper's growth kept as balls
//! ([`balls`]) or grains of a power diagram ([`grains`]); either way a point's domain is
//! evaluated exactly, so patch edges are spheres or planes at any resolution, never the cell
//! grid's staircase. Each domain has a full lattice orientation and its own sphere diameter;
//! it reflects by every family whose first-order line can fall in the spectral range.
//!
//! [`Stone::new`] composes its builders: `layout.rs` (where the domains lie, their
//! orientations and sphere sizes), `crystal.rs` (the families they reflect by, their normals
//! and lobes), `cut.rs` (the outline, backing, cap and colour bar) and [`Potch`]'s. What a
//! ray segment meets is `walk.rs` ([`Stone::walk`]); the potch, backing, cap and colour bar
//! and where a ray leaves its region, `regions.rs`; the width of a reflection's lobe,
//! `widths.rs` ([`Stone::lobe_sigma`]); the cell grid the paper's two passes read,
//! `voxels.rs` ([`Stone::voxels`]).

pub mod balls;
pub mod body;
mod crystal;
mod cut;
mod faces;
pub mod grains;
mod layout;
mod light_path;
mod lines;
mod regions;
pub mod rough;
pub mod size_field;
mod voxels;
mod walk;
mod widths;

use glam::{Quat, Vec3};

use crate::error::Result;
use crate::geometry::{Ellipsoid, Outline};
use crate::optics::{BraggLine, Families};
use crate::scene::Scene;

pub use crate::scatter::angle_between;
use balls::Balls;
use crystal::{domain_normals, Crystal};
use cut::Surfaces;
use grains::Grains;
use layout::lay_out;
pub use light_path::{PathToLight, LOBE_SIGMAS};
pub use lines::LineWavelength;
use lines::{normal_blocks, NormalBlock, SlotTable};
pub use regions::{ironstone_reflectance, BackSurface, Boundary, Cap, Potch, Region};
use rough::Outlines;
use walk::Merge;
pub use walk::{Hint, Span};
pub use widths::diffraction_sigma_rad;
use widths::WIDTH_ROWS;

/// A line whose centre lies below this fraction of the range's short end is not met (a thin
/// chord's broad line reaches a little beyond its centre).
const LINE_REACH: f64 = 0.8;
/// One ordered domain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Domain {
    /// Lattice orientation (lattice frame → stone frame).
    pub orientation: Quat,
    /// Sphere diameter, nm.
    pub sphere_diameter_nm: f32,
}

/// A family's line met by a ray crossing a domain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ActiveLine {
    /// The planes' unit normal, turned to face the ray (`normal · dir < 0`).
    pub normal: Vec3,
    /// The family kind (index into [`Families::kinds`]).
    pub kind: u8,
    /// The planes' slot among the domain's (the same planes in every ray's lines).
    pub slot: u16,
    /// The line at the ray's angle to the planes, for the layers the chord meets.
    pub line: BraggLine,
}

#[derive(Debug)]
enum Layout {
    /// One domain fills the stone.
    Single,
    Balls(Balls),
    Grains {
        grains: Box<Grains>,
        /// Per grain, its domain or `None` (potch).
        domain_of: Vec<Option<u32>>,
        /// Ragged outlines (`domains.boundary_roughness` > 0), else the grains' own.
        outlines: Option<Box<Outlines>>,
    },
}

/// The stone: shape, domains and their optics.
#[derive(Debug)]
pub struct Stone {
    /// The stone's outer surface.
    pub shape: Outline,
    /// What the flat back sits on, if anything.
    pub back: Option<BackSurface>,
    /// A triplet's cap.
    pub cap: Option<Cap>,
    /// A colour bar: the domains lie only outside this inner surface (in the stone's frame).
    bar_inner: Option<Ellipsoid>,
    /// Centre of `bar_inner`.
    bar_centre: Vec3,
    /// Effective index of the stone (and every domain).
    pub n_eff: f32,
    /// The potch between domains.
    pub potch: Potch,
    /// Every domain.
    pub domains: Vec<Domain>,
    /// The plane families of the crystal.
    pub families: Families,
    layout: Layout,
    /// Per domain, every family normal in the stone frame, four slots to a block
    /// ([`SlotTable::blocks`] per domain).
    normals: Vec<NormalBlock>,
    /// Each slot's family kind and what its lines read of it.
    slots: SlotTable,
    /// Per kind, the lobe's standard deviation (rad) over cos θ, rocking width and mosaic.
    lobe_sigma: Vec<[f32; WIDTH_ROWS]>,
    /// Wavelength range lines are kept in, nm.
    range_nm: (f64, f64),
}

impl Stone {
    /// Build the stone of `scene` (validated by the caller): where its domains lie
    /// (`layout.rs`), what they reflect by (`crystal.rs`), its surfaces (`cut.rs`) and its potch.
    pub fn new(scene: &Scene) -> Result<Stone> {
        let semi_axes_mm = scene.body.box_semi_axes(scene.structure.semi_axes_mm);
        let axes = Vec3::from_array(semi_axes_mm.map(|v| v as f32));
        let (layout, domains) = lay_out(scene, axes)?;
        crate::cancel::Cancel::check_current()?;
        let crystal = Crystal::new(scene, &domains);
        let surfaces = Surfaces::new(scene, axes);
        let n_eff = crystal.families.n_eff as f32;
        Ok(Stone {
            shape: surfaces.shape,
            back: surfaces.back,
            cap: surfaces.cap,
            bar_inner: surfaces.bar_inner,
            bar_centre: surfaces.bar_centre,
            n_eff,
            potch: Potch::of(scene, n_eff),
            domains,
            families: crystal.families,
            layout,
            normals: normal_blocks(&crystal.normals, crystal.slots.optics.len()),
            slots: crystal.slots,
            lobe_sigma: crystal.lobe_sigma,
            range_nm: (scene.spectrum.min_nm, scene.spectrum.max_nm),
        })
    }

    /// The stone of `scene` made of one domain of orientation `orientation` and the crystal's
    /// sphere diameter: a single crystal (for teaching and for tests of the optics).
    pub fn single_crystal(scene: &Scene, orientation: Quat) -> Result<Stone> {
        let mut stone = Stone::new(scene)?;
        let domain = Domain {
            orientation,
            sphere_diameter_nm: scene.crystal.sphere_diameter_nm as f32,
        };
        let normals = domain_normals(&stone.families, &[domain]);
        stone.normals = normal_blocks(&normals, stone.slots());
        stone.domains = vec![domain];
        stone.layout = Layout::Single;
        Ok(stone)
    }

    /// Family slots per domain.
    pub fn slots(&self) -> usize {
        self.slots.optics.len()
    }

    /// The domain at `p` (mm), `None` in potch (or outside the stone, or in a cap).
    pub fn domain_at(&self, p: Vec3) -> Option<u32> {
        if !self.shape.contains(p) || self.region_at(p) == Region::Cap {
            return None;
        }
        if let Some(inner) = &self.bar_inner {
            if inner.contains(p - self.bar_centre) {
                return None;
            }
        }
        match &self.layout {
            Layout::Single => Some(0),
            Layout::Balls(b) => b.at(p),
            Layout::Grains {
                grains,
                domain_of,
                outlines,
            } => {
                let grain = match outlines {
                    Some(o) => o.grain_at(grains, p),
                    None => grains.at(p),
                };
                domain_of[grain as usize]
            }
        }
    }
}

#[cfg(test)]
pub(crate) mod tests;

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
//! and lobes), `cut.rs` (the outline, backing, cap and colour bar) and [`Potch`]'s.

pub mod balls;
pub mod body;
mod crystal;
mod cut;
mod faces;
pub mod grains;
mod layout;
mod light_path;
mod lines;
pub mod rough;
pub mod size_field;

use glam::{Quat, Vec3};

use crate::error::Result;
use crate::geometry::{Ellipsoid, Outline, Ray};
use crate::optics::{BraggLine, Families};
use crate::scene::{Backing, Pattern, Scene};

pub use crate::scatter::angle_between;
use balls::Balls;
use crystal::{domain_normals, Crystal};
use cut::Surfaces;
use grains::Grains;
use layout::lay_out;
pub use light_path::{PathToLight, LOBE_SIGMAS};
use lines::{normal_blocks, NormalBlock, SlotTable};
use rough::Outlines;

/// Rows of the rocking-width table over cos θ.
const WIDTH_ROWS: usize = 64;
/// Lowest cos θ of the rocking-width table (below it the width of this row is used).
const WIDTH_MIN_COS: f64 = 0.2;
/// Full width at half maximum of a Gaussian over its standard deviation, `2√(2 ln 2)`.
const FWHM_PER_SIGMA: f64 = 2.354_820_045;
/// A line whose centre lies below this fraction of the range's short end is not met (a thin
/// chord's broad line reaches a little beyond its centre).
const LINE_REACH: f64 = 0.8;
/// FWHM of a slit's Fraunhofer pattern `sinc²`, in wavelengths over the slit's width.
const SLIT_FWHM_PER_WAVELENGTH: f64 = 0.885_893;

/// A piece of a ray inside the stone: `[t0, t1]` along it, in one domain (or potch: `None`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Span {
    /// Start, mm along the ray.
    pub t0: f32,
    /// End, mm along the ray.
    pub t1: f32,
    /// The domain, or `None` in potch.
    pub domain: Option<u32>,
    /// The cells holding its start: a walk starting there tries them first.
    pub hint: Hint,
}

/// Cells of the grains that likely hold a point, tried first by a walk starting there
/// ([`Stone::walk`]): the column of the ragged outlines and the grain (in that column's shift).
/// A walk finds the same spans with any hint or none, but where a hinted grain claims a sliver
/// beyond a face its rays missed (as a walk from grain to grain does, [`Grains::at_with`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct Hint {
    /// The outlines' column.
    pub column: Option<u32>,
    /// The grain.
    pub grain: Option<u32>,
}

/// One ordered domain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Domain {
    /// Lattice orientation (lattice frame → stone frame).
    pub orientation: Quat,
    /// Sphere diameter, nm.
    pub sphere_diameter_nm: f32,
}

/// The potch (common opal) between the domains: a scattering and absorbing medium.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Potch {
    /// Extinction coefficient, per mm.
    pub extinction_per_mm: f32,
    /// Single-scattering albedo (from the body tone, [`body::potch_albedo`]).
    pub albedo: f32,
    /// Henyey–Greenstein anisotropy of its scattering.
    pub anisotropy: f32,
    /// Scattering coefficient inside the domains (no absorption there), per mm.
    pub domain_scattering_per_mm: f32,
}

impl Potch {
    /// The potch of `scene` (`[body]`, `render.body_tone`) in a stone of index `n_eff`: its
    /// albedo makes a thick slab show the body tone; inside the domains only its haze
    /// (`body.domain_haze`) scatters.
    fn of(scene: &Scene, n_eff: f32) -> Potch {
        let body = &scene.body;
        let albedo = body::potch_albedo(scene.render.body_tone, body.anisotropy, f64::from(n_eff));
        let sigma = body.potch_extinction_per_mm as f32;
        Potch {
            extinction_per_mm: sigma,
            albedo,
            anisotropy: body.anisotropy as f32,
            domain_scattering_per_mm: body.domain_haze as f32 * sigma * albedo,
        }
    }
}

/// The surface a flat back is glued on.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BackSurface {
    /// Height of the back plane, mm.
    pub z: f32,
    /// What it is.
    pub kind: Backing,
}

impl BackSurface {
    /// Its diffuse (Lambertian) reflectance at `wavelength_nm`.
    pub fn reflectance(&self, wavelength_nm: f64) -> f64 {
        match self.kind {
            Backing::None => 0.0,
            Backing::Black => 0.03,
            Backing::Ironstone => ironstone_reflectance(wavelength_nm),
        }
    }
}

/// Diffuse reflectance of ironstone (a boulder opal's matrix) at `wavelength_nm`: iron oxides
/// reflect little blue and more red, 6 % at 400 nm rising to 22 % at 700 nm — a brown.
pub fn ironstone_reflectance(wavelength_nm: f64) -> f64 {
    let x = ((wavelength_nm - 400.0) / 300.0).clamp(0.0, 1.0);
    0.06 + 0.16 * x * x
}

/// A triplet's clear cap: the dome above the plane `z`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cap {
    /// Height of the plane between the opal slice and the cap, mm.
    pub z: f32,
    /// The cap's refractive index.
    pub n: f32,
}

/// The region of the stone a point lies in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Region {
    /// The opal.
    Opal,
    /// A triplet's clear cap.
    Cap,
}

/// Where a ray inside a region leaves it.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Boundary {
    /// The stone's outer surface.
    Surface,
    /// The backing under a flat back.
    Back,
    /// The plane between a triplet's slice and its cap.
    CapPlane,
}

/// A family's line met by a ray crossing a domain.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ActiveLine {
    /// The planes' unit normal, turned to face the ray (`normal · dir < 0`).
    pub normal: Vec3,
    /// The family kind (index into [`Families::kinds`]).
    pub kind: u8,
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

    /// Call `visit` for the spans of `[t0, t1]` along `origin + t·dir` (mm; `dir` unit), in
    /// order, each in one domain or in potch, until it returns false (a path's event: the
    /// rest of the segment is not walked). The caller keeps the segment inside the stone.
    ///
    /// `hint` holds the cells of the start, if known (a walk's return value, where it ended,
    /// or a span's); it returns the cells of the end (of a walk that reached `t1`).
    pub fn walk(
        &self,
        origin: Vec3,
        dir: Vec3,
        t0: f32,
        t1: f32,
        hint: Hint,
        visit: &mut dyn FnMut(Span) -> bool,
    ) -> Hint {
        if self.domains.is_empty() {
            // Potch only.
            visit(Span {
                t0,
                t1,
                domain: None,
                hint: Hint::default(),
            });
            return Hint::default();
        }
        let Some(inner) = &self.bar_inner else {
            return self.walk_domains(origin, dir, t0, t1, hint, visit);
        };
        // Under the colour bar the domains are potch: split the spans at the inner surface.
        let ray = Ray {
            origin: origin - self.bar_centre,
            direction: dir,
        };
        let Some((a, b)) = inner.intersect(&ray).filter(|&(a, b)| b > t0 && a < t1) else {
            return self.walk_domains(origin, dir, t0, t1, hint, visit);
        };
        // Walk the domains only outside the inner surface: under it is one span of potch.
        let (a, b) = (a.max(t0), b.min(t1));
        let mut merged = Merge::default();
        if a > t0 {
            self.walk_domains(origin, dir, t0, a, hint, &mut |span| {
                merged.push(span, visit)
            });
        }
        let under = Span {
            t0: a,
            t1: b,
            domain: None,
            hint: Hint::default(),
        };
        // The hint is of the walk that ends at `t1`.
        let mut end = Hint::default();
        if merged.push(under, visit) && t1 > b {
            end = self.walk_domains(origin, dir, b, t1, Hint::default(), &mut |span| {
                merged.push(span, visit)
            });
        }
        merged.finish(visit);
        end
    }

    /// [`Stone::walk`] without the colour bar.
    fn walk_domains(
        &self,
        origin: Vec3,
        dir: Vec3,
        t0: f32,
        t1: f32,
        hint: Hint,
        visit: &mut dyn FnMut(Span) -> bool,
    ) -> Hint {
        match &self.layout {
            Layout::Single => {
                visit(Span {
                    t0,
                    t1,
                    domain: Some(0),
                    hint: Hint::default(),
                });
                Hint::default()
            }
            Layout::Balls(b) => {
                b.walk(origin, dir, t0, t1, visit);
                Hint::default()
            }
            Layout::Grains {
                grains,
                domain_of,
                outlines,
            } => {
                let mut merged = Merge::default();
                let mut last = hint;
                // A span of a domain starts in its first grain's cells.
                let mut merge = |span: Span, grain: u32| {
                    last = span.hint;
                    let domain = domain_of[grain as usize];
                    merged.push(Span { domain, ..span }, visit)
                };
                match outlines {
                    Some(o) => {
                        let ray = Ray {
                            origin,
                            direction: dir,
                        };
                        o.walk(grains, &ray, t0, t1, hint, &mut merge)
                    }
                    None => grains.walk(origin, dir, t0, t1, hint.grain, &mut merge),
                };
                merged.finish(visit);
                last
            }
        }
    }

    /// An upper bound of the share of light from outside that reaches `p` (inside the opal)
    /// unscattered: `exp(−σ_min d)`, d a lower bound of the distance to the surface
    /// ([`Outline::depth_bound`]) and σ_min the least extinction on the way (the potch's, or
    /// the milky domains'; 0 where domains are clear).
    pub fn reach_bound(&self, p: Vec3) -> f32 {
        let sigma = if self.domains.is_empty() {
            self.potch.extinction_per_mm
        } else {
            self.potch
                .extinction_per_mm
                .min(self.potch.domain_scattering_per_mm)
        };
        if sigma <= 0.0 {
            // Clear domains: no bound short of 1, and no distance worth finding.
            return 1.0;
        }
        (-sigma * self.shape.depth_bound(p)).exp()
    }

    /// The colour bar's inner surface (the top of the potch under it) as an ellipsoid about
    /// the returned centre, if the stone has a bar.
    pub fn bar_surface(&self) -> Option<(Ellipsoid, Vec3)> {
        self.bar_inner.map(|e| (e, self.bar_centre))
    }

    /// The length of `ray.at(t)`, `t ∈ [0, t_end]`, under the colour bar's inner surface (in
    /// the potch there), 0 without a bar.
    pub fn bar_chord(&self, ray: &Ray, t_end: f32) -> f32 {
        let Some(inner) = &self.bar_inner else {
            return 0.0;
        };
        let local = Ray {
            origin: ray.origin - self.bar_centre,
            direction: ray.direction,
        };
        inner
            .intersect(&local)
            .map_or(0.0, |(a, b)| (b.min(t_end) - a.max(0.0)).max(0.0))
    }

    /// The region `p` (inside the stone) lies in.
    #[inline]
    pub fn region_at(&self, p: Vec3) -> Region {
        match self.cap {
            Some(cap) if p.z > cap.z => Region::Cap,
            _ => Region::Opal,
        }
    }

    /// The refractive index of `region`.
    #[inline]
    pub fn index_of(&self, region: Region) -> f32 {
        match (region, self.cap) {
            (Region::Cap, Some(cap)) => cap.n,
            _ => self.n_eff,
        }
    }

    /// Where `ray`, inside the stone in `region`, leaves that region: `(t, boundary)`, or
    /// `None` if it does not meet the surface (numerically outside).
    #[inline]
    pub fn exit(&self, ray: &Ray, region: Region) -> Option<(f32, Boundary)> {
        let (_, t_far) = self.shape.intersect(ray)?;
        let mut best = (t_far.max(0.0), Boundary::Surface);
        let dz = ray.direction.z;
        let oz = ray.origin.z;
        // A plane closer than the surface, or as close (the flat back lies on it).
        let mut plane = |z: f32, boundary: Boundary, downwards: bool| {
            if (downwards && dz < 0.0) || (!downwards && dz > 0.0) {
                let t = ((z - oz) / dz).max(0.0);
                if t <= best.0 + 1e-4 {
                    best = (t.min(best.0), boundary);
                }
            }
        };
        match region {
            Region::Opal => {
                if let Some(back) = self.back {
                    plane(back.z, Boundary::Back, true);
                }
                if let Some(cap) = self.cap {
                    plane(cap.z, Boundary::CapPlane, false);
                }
            }
            Region::Cap => {
                if let Some(cap) = self.cap {
                    plane(cap.z, Boundary::CapPlane, true);
                }
            }
        }
        Some(best)
    }

    /// Standard deviation (rad) of the reflection lobe of family kind `kind` about its normal
    /// at cos θ `cos_theta`: the mosaic spread and the diffraction of the domain's width
    /// ([`diffraction_sigma_rad`]). A perfect domain (mosaic 0) is a mirror; the stack's
    /// rocking width is not in it (it sets which wavelengths reflect, in R(λ, θ)).
    pub fn lobe_sigma(&self, kind: u8, cos_theta: f32) -> f32 {
        let table = &self.lobe_sigma[kind as usize];
        let x = (f64::from(cos_theta) - WIDTH_MIN_COS) / (1.0 - WIDTH_MIN_COS)
            * (WIDTH_ROWS - 1) as f64;
        let x = x.clamp(0.0, (WIDTH_ROWS - 1) as f64);
        let i = (x as usize).min(WIDTH_ROWS - 2);
        let f = (x - i as f64) as f32;
        table[i] * (1.0 - f) + table[i + 1] * f
    }
}

/// Adjacent spans of one domain merged into one before they are visited; once `visit` has
/// said stop, nothing more is visited.
#[derive(Default)]
struct Merge {
    pending: Option<Span>,
    stopped: bool,
}

impl Merge {
    /// Take the next span in order; false once the walk should stop.
    fn push(&mut self, span: Span, visit: &mut dyn FnMut(Span) -> bool) -> bool {
        if self.stopped {
            return false;
        }
        match self.pending.as_mut() {
            Some(p) if p.domain == span.domain => p.t1 = span.t1,
            _ => {
                if let Some(p) = self.pending.replace(span) {
                    self.stopped = !visit(p);
                }
            }
        }
        !self.stopped
    }

    /// Visit the last span, unless the walk was stopped.
    fn finish(self, visit: &mut dyn FnMut(Span) -> bool) {
        if let (Some(p), false) = (self.pending, self.stopped) {
            visit(p);
        }
    }
}

/// The far-field spread of a reflection by a domain `width_mm` wide, as the standard deviation
/// (rad, inside) of the Gaussian of the same half width: a uniformly lit aperture's `sinc²`
/// has FWHM `0.886 λ/w` (Born & Wolf §8.5), λ the wavelength inside, `2 d cos θ` for planes of
/// spacing `spacing_mm` met at `cos_theta` (Bragg's law).
pub fn diffraction_sigma_rad(spacing_mm: f64, cos_theta: f64, width_mm: f64) -> f64 {
    SLIT_FWHM_PER_WAVELENGTH * 2.0 * spacing_mm * cos_theta / width_mm / FWHM_PER_SIGMA
}

/// A domain's width, mm: the grains' `grain_size_mm`, or the diameter of the paper's mean
/// ball (`2 R` cells of the growth grid).
fn domain_width_mm(scene: &Scene) -> f64 {
    let s = &scene.structure;
    match scene.domains.pattern {
        Pattern::Grains => scene.domains.grain_size_mm,
        Pattern::Paper => 2.0 * s.mean_radius_cells * 2.0 * s.semi_axes_mm[0] / s.grid[0] as f64,
    }
}

fn width_row_cos(row: usize) -> f64 {
    WIDTH_MIN_COS + (1.0 - WIDTH_MIN_COS) * row as f64 / (WIDTH_ROWS - 1) as f64
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::OrientationLaw;
    use crate::structure::AXIS_111;

    /// The default scene with its domains as grains.
    pub(super) fn grains_scene() -> Scene {
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

    #[test]
    fn a_walk_told_to_stop_visits_what_a_full_walk_visits_first_and_no_more() {
        // The default stone: a colour bar of ragged plates over potch, so spans are merged
        // from columns and grains and split at the bar's inner surface.
        let stone = Stone::new(&crate::scene::preset("black-opal").unwrap()).unwrap();
        let origin = Vec3::new(-3.0, 1.0, 3.9);
        let dir = Vec3::new(0.3, -0.1, -1.0).normalize();
        let Some((_, t1)) = stone.shape.intersect(&Ray {
            origin: origin - dir * 10.0,
            direction: dir,
        }) else {
            panic!("the ray misses the stone")
        };
        let t1 = t1 - 10.0;
        let mut full = Vec::new();
        stone.walk(origin, dir, 0.0, t1, Hint::default(), &mut |s| {
            full.push(s);
            true
        });
        assert!(full.len() > 5, "{} spans", full.len());
        assert!(full.iter().any(|s| s.domain.is_none()), "no potch met");
        for k in 1..=full.len() {
            let mut seen = Vec::new();
            stone.walk(origin, dir, 0.0, t1, Hint::default(), &mut |s| {
                seen.push(s);
                seen.len() < k
            });
            assert_eq!(seen, full[..k], "stopped after {k}");
        }
    }

    #[test]
    fn a_perfect_domain_spreads_its_reflection_by_its_width_alone() {
        // Mosaic 0: the lobe is the diffraction of the 2 mm grain, FWHM 0.886 λ/w with λ the
        // wavelength inside (the line's centre over n_eff) — about 0.01°, not the stack's
        // rocking width (0.48° at 30° for 400 layers, DESIGN §4).
        let mut scene = grains_scene();
        scene.domains.mosaic_spread_deg = 0.0;
        let stone = Stone::new(&scene).unwrap();
        let c = 30f64.to_radians().cos();
        let fwhm = f64::from(stone.lobe_sigma(0, c as f32)) * FWHM_PER_SIGMA;
        let d111_nm = 250.0 * (2.0f64 / 3.0).sqrt();
        let lambda_inside_mm = 2.0 * d111_nm * c * 1e-6;
        let expected = 0.886 * lambda_inside_mm / scene.domains.grain_size_mm;
        assert!((fwhm / expected - 1.0).abs() < 0.01, "{fwhm} vs {expected}");
        assert!(fwhm.to_degrees() < 0.02, "{}°", fwhm.to_degrees());
        // With a mosaic, the mosaic rules it.
        scene.domains.mosaic_spread_deg = 1.5;
        let stone = Stone::new(&scene).unwrap();
        let sigma = f64::from(stone.lobe_sigma(0, c as f32)).to_degrees();
        assert!((sigma - 1.5).abs() < 1e-3, "{sigma}°");
    }
}

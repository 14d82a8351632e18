//! The stone's media and boundaries besides the domains: the potch between them, the
//! backing under a flat back (and ironstone's colour), a triplet's cap and the colour bar;
//! which region a point lies in, its index, and where a ray leaves its region.

use glam::Vec3;

use super::{body, Stone};
use crate::geometry::{Ellipsoid, Ray};
use crate::scene::{Backing, Scene};

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
    pub(super) fn of(scene: &Scene, n_eff: f32) -> Potch {
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

impl Stone {
    /// An upper bound of the share of light from outside that reaches `p` (inside the opal)
    /// unscattered: `exp(−σ_min d)`, d a lower bound of the distance to the surface
    /// ([`Outline::depth_bound`](crate::geometry::Outline::depth_bound)) and σ_min the least
    /// extinction on the way (the potch's, or the milky domains'; 0 where domains are clear).
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
}

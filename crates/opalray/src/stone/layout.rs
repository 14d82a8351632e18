//! Where the domains lie, the first of [`Stone::new`](super::Stone::new)'s builders: the
//! paper's growth kept as balls, or the grains of a power diagram with their laws of
//! orientation (independent, correlated, settled, settled over smooth tilt fields), of sphere
//! size (drawn per domain or a smooth field) and their ragged outlines.
//!
//! Input: the scene and the stone's box → output: the [`Layout`] and every domain's
//! orientation and sphere diameter. Each draw has its own `(seed, stage::STONE, index)`
//! stream, so a domain is the same whatever else the stone holds.

use glam::{Quat, Vec3};

use super::balls::Balls;
use super::grains::{normal, Grains};
use super::rough::Outlines;
use super::size_field::SizeField;
use super::{Domain, Layout};
use crate::error::Result;
use crate::sampling::{stage, Rng};
use crate::scene::{OrientationLaw, Pattern, Scene};
use crate::structure::orientation::jitter;
use crate::structure::AXIS_111;

/// Stream index of the grains' seeds.
const GRAINS_STREAM: u64 = 0;
/// Stream index of the correlated orientation's parent grains.
const PARENTS_STREAM: u64 = 1;
/// First stream index of the grains' own draws (void or not, orientation), one per grain.
const GRAIN_STREAM: u64 = 2;
/// First stream index of the sphere diameters drawn per domain.
const DIAMETER_STREAM: u64 = 1 << 40;
/// First stream index of the parent grains' orientations.
const PARENT_ORIENTATION_STREAM: u64 = 1 << 41;
/// Stream index of the smooth field of sphere sizes.
const SIZE_FIELD_STREAM: u64 = 1 << 42;
/// Stream index of the ragged outlines.
const OUTLINES_STREAM: u64 = 1 << 43;
/// Stream index of the settled grains' tilt fields.
const TILT_FIELD_STREAM: u64 = 1 << 44;

/// The layout of `scene`'s domains in the stone's box of semi-axes `axes` (mm), and every
/// domain (in the layout's order).
pub(super) fn lay_out(scene: &Scene, axes: Vec3) -> Result<(Layout, Vec<Domain>)> {
    let diameters = Diameters { scene };
    match scene.domains.pattern {
        Pattern::Paper => {
            let balls = Balls::grow(&scene.structure)?;
            let domains = (0..balls.balls.len())
                .map(|k| Domain {
                    orientation: balls.balls[k].orientation,
                    sphere_diameter_nm: diameters.drawn(k as u64),
                })
                .collect();
            Ok((Layout::Balls(balls), domains))
        }
        Pattern::Grains => lay_out_grains(scene, axes, &diameters),
    }
}

/// Sphere diameters about the crystal's, spread by `domains.sphere_diameter_spread`.
struct Diameters<'a> {
    scene: &'a Scene,
}

impl Diameters<'_> {
    /// The sphere diameter `z` standard deviations from the mean (clipped at ±3), nm.
    fn at(&self, z: f32) -> f32 {
        let z = z.clamp(-3.0, 3.0);
        let spread = self.scene.domains.sphere_diameter_spread;
        (self.scene.crystal.sphere_diameter_nm * (1.0 + spread * f64::from(z))) as f32
    }

    /// The sphere diameter of domain (or grain) `index`, drawn from its own stream, nm.
    fn drawn(&self, index: u64) -> f32 {
        let seed = self.scene.structure.seed;
        let mut rng = Rng::new(seed, stage::STONE, DIAMETER_STREAM + index);
        self.at(normal(&mut rng))
    }
}

/// The grains of `scene` in the box of semi-axes `axes`: each a domain or, with probability
/// `domains.void_fraction`, potch. A cancelled preparation stops between blocks of grains.
fn lay_out_grains(
    scene: &Scene,
    axes: Vec3,
    diameters: &Diameters,
) -> Result<(Layout, Vec<Domain>)> {
    let d = &scene.domains;
    let seed = scene.structure.seed;
    let laws = GrainLaws::new(scene, axes);
    let mut rng = Rng::new(seed, stage::STONE, GRAINS_STREAM);
    let grains = Grains::new(
        axes,
        d.grain_size_mm as f32,
        d.grain_size_spread as f32,
        laws.stretch,
        &mut rng,
    );
    let mut domains = Vec::new();
    let mut domain_of = Vec::with_capacity(grains.seeds.len());
    for (i, &seed_q) in grains.seeds.iter().enumerate() {
        if i % 1024 == 0 {
            crate::cancel::Cancel::check_current()?;
        }
        let mut rng = Rng::new(seed, stage::STONE, GRAIN_STREAM + i as u64);
        if rng.uniform() < d.void_fraction {
            domain_of.push(None);
            continue;
        }
        let orientation = laws.orientation(seed_q, &mut rng);
        domain_of.push(Some(domains.len() as u32));
        domains.push(Domain {
            orientation,
            sphere_diameter_nm: laws.diameter(i, seed_q, diameters),
        });
    }
    crate::cancel::Cancel::check_current()?;
    let layout = Layout::Grains {
        grains: Box::new(grains),
        domain_of,
        outlines: ragged_outlines(scene, axes, laws.stretch),
    };
    Ok((layout, domains))
}

/// Ragged outlines (`domains.boundary_roughness` > 0): columns that shift the grains each by
/// its own offset.
fn ragged_outlines(scene: &Scene, axes: Vec3, stretch: Vec3) -> Option<Box<Outlines>> {
    let d = &scene.domains;
    (d.boundary_roughness > 0.0).then(|| {
        let mut rng = Rng::new(scene.structure.seed, stage::STONE, OUTLINES_STREAM);
        Box::new(Outlines::new(
            axes,
            d.grain_size_mm as f32,
            stretch,
            d.boundary_roughness as f32,
            &mut rng,
        ))
    })
}

/// How a grain's orientation and sphere size are drawn (`[domains]`).
struct GrainLaws {
    /// The stone's seed (`structure.seed`).
    seed: u64,
    /// The orientation law (`domains.orientation`).
    law: OrientationLaw,
    /// The grains' stretch (`domains.stretch`).
    stretch: Vec3,
    /// RMS spread of the orientations about their parent's or the face, radians.
    spread: f64,
    /// Correlated orientations: the larger grains whose orientation the grains share.
    parents: Option<Grains>,
    /// A smooth field of sphere sizes, else drawn grain by grain.
    sizes: Option<SizeField>,
    /// Settled tilts over smooth fields, else drawn grain by grain.
    tilts: Option<TiltField>,
}

impl GrainLaws {
    /// The laws of `scene`'s grains in the box of semi-axes `axes`.
    fn new(scene: &Scene, axes: Vec3) -> GrainLaws {
        let d = &scene.domains;
        let seed = scene.structure.seed;
        let spread = d.orientation_spread_deg.to_radians();
        let parents = (d.orientation == OrientationLaw::Correlated).then(|| {
            let mut rng = Rng::new(seed, stage::STONE, PARENTS_STREAM);
            Grains::new(axes, d.correlation_mm as f32, 0.0, Vec3::ONE, &mut rng)
        });
        let sizes = (d.diameter_correlation_mm > 0.0).then(|| {
            let mut rng = Rng::new(seed, stage::STONE, SIZE_FIELD_STREAM);
            SizeField::new(d.diameter_correlation_mm, &mut rng)
        });
        let settled_fields =
            d.orientation == OrientationLaw::Settled && d.tilt_correlation_mm > 0.0;
        let tilts = settled_fields.then(|| {
            let mut rng = Rng::new(seed, stage::STONE, TILT_FIELD_STREAM);
            let jitter = d.tilt_jitter_deg.to_radians();
            TiltField::new(d.tilt_correlation_mm, spread, jitter, &mut rng)
        });
        GrainLaws {
            seed,
            law: d.orientation,
            stretch: Vec3::from_array(d.stretch.map(|v| v as f32)),
            spread,
            parents,
            sizes,
            tilts,
        }
    }

    /// The orientation of the grain whose seed is at `seed_q` (mm), drawn from its `rng`.
    fn orientation(&self, seed_q: Vec3, rng: &mut Rng) -> Quat {
        match &self.parents {
            None if self.law == OrientationLaw::Settled => match &self.tilts {
                None => settled(self.spread, rng),
                Some(field) => field.at(seed_q * self.stretch, rng),
            },
            None => rng.rotation(),
            Some(p) => {
                let parent = p.at(seed_q * self.stretch);
                let stream = PARENT_ORIENTATION_STREAM + u64::from(parent);
                let q = Rng::new(self.seed, stage::STONE, stream).rotation();
                jitter(q, self.spread, rng)
            }
        }
    }

    /// The sphere diameter (nm) of grain `i`, whose seed is at `seed_q` (mm).
    fn diameter(&self, i: usize, seed_q: Vec3, diameters: &Diameters) -> f32 {
        match &self.sizes {
            None => diameters.drawn(i as u64),
            Some(field) => diameters.at(field.at(seed_q * self.stretch)),
        }
    }
}

/// A settled grain's orientation: its layers of spheres (a (111) plane family) lie near the
/// stone's bedding plane (xy), the layers' normal tilted from z by an angle whose root mean
/// square is `spread_rad` (a two-dimensional Gaussian tilt, so the tilt's azimuth is
/// uniform), the lattice turned about that normal by a uniform angle.
fn settled(spread_rad: f64, rng: &mut Rng) -> Quat {
    let spin = std::f64::consts::TAU * rng.uniform();
    let per_axis = spread_rad / std::f64::consts::SQRT_2;
    let tilt = per_axis * (-2.0 * (1.0 - rng.uniform()).max(1e-300).ln()).sqrt();
    let azimuth = std::f64::consts::TAU * rng.uniform();
    settled_at(tilt, azimuth, spin)
}

/// The orientation whose layers' normal is tilted from z by `tilt` towards the azimuth
/// `azimuth` (radians), the lattice turned by `spin` about the normal first.
fn settled_at(tilt: f64, azimuth: f64, spin: f64) -> Quat {
    let align = Quat::from_rotation_arc(AXIS_111, Vec3::Z);
    let turn = Quat::from_rotation_z(spin as f32);
    let axis = Vec3::new(-azimuth.sin() as f32, azimuth.cos() as f32, 0.0);
    (Quat::from_axis_angle(axis, tilt as f32) * turn * align).normalize()
}

/// Settled grains that are parts of larger crystals: the layers' tilt and the lattice's turn
/// vary smoothly over the stone, and each grain departs from them a little.
///
/// The tilt vector is `σ_f/√2 (Z₁(p), Z₂(p))` of two smooth fields ([`SizeField`], standard
/// normal, correlation length L) plus the grain's own Gaussian vector of RMS `jitter`, with
/// `σ_f² = spread² − jitter²`: the RMS tilt is the spread, as for independent grains. The
/// turn is the angle of `(Z₃(p), Z₄(p))` (uniform, since an isotropic Gaussian vector's angle
/// is) plus the grain's normal draw of RMS `jitter`.
struct TiltField {
    fields: [SizeField; 4],
    field_rms: f64,
    jitter: f64,
}

impl TiltField {
    fn new(length_mm: f64, spread: f64, jitter: f64, rng: &mut Rng) -> TiltField {
        TiltField {
            fields: std::array::from_fn(|_| SizeField::new(length_mm, rng)),
            field_rms: (spread * spread - jitter * jitter).max(0.0).sqrt(),
            jitter,
        }
    }

    /// The orientation of the grain whose seed is at `p` (mm), its own part drawn from `rng`.
    fn at(&self, p: Vec3, rng: &mut Rng) -> Quat {
        let [z1, z2, z3, z4] = self.fields.each_ref().map(|f| f64::from(f.at(p)));
        let field = self.field_rms / std::f64::consts::SQRT_2;
        let own = self.jitter / std::f64::consts::SQRT_2;
        let tx = field * z1 + own * f64::from(normal(rng));
        let ty = field * z2 + own * f64::from(normal(rng));
        let spin = z4.atan2(z3) + self.jitter * f64::from(normal(rng));
        settled_at(tx.hypot(ty), ty.atan2(tx), spin)
    }
}

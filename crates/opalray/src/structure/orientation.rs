//! Cluster orientations: averaging the orientations already set in a neighbourhood (paper
//! §2.4, step 4) and the optional jitter of a grown patch.
//!
//! An orientation is a unit quaternion `q` taking the lattice frame to the stone frame; the
//! optics use its (111) plane normal `n = q·(1, 1, 1)/√3`. Two quaternions describe the same
//! planes when they differ by sign (`q` and `−q` are one rotation) or by a symmetry of the
//! close-packed stack that keeps the \[111\] axis as a line: the dihedral group D3 (identity,
//! ±120° about \[111\], 180° about the in-plane axes \[1−10\], \[01−1\], \[−101\]); the 180° turns
//! take `n` to `−n`, the same planes. Before averaging, each quaternion is replaced by its
//! equivalent (over sign and D3, 12 candidates) closest to a reference, then the aligned
//! quaternions are summed and normalised: the chordal L2 mean, which for the clustered
//! orientations met in growth agrees with the geodesic mean to second order in their spread.

use glam::{DQuat, DVec4, Quat, Vec3};

use crate::sampling::Rng;

const H: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// The six rotations of D3 about the lattice's \[111\] axis, as unit quaternions `(x, y, z, w)`
/// in the lattice frame.
pub const STACK_SYMMETRIES: [[f64; 4]; 6] = [
    [0.0, 0.0, 0.0, 1.0],
    [0.5, 0.5, 0.5, 0.5],
    [-0.5, -0.5, -0.5, 0.5],
    [H, -H, 0.0, 0.0],
    [0.0, H, -H, 0.0],
    [-H, 0.0, H, 0.0],
];

/// Hamilton product of two quaternions stored as `(x, y, z, w)`, not necessarily unit.
fn mul(a: DVec4, b: DVec4) -> DVec4 {
    DVec4::new(
        a.w * b.x + a.x * b.w + a.y * b.z - a.z * b.y,
        a.w * b.y - a.x * b.z + a.y * b.w + a.z * b.x,
        a.w * b.z + a.x * b.y - a.y * b.x + a.z * b.w,
        a.w * b.w - a.x * b.x - a.y * b.y - a.z * b.z,
    )
}

fn conjugate(q: DVec4) -> DVec4 {
    DVec4::new(-q.x, -q.y, -q.z, q.w)
}

fn to_dvec4(q: Quat) -> DVec4 {
    DVec4::new(
        f64::from(q.x),
        f64::from(q.y),
        f64::from(q.z),
        f64::from(q.w),
    )
}

/// Running symmetry-aligned mean of orientations.
///
/// The first orientation added (or the one given to [`OrientationMean::with_reference`]) is
/// the reference. Aligning `q` means choosing the symmetry `g` and sign `s` maximising
/// `⟨q_ref, s·q·g⟩ = s·⟨q_ref·g⁻¹, q⟩`, so the six products `q_ref·g⁻¹` are formed once and
/// each addition costs six 4-D dot products; the aligned sum is kept as one sum per `g`,
/// `Σ s·q·g = Σ_g (Σ s·q)·g`, and multiplied out only at the end.
#[derive(Clone, Debug, Default)]
pub struct OrientationMean {
    references: Option<[DVec4; 6]>,
    sums: [DVec4; 6],
    count: usize,
    last: Option<(Quat, usize, f64)>,
}

impl OrientationMean {
    /// An empty mean; the first orientation added becomes the reference.
    pub fn new() -> Self {
        Self::default()
    }

    /// An empty mean aligned to `reference` (which is not itself added).
    pub fn with_reference(reference: Quat) -> Self {
        let mut mean = Self::default();
        mean.set_reference(reference);
        mean
    }

    fn set_reference(&mut self, reference: Quat) {
        let r = to_dvec4(reference);
        self.references = Some(STACK_SYMMETRIES.map(|g| mul(r, conjugate(DVec4::from(g)))));
    }

    /// Add one orientation (a unit quaternion) to the mean.
    pub fn add(&mut self, q: Quat) {
        // Neighbouring cells of one patch share a quaternion: reuse the last alignment.
        let (best, sign) = match self.last {
            Some((last, best, sign)) if last == q => (best, sign),
            _ => {
                if self.references.is_none() {
                    self.set_reference(q);
                }
                let references = self.references.as_ref().expect("reference set above");
                let v = to_dvec4(q);
                let (mut best, mut best_dot) = (0, references[0].dot(v));
                for (g, r) in references.iter().enumerate().skip(1) {
                    let dot = r.dot(v);
                    if dot.abs() > best_dot.abs() {
                        (best, best_dot) = (g, dot);
                    }
                }
                let sign = if best_dot < 0.0 { -1.0 } else { 1.0 };
                self.last = Some((q, best, sign));
                (best, sign)
            }
        };
        self.sums[best] += sign * to_dvec4(q);
        self.count += 1;
    }

    /// Orientations added so far.
    pub fn count(&self) -> usize {
        self.count
    }

    /// The normalised aligned mean, or `None` if nothing was added.
    pub fn mean(&self) -> Option<Quat> {
        if self.count == 0 {
            return None;
        }
        let total = self
            .sums
            .iter()
            .zip(STACK_SYMMETRIES)
            .fold(DVec4::ZERO, |acc, (&s, g)| acc + mul(s, DVec4::from(g)));
        // ⟨q_ref, total⟩ ≥ 1 when the reference was added, so the sum never vanishes then.
        let q = DQuat::from_vec4(total.normalize());
        Some(Quat::from_xyzw(q.x as f32, q.y as f32, q.z as f32, q.w as f32).normalize())
    }
}

/// Standard normal variate (Box–Muller), two uniforms from `rng`.
fn standard_normal(rng: &mut Rng) -> f64 {
    let u1 = 1.0 - rng.uniform();
    let u2 = rng.uniform();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// Tilt `q` by a random rotation: axis uniform on the sphere, angle `sigma_rad·|Z|` with `Z`
/// standard normal, so the angle's root mean square is `sigma_rad`. Applied in the stone
/// frame (`q' = Δ·q`). `sigma_rad = 0` returns `q` and draws nothing.
pub fn jitter(q: Quat, sigma_rad: f64, rng: &mut Rng) -> Quat {
    if sigma_rad <= 0.0 {
        return q;
    }
    let axis: Vec3 = rng.unit_vector();
    let angle = sigma_rad * standard_normal(rng).abs();
    (Quat::from_axis_angle(axis, angle as f32) * q).normalize()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::structure::AXIS_111;

    fn q(v: [f64; 4]) -> Quat {
        Quat::from_xyzw(v[0] as f32, v[1] as f32, v[2] as f32, v[3] as f32)
    }

    #[test]
    fn stack_symmetries_keep_the_111_planes() {
        for g in STACK_SYMMETRIES {
            let n = q(g) * AXIS_111;
            assert!(
                n.dot(AXIS_111).abs() > 1.0 - 1e-6,
                "{g:?} maps (111) to {n}"
            );
            assert!((DVec4::from(g).length() - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn stack_symmetries_form_a_group() {
        for a in STACK_SYMMETRIES {
            for b in STACK_SYMMETRIES {
                let ab = mul(DVec4::from(a), DVec4::from(b));
                let found = STACK_SYMMETRIES
                    .iter()
                    .any(|&g| DVec4::from(g).dot(ab).abs() > 1.0 - 1e-12);
                assert!(found, "{a:?}·{b:?} = {ab} is not in the group");
            }
        }
    }

    #[test]
    fn mean_of_equal_orientations_is_that_orientation() {
        let r = Quat::from_axis_angle(Vec3::new(1.0, 2.0, 3.0).normalize(), 0.7);
        let mut mean = OrientationMean::new();
        for _ in 0..5 {
            mean.add(r);
        }
        assert!(mean.mean().unwrap().dot(r).abs() > 1.0 - 1e-6);
        assert_eq!(mean.count(), 5);
    }

    #[test]
    fn mean_ignores_quaternion_sign() {
        let r = Quat::from_axis_angle(Vec3::Y, 1.1);
        let mut mean = OrientationMean::new();
        mean.add(r);
        mean.add(-r);
        assert!(mean.mean().unwrap().dot(r).abs() > 1.0 - 1e-6);
    }

    #[test]
    fn mean_treats_flipped_normals_as_the_same_planes() {
        // q and q·g (g a 180° turn about [1−10]) have normals n and −n: the same planes.
        // A plain quaternion mean would tilt the normal by 90°; the aligned mean keeps it.
        let r = Quat::from_axis_angle(Vec3::new(0.3, -1.0, 0.2).normalize(), 0.9);
        let flipped = r * q(STACK_SYMMETRIES[3]);
        assert!((flipped * AXIS_111).dot(r * AXIS_111) < -0.999);
        let mut mean = OrientationMean::new();
        mean.add(r);
        mean.add(flipped);
        let n = mean.mean().unwrap() * AXIS_111;
        assert!(n.dot(r * AXIS_111).abs() > 1.0 - 1e-5, "{n}");
    }

    #[test]
    fn mean_of_symmetric_tilts_is_the_middle() {
        let axis = Vec3::new(1.0, 0.0, -1.0).normalize();
        let mut mean = OrientationMean::new();
        mean.add(Quat::from_axis_angle(axis, 0.4));
        mean.add(Quat::from_axis_angle(axis, -0.4));
        mean.add(Quat::from_axis_angle(axis, 0.1));
        mean.add(Quat::from_axis_angle(axis, -0.1));
        assert!(mean.mean().unwrap().dot(Quat::IDENTITY).abs() > 1.0 - 1e-6);
    }

    #[test]
    fn mean_of_nothing_is_none() {
        assert!(OrientationMean::with_reference(Quat::IDENTITY)
            .mean()
            .is_none());
    }

    #[test]
    fn jitter_angle_has_the_requested_rms() {
        let sigma = 10f64.to_radians();
        let n = 20_000;
        let mut sum_sq = 0.0;
        for i in 0..n {
            let mut rng = Rng::new(4, 0, i);
            let angle =
                f64::from(jitter(Quat::IDENTITY, sigma, &mut rng).angle_between(Quat::IDENTITY));
            sum_sq += angle * angle;
        }
        // E[(σZ)²] = σ²; the estimate of E[Z²] from n draws has standard error √(2/n) ≈ 0.01.
        let rms = (sum_sq / n as f64).sqrt();
        assert!(
            (rms / sigma - 1.0).abs() < 0.03,
            "rms {} deg",
            rms.to_degrees()
        );
        assert_eq!(
            jitter(Quat::IDENTITY, 0.0, &mut Rng::new(0, 0, 0)),
            Quat::IDENTITY
        );
    }
}

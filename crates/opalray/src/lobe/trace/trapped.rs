//! The second Bragg reflection of a reflection the dome traps (`integrator.trapped`): a
//! line's reflection whose way out the surface alone shows dark (total internal reflection
//! sends it back down into the stone) is not walked through the domains
//! ([`Tracer::reflected`]'s cull), yet a line it meets on its way can reflect it again
//! towards the lights: most of the blue the lobe integrator misses against the path tracer
//! (`docs/model.md`, "The lobe integrator"). With `integrator.trapped`, such a reflection
//! is walked out ([`Tracer::follow_out`]) where its bound reaches [`TRAPPED_CUT`].

use super::*;

/// A trapped reflection is walked where its colour's largest tristimulus value (times the
/// eye ray's weight) times the share the dome sends back inside where it first meets it
/// times the brightest light any reflection can see ([`Tracer`]'s `peak`) is at least this,
/// relative to a white diffuser under the light: 0.1 took pinfire's blue from 0.893 to 0.941
/// of the path tracer's and black-opal's from 0.941 to 0.971, for 2 to 2.7 × the render's
/// time; 1 took none of it back (`BENCHMARKS.md`).
const TRAPPED_CUT: f32 = 0.1;

impl Tracer<'_> {
    /// Whether the reflection leaving `out`, its colour's largest tristimulus value times the
    /// eye ray's weight `vivid`, is walked for its second reflections although the surface
    /// alone shows it dark: `integrator.trapped` is set, and its bound (`vivid` times the
    /// Fresnel reflectance where it first meets the surface, total at and past the critical
    /// angle, times the brightest light) reaches [`TRAPPED_CUT`].
    pub(super) fn trapped(&self, out: &Out, vivid: f32) -> bool {
        if !self.setup.trapped || vivid * self.peak < TRAPPED_CUT {
            return false;
        }
        let stone = self.stone;
        let ray = Ray {
            origin: out.face,
            direction: out.dir,
        };
        match stone.exit(&ray, Region::Opal) {
            Some((t_end, Boundary::Surface)) => {
                let normal = stone.shape.normal(ray.at(t_end));
                let f = fresnel_dielectric(out.dir.dot(normal), stone.n_eff, 1.0);
                vivid * f * self.peak >= TRAPPED_CUT
            }
            _ => false,
        }
    }
}

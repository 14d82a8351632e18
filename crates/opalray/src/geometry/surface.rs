//! Optics of a smooth dielectric interface: mirror reflection, Snell refraction and the
//! unpolarised Fresnel reflectance (Born & Wolf, *Principles of Optics*, §1.5.2).

use glam::Vec3;

/// Mirror `d` about the plane with unit normal `n`: `d − 2 (d·n) n`.
pub fn reflect(d: Vec3, n: Vec3) -> Vec3 {
    d - 2.0 * d.dot(n) * n
}

/// Refract unit direction `d` through the interface with unit normal `n` (either side),
/// from index `eta_i` into index `eta_t`. Returns `None` on total internal reflection.
pub fn refract(d: Vec3, n: Vec3, eta_i: f32, eta_t: f32) -> Option<Vec3> {
    let n = if d.dot(n) > 0.0 { -n } else { n };
    let eta = eta_i / eta_t;
    let cos_i = -d.dot(n);
    let sin2_t = eta * eta * (1.0 - cos_i * cos_i).max(0.0);
    if sin2_t >= 1.0 {
        return None;
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    Some((eta * d + (eta * cos_i - cos_t) * n).normalize())
}

/// Unpolarised Fresnel reflectance `(R_s + R_p) / 2` for light meeting the interface at
/// `cos_i = |cos θ_i|` from index `eta_i` into `eta_t`; 1 beyond the critical angle.
pub fn fresnel_dielectric(cos_i: f32, eta_i: f32, eta_t: f32) -> f32 {
    let (rs, rp) = fresnel_dielectric_sp(cos_i, eta_i, eta_t);
    0.5 * (rs + rp)
}

/// Fresnel reflectances `(R_s, R_p)` of s- and p-polarised light (relative to the plane of
/// incidence) meeting the interface at `cos_i = |cos θ_i|` from index `eta_i` into `eta_t`;
/// both 1 beyond the critical angle. The transmittances are `1 − R_s`, `1 − R_p`.
pub fn fresnel_dielectric_sp(cos_i: f32, eta_i: f32, eta_t: f32) -> (f32, f32) {
    let cos_i = cos_i.clamp(0.0, 1.0);
    let sin2_t = (eta_i / eta_t).powi(2) * (1.0 - cos_i * cos_i);
    if sin2_t >= 1.0 {
        return (1.0, 1.0);
    }
    let cos_t = (1.0 - sin2_t).sqrt();
    let rs = (eta_i * cos_i - eta_t * cos_t) / (eta_i * cos_i + eta_t * cos_t);
    let rp = (eta_t * cos_i - eta_i * cos_t) / (eta_t * cos_i + eta_i * cos_t);
    (rs * rs, rp * rp)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn normal_incidence_reflectance_is_the_index_ratio_formula() {
        // ((n1 − n2) / (n1 + n2))² = (0.45 / 2.45)² = 0.033736 for air → 1.45.
        let r = fresnel_dielectric(1.0, 1.0, 1.45);
        assert!((r - 0.033_736).abs() < 1e-5, "{r}");
    }

    #[test]
    fn brewster_angle_has_only_the_s_part() {
        // At Brewster's angle tan θ_B = n2/n1, R_p = 0 and R_s = sin²(θ_i − θ_t) / sin²(θ_i + θ_t)
        // = cos²(2 θ_B) since θ_i + θ_t = 90°.
        let theta_b = (1.5f32).atan();
        let expected = 0.5 * (2.0 * theta_b).cos().powi(2);
        let r = fresnel_dielectric(theta_b.cos(), 1.0, 1.5);
        assert!((r - expected).abs() < 1e-5, "{r} vs {expected}");
    }

    #[test]
    fn brewster_angle_splits_into_s_and_p() {
        // At tan θ_B = n2/n1: R_p = 0 and R_s = ((n² − 1)/(n² + 1))² (Born & Wolf §1.5.3),
        // 0.147929 for n = 1.5.
        let theta_b = (1.5f32).atan();
        let (rs, rp) = fresnel_dielectric_sp(theta_b.cos(), 1.0, 1.5);
        assert!(rp < 1e-7, "R_p {rp}");
        assert!((rs - 0.147_929).abs() < 1e-5, "R_s {rs}");
    }

    #[test]
    fn total_internal_reflection_beyond_the_critical_angle() {
        let critical = (1.0f32 / 1.45).asin();
        assert_eq!(fresnel_dielectric((critical + 0.01).cos(), 1.45, 1.0), 1.0);
        let d = Vec3::new((critical + 0.01).sin(), 0.0, (critical + 0.01).cos());
        assert!(refract(d, -Vec3::Z, 1.45, 1.0).is_none());
    }

    #[test]
    fn refraction_obeys_snell() {
        let theta = 0.6f32;
        let d = Vec3::new(theta.sin(), 0.0, -theta.cos());
        let t = refract(d, Vec3::Z, 1.0, 1.45).unwrap();
        assert!((t.x - theta.sin() / 1.45).abs() < 1e-6);
        assert!((t.length() - 1.0).abs() < 1e-6 && t.z < 0.0);
    }
}

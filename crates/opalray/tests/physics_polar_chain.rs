//! Two Bragg reflections of unpolarised light, by two plates whose planes of incidence are
//! turned by φ about the beam between them, carried by the path tracer's own event code
//! (`PathSpectrum::reflected`: the path's s/p state turned into each plane of incidence, each
//! line's `R_s`, `R_p` applied, the wavelengths drawn from the first line), against an
//! independent computation: each plate's s and p reflectances by an exact transfer-matrix scan
//! of its layer stack (complex characteristic matrices, Macleod's conventions, written here),
//! the turn between the planes done here, and the light's luminance integrated here from the
//! CIE tables in `data/cie`.
//!
//! For unpolarised light two polarising events give exactly (Jones, real amplitudes; the
//! coherence made by the turn never reaches the intensity)
//! `½ [cos²φ (R_s R_s' + R_p R_p') + sin²φ (R_s R_p' + R_p R_s')]` at every wavelength; a
//! tracer that averaged s and p would give `¼ (R_s + R_p)(R_s' + R_p')`, twice too little in
//! one plane at 45° inside (where p is hardly reflected) and far too much with crossed planes.

mod common;

use std::f64::consts::PI;

use glam::Vec3;
use opalray::geometry::reflect;
use opalray::optics::{BraggLine, Families};
use opalray::path::polar::SpState;
use opalray::path::{PathSpectrum, SpectralSampler};
use opalray::scene::{CrystalConfig, Illuminant};
use opalray::spectrum::WavelengthGrid;

/// Layers of each plate: few enough that a line is a few nm wide (so the transfer-matrix
/// integral needs only a modest grid), enough that p and s differ strongly.
const LAYERS: u32 = 200;

/// A complex number, for the characteristic matrices (no crate does it here).
#[derive(Clone, Copy, Debug)]
struct C(f64, f64);

impl std::ops::Add for C {
    type Output = C;
    fn add(self, o: C) -> C {
        C(self.0 + o.0, self.1 + o.1)
    }
}

impl std::ops::Mul for C {
    type Output = C;
    fn mul(self, o: C) -> C {
        C(self.0 * o.0 - self.1 * o.1, self.0 * o.1 + self.1 * o.0)
    }
}

impl C {
    fn scale(self, k: f64) -> C {
        C(self.0 * k, self.1 * k)
    }
    fn norm_sq(self) -> f64 {
        self.0 * self.0 + self.1 * self.1
    }
}

type M2 = [[C; 2]; 2];

fn mul(a: &M2, b: &M2) -> M2 {
    let e = |i: usize, j: usize| a[i][0] * b[0][j] + a[i][1] * b[1][j];
    [[e(0, 0), e(0, 1)], [e(1, 0), e(1, 1)]]
}

/// The square-wave stack of one (111) plate: `LAYERS` periods of two layers `d/2` thick of
/// permittivities `ε̄ ± π g ε̄ / 2` (first Fourier coefficient `g ε̄`, the family's coupling;
/// `docs/model.md`, "The index profile along [111]"), in a medium of `ε̄` on both sides.
struct Plate {
    eps_mean: f64,
    eps_high: f64,
    eps_low: f64,
    d_nm: f64,
}

impl Plate {
    /// `(R_s, R_p)` at `wavelength_nm` for light meeting the layers at `cos_theta` in the
    /// medium `ε̄`: `R = |(η₀ B − C)/(η₀ B + C)|²`, `[B, C] = M [1, η₀]`, M the product of the
    /// layers' characteristic matrices `[[cos β, i sin β / η], [i η sin β, cos β]]`, tilted
    /// admittances `η_s = n cos θ`, `η_p = n / cos θ` (Macleod, *Thin-Film Optical Filters*,
    /// ch. 2).
    fn rs_rp(&self, wavelength_nm: f64, cos_theta: f64) -> (f64, f64) {
        let kappa_sq = self.eps_mean * (1.0 - cos_theta * cos_theta);
        let layer = |eps: f64, p: bool| -> M2 {
            let root = (eps - kappa_sq).sqrt();
            let eta = if p { eps / root } else { root };
            let beta = 2.0 * PI * root * 0.5 * self.d_nm / wavelength_nm;
            let (s, c) = beta.sin_cos();
            [[C(c, 0.0), C(0.0, s / eta)], [C(0.0, eta * s), C(c, 0.0)]]
        };
        let r = |p: bool| {
            let period = mul(&layer(self.eps_high, p), &layer(self.eps_low, p));
            let mut m: M2 = [[C(1.0, 0.0), C(0.0, 0.0)], [C(0.0, 0.0), C(1.0, 0.0)]];
            let mut power = period;
            let mut k = LAYERS;
            while k > 0 {
                if k & 1 == 1 {
                    m = mul(&m, &power);
                }
                power = mul(&power, &power);
                k >>= 1;
            }
            let root = (self.eps_mean - kappa_sq).sqrt();
            let eta0 = if p { self.eps_mean / root } else { root };
            let b = m[0][0] + m[0][1].scale(eta0);
            let c = m[1][0] + m[1][1].scale(eta0);
            let num = b.scale(eta0) + c.scale(-1.0);
            let den = b.scale(eta0) + c;
            num.norm_sq() / den.norm_sq()
        };
        (r(false), r(true))
    }
}

/// `(λ, S(λ) ȳ(λ))` of D65 every nm over `range`, from the CIE tables (D65 every 5 nm,
/// joined linearly).
fn d65_y(range: (f64, f64)) -> Vec<(f64, f64)> {
    let cmf = common::cie_table("cie1931_2deg_xyz_1nm.csv");
    let d65 = common::cie_table("illuminant_d65_5nm.csv");
    cmf.iter()
        .filter(|r| r.0 >= range.0 && r.0 <= range.1)
        .map(|r| (r.0, common::linear_at(&d65, r.0) * r.2))
        .collect()
}

/// `S ȳ` at `w` from the 1 nm samples, linearly.
fn sy_at(table: &[(f64, f64)], w: f64) -> f64 {
    let i = ((w - table[0].0).floor() as usize).min(table.len() - 2);
    let (a, b) = (table[i], table[i + 1]);
    a.1 + (b.1 - a.1) * (w - a.0)
}

/// The luminance of unpolarised white light (D65, Y = 1) after the two plates met at
/// `cos_theta`, their planes turned by `phi`: the closed form of the module notes integrated
/// over wavelength (0.002 nm steps across the lines).
fn exact_luminance(plate: &Plate, cos_theta: f64, phi: f64, centre_nm: f64) -> f64 {
    let sy = d65_y((360.0, 830.0));
    let white: f64 = sy.windows(2).map(|p| 0.5 * (p[0].1 + p[1].1)).sum();
    let (c2, s2) = (phi.cos().powi(2), phi.sin().powi(2));
    let (step, half) = (0.002, 25.0);
    let n = (2.0 * half / step) as usize;
    let mut sum = 0.0;
    for i in 0..n {
        let w = centre_nm - half + (i as f64 + 0.5) * step;
        let (rs, rp) = plate.rs_rp(w, cos_theta);
        let m = 0.5 * (c2 * (rs * rs + rp * rp) + s2 * 2.0 * rs * rp);
        sum += m * sy_at(&sy, w) * step;
    }
    sum / white
}

/// The same luminance by the tracer's events: unpolarised white along `d0` reflected by
/// `line1` (normal `n1`) and then by `line2` (normal `n2`), each in its own plane of
/// incidence, over `paths` stratified draws.
fn traced_luminance(
    sampler: &SpectralSampler,
    (d0, n1, line1): (Vec3, Vec3, BraggLine),
    (n2, line2): (Vec3, BraggLine),
    paths: usize,
) -> f64 {
    let d1 = reflect(d0, n1);
    let mut bins = vec![0.0f32; sampler.grid.bins];
    let mut xyz = [0.0f64; 3];
    for i in 0..paths {
        let u = (i as f64 + 0.5) / paths as f64;
        let white = PathSpectrum::default();
        let once = white.reflected(line1, sampler, u, SpState::s_axis(d0, n1));
        let twice = once.reflected(line2, sampler, u, SpState::s_axis(d1, n2));
        sampler.add_path(&twice, 1.0 / paths as f64, &mut xyz, &mut bins);
    }
    xyz[1]
}

#[test]
fn two_reflections_by_turned_plates_match_the_transfer_matrix_product() {
    let families = Families::new(&CrystalConfig::default(), true);
    let g = families.kinds[0].coupling;
    let n_eff = families.n_eff;
    let eps_mean = n_eff * n_eff;
    let grid = WavelengthGrid {
        min_nm: 360.0,
        max_nm: 830.0,
        bins: 47,
    };
    let sampler = SpectralSampler::new(Illuminant::D65, &grid, 16);
    let d0 = Vec3::new(0.0, 0.0, -1.0);
    let mut failures = Vec::new();
    for theta_deg in [25.0f64, 40.0, 45.0] {
        let theta = theta_deg.to_radians();
        // Spheres whose line at θ is green (560 nm), where the eye sees it best.
        let d_nm = 560.0 / (2.0 * n_eff * theta.cos());
        let plate = Plate {
            eps_mean,
            eps_high: eps_mean * (1.0 + 0.5 * PI * g),
            eps_low: eps_mean * (1.0 - 0.5 * PI * g),
            d_nm,
        };
        let line = BraggLine::new(g, 2.0 * d_nm * n_eff, theta.cos(), f64::from(LAYERS));
        // Plate 1 met at θ; the beam mirrored; plate 2 met at θ too, its plane of incidence
        // turned by φ about the beam from plate 1's.
        let t = theta as f32;
        let n1 = Vec3::new(0.0, t.sin(), t.cos());
        let d1 = reflect(d0, n1);
        let a1 = SpState::s_axis(d0, n1);
        let across = d1.cross(a1).normalize();
        let same_plane = exact_luminance(&plate, theta.cos(), 0.0, line.center_nm);
        for phi_deg in [0.0f64, 30.0, 60.0, 90.0] {
            let phi = phi_deg.to_radians();
            let lateral = across * (phi as f32).cos() + a1 * (phi as f32).sin();
            let n2 = (-d1 * t.cos() + lateral * t.sin()).normalize();
            assert!((-d1.dot(n2) - t.cos()).abs() < 1e-5);
            let traced = traced_luminance(&sampler, (d0, n1, line), (n2, line), 4000);
            let exact = exact_luminance(&plate, theta.cos(), phi, line.center_nm);
            eprintln!("θ {theta_deg}°, φ {phi_deg}°: traced {traced:.7}, exact {exact:.7}");
            // 0.5 % of the same-plane light: the line model against the exact stack
            // (a few 10⁻³ in R) and the draws' noise.
            if (traced - exact).abs() > 0.005 * same_plane {
                failures.push(format!("θ {theta_deg}° φ {phi_deg}°: {traced} vs {exact}"));
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
}

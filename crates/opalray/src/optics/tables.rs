//! The cluster's reflectance tables over wavelength bin × angle (paper §3.1).
//!
//! Input: [`CrystalConfig`] + [`WavelengthGrid`] → output: [`OpticsTables`]. Each row is one
//! angle θ inside the stone between a ray and the cluster's (111) normal, uniform in cos θ;
//! each row holds the bin averages of the specular (Bragg) reflectance R, the coherent
//! transmittance T and the diffuse part D, with R + T + D = 1 (no absorption).
//!
//! Diffuse part: stacking faults, finite domains and the spread of sphere sizes smear the
//! Bragg reflection over a cone of directions. A fraction δ (`diffuse_fraction`) of the
//! coherent reflection leaves diffusely, the rest specularly: `D = δ·R_coh`,
//! `R = (1 − δ)·R_coh`, `T = T_coh`. The diffuse light keeps the colour of the Bragg line (the
//! soft glow of a patch seen off its flash angle); the silica matrix itself is clear.

use rayon::prelude::*;

use super::fine::{integrate_bins, RowPlan};
use super::scan::ClusterOptics;
use crate::error::Result;
use crate::scene::CrystalConfig;
use crate::spectrum::WavelengthGrid;

/// R, T and D of one cluster for every wavelength bin and angle, shared by all clusters.
///
/// Layout: `angles` rows × `grid.bins` columns, row-major, `f32`. Row `i` is
/// `cos θ_i = 1 − i / (angles − 1)`: row 0 normal incidence, the last row grazing.
#[derive(Clone, Debug)]
pub struct OpticsTables {
    /// The wavelength bins of every row.
    pub grid: WavelengthGrid,
    /// Effective index of the cluster: the medium rays travel in inside the stone.
    pub n_eff: f64,
    /// (111) plane spacing `D·√(2/3)`, nm.
    pub d111_nm: f64,
    /// Number of rows (angles), ≥ 90.
    pub angles: usize,
    /// Bin-averaged specular (Bragg) reflectance R in [0, 1], `angles × bins`.
    pub reflectance: Vec<f32>,
    /// Bin-averaged coherent transmittance T in [0, 1], same layout.
    pub transmittance: Vec<f32>,
    /// Bin-averaged diffuse part D in [0, 1], same layout; R + T + D = 1 to rounding.
    pub diffuse: Vec<f32>,
}

impl OpticsTables {
    /// `cos θ` of row `i`: `1 − i / (angles − 1)`.
    pub fn row_cos_theta(&self, i: usize) -> f64 {
        row_cos_theta(i, self.angles)
    }

    /// R, T, D of row `i` (`i < angles`), each `grid.bins` long.
    pub fn row(&self, i: usize) -> (&[f32], &[f32], &[f32]) {
        let bins = self.grid.bins;
        let range = i * bins..(i + 1) * bins;
        (
            &self.reflectance[range.clone()],
            &self.transmittance[range.clone()],
            &self.diffuse[range],
        )
    }

    /// R, T, D at `cos_theta` (callers pass `|cos θ|`; clamped to [0, 1], NaN taken as 0),
    /// linearly interpolated between the two nearest rows. Row `i` corresponds to
    /// `cos θ_i = 1 − i / (angles − 1)` (row 0 normal incidence, the last row grazing).
    /// Writes the first `grid.bins` entries of `r`, `t`, `d` (each must be at least that
    /// long).
    pub fn lookup(&self, cos_theta: f32, r: &mut [f32], t: &mut [f32], d: &mut [f32]) {
        let bins = self.grid.bins;
        let c = if cos_theta.is_nan() {
            0.0
        } else {
            cos_theta.clamp(0.0, 1.0)
        };
        let u = (1.0 - c) * (self.angles - 1) as f32;
        let i0 = (u as usize).min(self.angles - 2);
        let w = u - i0 as f32;
        let (r0, t0, d0) = self.row(i0);
        let (r1, t1, d1) = self.row(i0 + 1);
        let lerp = |out: &mut [f32], a: &[f32], b: &[f32]| {
            for ((o, &x), &y) in out[..bins].iter_mut().zip(a).zip(b) {
                *o = x * (1.0 - w) + y * w;
            }
        };
        lerp(r, r0, r1);
        lerp(t, t0, t1);
        lerp(d, d0, d1);
    }
}

fn row_cos_theta(i: usize, angles: usize) -> f64 {
    1.0 - i as f64 / (angles - 1) as f64
}

/// Build the tables of `crystal` over `grid` (both validated first): `crystal.angles`
/// rows, each integrated from a fine evaluation of the transfer-matrix stack (≤ 1 nm, finer
/// at the Bragg lines), of the indices at each wavelength where `crystal.dispersion` gives a
/// law (row i at `cos θ_i` in the effective medium of that wavelength). Rows are computed in parallel and written by index, so the result
/// does not depend on the number of threads.
pub fn build_optics(crystal: &CrystalConfig, grid: &WavelengthGrid) -> Result<OpticsTables> {
    grid.validate("spectrum")?;
    let optics = ClusterOptics::new(crystal)?;
    let (angles, bins) = (crystal.angles, grid.bins);
    let delta = crystal.diffuse_fraction;
    let mut reflectance = vec![0.0f32; angles * bins];
    let mut transmittance = vec![0.0f32; angles * bins];
    let mut diffuse = vec![0.0f32; angles * bins];
    reflectance
        .par_chunks_mut(bins)
        .zip(transmittance.par_chunks_mut(bins))
        .zip(diffuse.par_chunks_mut(bins))
        .enumerate()
        .for_each_init(
            || (vec![0.0f64; bins], vec![0.0f64; bins]),
            |(r_avg, t_avg), (i, ((r, t), d))| {
                let cos_theta = row_cos_theta(i, angles);
                let plan = RowPlan::new(&optics.stack, &optics.index, cos_theta, grid);
                // The stack of the indices at each wavelength (optics::scan).
                let at = optics.at(cos_theta);
                integrate_bins(grid, &plan, |wl| at.rt_unpolarized(wl), r_avg, t_avg);
                for k in 0..bins {
                    r[k] = ((1.0 - delta) * r_avg[k]) as f32;
                    t[k] = t_avg[k] as f32;
                    d[k] = (delta * r_avg[k]) as f32;
                }
            },
        );
    Ok(OpticsTables {
        grid: *grid,
        n_eff: optics.stack.n_eff,
        d111_nm: optics.stack.d111_nm,
        angles,
        reflectance,
        transmittance,
        diffuse,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn default_tables() -> OpticsTables {
        build_optics(&CrystalConfig::default(), &WavelengthGrid::default()).unwrap()
    }

    #[test]
    fn tables_have_the_documented_shape() {
        let tables = default_tables();
        assert_eq!(tables.angles, 181);
        assert_eq!(tables.reflectance.len(), 181 * 40);
        assert_eq!(tables.row_cos_theta(0), 1.0);
        assert_eq!(tables.row_cos_theta(180), 0.0);
    }

    #[test]
    fn lookup_at_a_row_returns_the_row() {
        let tables = default_tables();
        let (mut r, mut t, mut d) = (vec![0.0; 40], vec![0.0; 40], vec![0.0; 40]);
        for i in [0, 1, 90, 179, 180] {
            tables.lookup(tables.row_cos_theta(i) as f32, &mut r, &mut t, &mut d);
            let (r_row, t_row, d_row) = tables.row(i);
            for k in 0..40 {
                assert!((r[k] - r_row[k]).abs() < 1e-5, "row {i} bin {k}");
                assert!((t[k] - t_row[k]).abs() < 1e-5 && (d[k] - d_row[k]).abs() < 1e-5);
            }
        }
    }

    #[test]
    fn lookup_clamps_out_of_range_and_nan() {
        let tables = default_tables();
        let (mut r, mut t, mut d) = (vec![0.0; 40], vec![0.0; 40], vec![0.0; 40]);
        tables.lookup(1.5, &mut r, &mut t, &mut d);
        assert_eq!(r, tables.row(0).0);
        tables.lookup(f32::NAN, &mut r, &mut t, &mut d);
        assert_eq!(r, tables.row(180).0);
        tables.lookup(-0.3, &mut r, &mut t, &mut d);
        assert_eq!(r, tables.row(180).0);
    }

    #[test]
    fn invalid_crystal_is_refused_with_its_field() {
        let crystal = CrystalConfig {
            sphere_diameter_nm: -250.0,
            ..CrystalConfig::default()
        };
        let err = build_optics(&crystal, &WavelengthGrid::default()).unwrap_err();
        assert!(
            err.to_string().contains("crystal.sphere_diameter_nm"),
            "{err}"
        );
    }
}

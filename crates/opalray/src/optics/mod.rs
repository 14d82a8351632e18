//! scratch optics for render development (replaced by the real stage).
#![allow(missing_docs)]
use crate::spectrum::WavelengthGrid;
#[derive(Clone, Debug)]
pub struct OpticsTables {
    pub grid: WavelengthGrid,
    pub n_eff: f64,
    pub d111_nm: f64,
    pub angles: usize,
    pub reflectance: Vec<f32>,
    pub transmittance: Vec<f32>,
    pub diffuse: Vec<f32>,
}
impl OpticsTables {
    pub fn row(&self, i: usize) -> (&[f32], &[f32], &[f32]) {
        let b = self.grid.bins;
        let r = i * b..(i + 1) * b;
        (
            &self.reflectance[r.clone()],
            &self.transmittance[r.clone()],
            &self.diffuse[r],
        )
    }
    pub fn lookup(&self, cos_theta: f32, r: &mut [f32], t: &mut [f32], d: &mut [f32]) {
        let f = (1.0 - cos_theta.clamp(0.0, 1.0)) * (self.angles - 1) as f32;
        let i = (f as usize).min(self.angles - 2);
        let w = f - i as f32;
        let (r0, t0, d0) = self.row(i);
        let (r1, t1, d1) = self.row(i + 1);
        for b in 0..self.grid.bins {
            r[b] = r0[b] + w * (r1[b] - r0[b]);
            t[b] = t0[b] + w * (t1[b] - t0[b]);
            d[b] = d0[b] + w * (d1[b] - d0[b]);
        }
    }
}
pub fn build_optics(
    c: &crate::scene::CrystalConfig,
    grid: &WavelengthGrid,
) -> crate::Result<OpticsTables> {
    let f = c.filling_fraction;
    let n_eff = (f * c.n_sphere.powi(2) + (1.0 - f) * c.n_matrix.powi(2)).sqrt();
    let d111 = c.sphere_diameter_nm * (2.0f64 / 3.0).sqrt();
    let angles = c.angles;
    let bins = grid.bins;
    let (mut r, mut t, mut d) = (
        vec![0.0; angles * bins],
        vec![0.0; angles * bins],
        vec![0.0; angles * bins],
    );
    for i in 0..angles {
        let cos = 1.0 - i as f64 / (angles - 1) as f64;
        let peak = 2.0 * d111 * n_eff * cos;
        let width = 0.0035 * peak;
        let samples: Vec<(f64, f64)> = (0..4000)
            .map(|k| {
                let l = 300.0 + k as f64 * 0.15;
                (l, (-(((l - peak) / (0.5 * width)).powi(2))).exp() * 0.95)
            })
            .collect();
        let avg = grid.bin_average(&samples);
        for b in 0..bins {
            let rr = avg[b] as f32;
            r[i * bins + b] = rr * (1.0 - c.diffuse_fraction as f32);
            d[i * bins + b] = rr * c.diffuse_fraction as f32;
            t[i * bins + b] = 1.0 - rr;
        }
    }
    Ok(OpticsTables {
        grid: *grid,
        n_eff,
        d111_nm: d111,
        angles,
        reflectance: r,
        transmittance: t,
        diffuse: d,
    })
}

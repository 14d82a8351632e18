//! scratch structure for render development (replaced by the real stage).
#![allow(missing_docs)]
use glam::{Quat, Vec3};
#[repr(u8)]
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Cell {
    Outside = 0,
    Void = 1,
    Cluster = 2,
}
#[derive(Clone, Debug)]
pub struct Structure {
    pub grid: [usize; 3],
    pub semi_axes_mm: [f64; 3],
    pub cells: Vec<Cell>,
    pub orientations: Vec<Quat>,
}
impl Structure {
    pub fn cell_size_mm(&self) -> [f64; 3] {
        [0, 1, 2].map(|a| 2.0 * self.semi_axes_mm[a] / self.grid[a] as f64)
    }
    pub fn index(&self, x: usize, y: usize, z: usize) -> usize {
        x + self.grid[0] * (y + self.grid[1] * z)
    }
    pub fn normal(&self, index: usize) -> Vec3 {
        self.orientations[index] * Vec3::ONE.normalize()
    }
}
pub fn grow_structure(c: &crate::scene::StructureConfig) -> crate::Result<Structure> {
    let [nx, ny, nz] = c.grid;
    let mut cells = vec![Cell::Outside; nx * ny * nz];
    let mut orientations = vec![Quat::IDENTITY; nx * ny * nz];
    for z in 0..nz {
        for y in 0..ny {
            for x in 0..nx {
                let p = Vec3::new(
                    (x as f32 + 0.5) / nx as f32 * 2.0 - 1.0,
                    (y as f32 + 0.5) / ny as f32 * 2.0 - 1.0,
                    (z as f32 + 0.5) / nz as f32 * 2.0 - 1.0,
                );
                let i = x + nx * (y + ny * z);
                if p.length_squared() <= 1.0 {
                    let block = (x / 8) + 100 * (y / 8) + 10000 * (z / 8);
                    let mut rng = crate::sampling::Rng::new(c.seed, 99, block as u64);
                    if rng.uniform() < 0.2 {
                        cells[i] = Cell::Void;
                    } else {
                        cells[i] = Cell::Cluster;
                        orientations[i] = rng.rotation();
                    }
                }
            }
        }
    }
    Ok(Structure {
        grid: c.grid,
        semi_axes_mm: c.semi_axes_mm,
        cells,
        orientations,
    })
}

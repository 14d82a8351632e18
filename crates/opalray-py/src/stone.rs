//! The stone model of the path integrator (domains as geometry) as numpy arrays: each
//! domain's orientation and sphere diameter, and the domain at any point.

use std::sync::Arc;

use numpy::ndarray::{Array1, Array2};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyReadonlyArray2, PyUntypedArrayMethods};
use opalray::optics::FamilyKind;
use opalray::stone::Stone;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use rayon::prelude::*;

use crate::deadline::run_detached;

/// The id `domain_ids` gives a point in potch (inside the stone, in no domain).
pub const POTCH: i32 = -1;
/// The id `domain_ids` gives a point outside the stone.
pub const OUTSIDE: i32 = -2;

/// A stone model, shared with the prepared scene.
#[pyclass(module = "opalray._opalray", frozen)]
pub struct StoneModel {
    pub(crate) stone: Arc<Stone>,
}

#[pymethods]
impl StoneModel {
    /// The domain of every point of `points_mm` (`n × 3` float32, mm in the stone frame),
    /// int32: the domain's index, [`POTCH`] in potch, [`OUTSIDE`] outside the stone.
    fn domain_ids<'py>(
        &self,
        py: Python<'py>,
        points_mm: PyReadonlyArray2<'_, f32>,
    ) -> PyResult<Bound<'py, PyArray1<i32>>> {
        if points_mm.shape()[1] != 3 {
            return Err(PyValueError::new_err(format!(
                "points_mm: {} columns, expected 3 (x, y, z in mm)",
                points_mm.shape()[1]
            )));
        }
        let points: Vec<glam::Vec3> = points_mm
            .as_array()
            .rows()
            .into_iter()
            .map(|r| glam::Vec3::new(r[0], r[1], r[2]))
            .collect();
        let stone = self.stone.clone();
        let ids = run_detached(py, move || {
            points
                .par_iter()
                .map(|&p| match stone.domain_at(p) {
                    Some(d) => d as i32,
                    None if stone.shape.contains(p) => POTCH,
                    None => OUTSIDE,
                })
                .collect::<Vec<i32>>()
        })?;
        Ok(Array1::from(ids).into_pyarray(py))
    }

    /// Lattice → stone rotation of every domain, `domains × 4` float32 unit quaternions
    /// `(x, y, z, w)` (scalar last).
    fn orientations<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f32>> {
        let flat: Vec<f32> = self
            .stone
            .domains
            .iter()
            .flat_map(|d| d.orientation.to_array())
            .collect();
        Array2::from_shape_vec((self.stone.domains.len(), 4), flat)
            .expect("4 per domain")
            .into_pyarray(py)
    }

    /// One (111) plane normal of every domain in the stone frame, `domains × 3` float32:
    /// the orientation applied to the lattice's (1, 1, 1)/√3.
    fn normals<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f32>> {
        let n111 = FamilyKind::F111.normals()[0].normalize();
        let flat: Vec<f32> = self
            .stone
            .domains
            .iter()
            .flat_map(|d| (d.orientation * n111).normalize().to_array())
            .collect();
        Array2::from_shape_vec((self.stone.domains.len(), 3), flat)
            .expect("3 per domain")
            .into_pyarray(py)
    }

    /// Sphere diameter of every domain, nm (float32, `domains` long).
    fn sphere_diameters_nm<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        Array1::from_iter(self.stone.domains.iter().map(|d| d.sphere_diameter_nm)).into_pyarray(py)
    }

    /// `(semi_axes_mm, n_eff)` of the stone.
    fn info(&self) -> ([f32; 3], f32) {
        (self.stone.shape.semi_axes().to_array(), self.stone.n_eff)
    }
}

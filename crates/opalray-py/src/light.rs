//! The light pass's stored light (paper §3.2) as numpy arrays: per storage slot (an inside
//! cell, cluster or void) and lobe, the fluence spectrum, its mean direction and how
//! concentrated that direction is, with the pass's energy ledger.

use numpy::ndarray::{Array1, Array2, Array3};
use numpy::{IntoPyArray, PyArray1, PyArray2, PyArray3};
use opalray::light_pass::{LightField, LOBES};
use pyo3::prelude::*;

/// The light stored by one light pass, with the flat cell index of each slot.
#[pyclass(module = "opalray._opalray", frozen)]
pub struct StoredLight {
    pub(crate) field: LightField,
    /// Flat cell index (`(z·ny + y)·nx + x`) of every slot.
    pub(crate) cell_of_slot: Vec<usize>,
    /// The light's spectrum per bin (irradiance per nm across the beam, before the stone).
    pub(crate) spectrum: Vec<f32>,
}

impl StoredLight {
    fn slots(&self) -> usize {
        self.cell_of_slot.len()
    }
}

#[pymethods]
impl StoredLight {
    /// Flat cell index of every slot (int64, `slots` long), into the structure's
    /// `nz × ny × nx` cells.
    fn cells<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<i64>> {
        Array1::from_iter(self.cell_of_slot.iter().map(|&c| c as i64)).into_pyarray(py)
    }

    /// Fluence spectra, `slots × lobes × bins` float32, power per mm² per nm.
    fn fluence<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f32>> {
        let bins = self.field.grid.bins;
        let flat: Vec<f32> = (0..self.slots())
            .flat_map(|slot| (0..LOBES).map(move |lobe| (slot, lobe)))
            .flat_map(|(slot, lobe)| self.field.fluence(slot, lobe).iter().copied())
            .collect();
        Array3::from_shape_vec((self.slots(), LOBES, bins), flat)
            .expect("slots × lobes × bins")
            .into_pyarray(py)
    }

    /// Mean direction of travel per slot and lobe, `slots × lobes × 3` float32 (unit, or
    /// zero where no light of that lobe arrived).
    fn directions<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f32>> {
        let flat: Vec<f32> = self
            .field
            .directions
            .iter()
            .flat_map(|d| d.to_array())
            .collect();
        Array3::from_shape_vec((self.slots(), LOBES, 3), flat)
            .expect("slots × lobes × 3")
            .into_pyarray(py)
    }

    /// Mean resultant length of the directions, `slots × lobes` float32 in [0, 1].
    fn concentration<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray2<f32>> {
        Array2::from_shape_vec((self.slots(), LOBES), self.field.concentration.clone())
            .expect("slots × lobes")
            .into_pyarray(py)
    }

    /// Centre of every wavelength bin, nm.
    fn wavelengths_nm<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        Array1::from(self.field.grid.centers_nm()).into_pyarray(py)
    }

    /// The light's spectrum per bin, float32 (irradiance across the beam per nm).
    fn light_spectrum<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f32>> {
        Array1::from(self.spectrum.clone()).into_pyarray(py)
    }

    /// The energy ledger as JSON (the fields of `--stats`' `energy`).
    fn ledger_json(&self) -> String {
        serde_json::to_string(&self.field.ledger).expect("the ledger serialises")
    }
}

//! The light-independent stages (structure, optics) of a scene as numpy arrays, and renders
//! of it at any light angle. The render runs on its own thread while the calling thread waits
//! without the GIL, so other Python threads run and Ctrl-C returns at once.

use std::sync::{Arc, OnceLock};

use numpy::ndarray::{Array1, Array2};
use numpy::{IntoPyArray, PyArray1, PyArray2};
use opalray::light_pass::VoxelLayout;
use opalray::stone::Stone;
use opalray::Prepared;
use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyBytes;

use crate::deadline::{run_detached, run_within, TimeLimit, FRAME, PREPARATION};
use crate::frame::Frame;
use crate::light::StoredLight;
use crate::scene::{dict_of, scene_of, to_py_err};
use crate::stone::StoneModel;

/// A prepared scene: the grown structure and the optics tables, computed once; renders at
/// any light angle reuse them (and the stone's cell layout).
#[pyclass(module = "opalray._opalray", frozen)]
pub struct Stages {
    prepared: Arc<Prepared>,
    /// The stone's cells laid out for the passes, built by the first render.
    cells: Arc<OnceLock<VoxelLayout>>,
    /// The stone model: the prepared one (`integrator.method = "path"`) or one built on
    /// first use.
    stone: OnceLock<Arc<Stone>>,
}

/// Run `job` detached (as [`run_detached`]) on a pool of `threads` threads, or on rayon's
/// global pool (every core) when `None`, within `limit` (the frame's render).
fn run_on<T: Send + 'static>(
    py: Python<'_>,
    threads: Option<usize>,
    limit: Option<TimeLimit>,
    job: impl FnOnce() -> T + Send + 'static,
) -> PyResult<T> {
    match threads {
        None => run_within(py, limit, FRAME, move |_| job()),
        Some(n) => {
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(n.max(1))
                .build()
                .map_err(|e| PyRuntimeError::new_err(format!("threads {n}: {e}")))?;
            // The pool's threads look at the call's cancel flag too.
            run_within(py, limit, FRAME, move |stage| {
                let cancel = stage.cancel().clone();
                pool.install(move || cancel.scope(job))
            })
        }
    }
}

impl Stages {
    /// `light_angle_deg`, or the scene's, checked.
    fn angle(&self, light_angle_deg: Option<f64>) -> PyResult<f64> {
        let angle = light_angle_deg.unwrap_or(self.prepared.scene.light.angle_deg);
        if !(angle.is_finite() && (-89.0..=89.0).contains(&angle)) {
            return Err(PyValueError::new_err(format!(
                "light_angle_deg {angle}: the light angle must be within −89° … 89°; try 30"
            )));
        }
        Ok(angle)
    }

    /// Render at `light_angle_deg` (default: the scene's), on `threads` threads (default:
    /// rayon's global pool, every core), within `limit`.
    fn frame(
        &self,
        py: Python<'_>,
        light_angle_deg: Option<f64>,
        threads: Option<usize>,
        limit: Option<TimeLimit>,
    ) -> PyResult<Frame> {
        let angle = self.angle(light_angle_deg)?;
        let prepared = self.prepared.clone();
        let job = move || {
            // By the scene's integrator (the two passes' cells were laid out when prepared).
            let frame = prepared.render(angle);
            let mut scene = prepared.scene.clone();
            scene.light.angle_deg = angle;
            Frame::new(&scene, frame, angle)
        };
        // The same bytes on any number of threads (the core's determinism).
        run_on(py, threads, limit, job)
    }
}

/// `prepare(scene, time_limit_s=None) -> Stages`: grow the structure and build the optics of
/// a scene dict, raising `TimeoutError` if that takes more than `time_limit_s` seconds.
#[pyfunction]
#[pyo3(signature = (scene, time_limit_s=None))]
pub fn prepare(
    py: Python<'_>,
    scene: &Bound<'_, PyAny>,
    time_limit_s: Option<f64>,
) -> PyResult<Stages> {
    let limit = TimeLimit::checked(time_limit_s)?;
    let scene = scene_of(scene)?;
    let prepared = run_within(py, limit, PREPARATION, move |_| opalray::prepare(&scene))?
        .map_err(to_py_err)?;
    Ok(Stages {
        prepared: Arc::new(prepared),
        cells: Arc::new(OnceLock::new()),
        stone: OnceLock::new(),
    })
}

#[pymethods]
impl Stages {
    /// The scene, complete, as a dict.
    fn scene<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        dict_of(py, &self.prepared.scene)
    }

    /// Render one frame at `light_angle_deg` (default: the scene's `light.angle_deg`) on
    /// `threads` threads (default: every core).
    #[pyo3(signature = (light_angle_deg=None, threads=None))]
    fn render(
        &self,
        py: Python<'_>,
        light_angle_deg: Option<f64>,
        threads: Option<usize>,
    ) -> PyResult<Frame> {
        self.frame(py, light_angle_deg, threads, None)
    }

    /// Render one frame and return only its display codes (H × W × 3 bytes, row-major), as
    /// a sweep's frames are; `TimeoutError` past `time_limit_s` seconds.
    #[pyo3(signature = (light_angle_deg, threads=None, time_limit_s=None))]
    fn render_rgb8<'py>(
        &self,
        py: Python<'py>,
        light_angle_deg: f64,
        threads: Option<usize>,
        time_limit_s: Option<f64>,
    ) -> PyResult<Bound<'py, PyBytes>> {
        let limit = TimeLimit::checked(time_limit_s)?;
        let frame = self.frame(py, Some(light_angle_deg), threads, limit)?;
        let codes = opalray::to_display_rgb8(&frame.rgb, &frame.color);
        Ok(PyBytes::new(py, &codes))
    }

    /// One sweep frame of the stone in another pose: tilted by `tilt_deg`, turned by
    /// `turn_deg` and the environment rotated by `rotation_deg` (`camera.tilt_deg`,
    /// `camera.turn_deg`, `environment.rotation_deg`), at the scene's light angle; its
    /// display codes, the bytes `opalray sweep --tilt-from …` gives; `TimeoutError` past
    /// `time_limit_s` seconds.
    #[pyo3(signature = (tilt_deg, turn_deg, rotation_deg, threads=None, time_limit_s=None))]
    fn render_posed_rgb8<'py>(
        &self,
        py: Python<'py>,
        tilt_deg: f64,
        turn_deg: f64,
        rotation_deg: f64,
        threads: Option<usize>,
        time_limit_s: Option<f64>,
    ) -> PyResult<Bound<'py, PyBytes>> {
        let limit = TimeLimit::checked(time_limit_s)?;
        let mut camera = self.prepared.scene.camera.clone();
        camera.tilt_deg = tilt_deg;
        camera.turn_deg = turn_deg;
        let posed = self
            .prepared
            .posed(&camera, rotation_deg)
            .map_err(to_py_err)?;
        let job = move || {
            let frame = posed.render(posed.scene.light.angle_deg);
            opalray::to_display_rgb8(&frame.rgb, &posed.scene.color)
        };
        let codes = run_on(py, threads, limit, job)?;
        Ok(PyBytes::new(py, &codes))
    }

    /// The light pass alone at `light_angle_deg` (default: the scene's), on `threads`
    /// threads: the light stored in every inside cell.
    #[pyo3(signature = (light_angle_deg=None, threads=None))]
    fn light_pass(
        &self,
        py: Python<'_>,
        light_angle_deg: Option<f64>,
        threads: Option<usize>,
    ) -> PyResult<StoredLight> {
        let angle = self.angle(light_angle_deg)?;
        let (prepared, cells) = (self.prepared.clone(), self.cells.clone());
        let light = run_on(py, threads, None, move || {
            // Grown when prepared for the two passes, here for another method.
            let structure = prepared.structure()?;
            let cells = cells.get_or_init(|| VoxelLayout::new(structure));
            Ok::<_, opalray::Error>(StoredLight {
                field: prepared.light_pass_in(cells, angle),
                cell_of_slot: cells.cell_of_slot.clone(),
                spectrum: prepared.light_spectrum(),
            })
        })?;
        light.map_err(to_py_err)
    }

    /// The stone model of the scene (the path integrator's: domains as geometry), built on
    /// first use unless the scene was prepared for the path integrator.
    fn stone(&self, py: Python<'_>) -> PyResult<StoneModel> {
        if let Some(stone) = self.stone.get() {
            return Ok(StoneModel {
                stone: stone.clone(),
            });
        }
        let stone = match &self.prepared.stone {
            Some(stone) => stone.clone(),
            None => {
                let scene = self.prepared.scene.clone();
                Arc::new(run_detached(py, move || Stone::new(&scene))?.map_err(to_py_err)?)
            }
        };
        let stone = self.stone.get_or_init(|| stone).clone();
        Ok(StoneModel { stone })
    }

    /// Seconds of the structure and optics stages, as JSON.
    fn times_json(&self) -> String {
        serde_json::to_string(&self.prepared.times).expect("times serialise")
    }

    /// Cell kinds, `nz × ny × nx` uint8 (indexed `[z, y, x]`): 0 outside, 1 void, 2 cluster.
    fn cell_kinds<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<u8>>> {
        let s = self.prepared.structure().map_err(to_py_err)?;
        Ok(Array1::from_iter(s.cells.iter().map(|&c| c as u8)).into_pyarray(py))
    }

    /// Lattice orientation of every cell as unit quaternions `(x, y, z, w)` (scalar last,
    /// as scipy's `Rotation.from_quat`), flat `cells × 4` float32; identity where no cluster.
    fn orientations<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let s = self.prepared.structure().map_err(to_py_err)?;
        let flat: Vec<f32> = s.orientations.iter().flat_map(|q| q.to_array()).collect();
        Ok(Array2::from_shape_vec((s.cells.len(), 4), flat)
            .expect("4 per cell")
            .into_pyarray(py))
    }

    /// The (111) plane normal of every cell in the stone frame, flat `cells × 3` float32.
    fn normals<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let s = self.prepared.structure().map_err(to_py_err)?;
        let flat: Vec<f32> = (0..s.cells.len())
            .flat_map(|i| s.normal(i).to_array())
            .collect();
        Ok(Array2::from_shape_vec((s.cells.len(), 3), flat)
            .expect("3 per cell")
            .into_pyarray(py))
    }

    /// `(nx, ny, nz, semi_axes_mm, cell_size_mm, stats_json)` of the structure.
    #[allow(clippy::type_complexity)]
    fn structure_info(&self) -> PyResult<(usize, usize, usize, [f64; 3], [f64; 3], String)> {
        let s = self.prepared.structure().map_err(to_py_err)?;
        let stats = serde_json::to_string(&s.stats).expect("stats serialise");
        let [nx, ny, nz] = s.grid;
        Ok((nx, ny, nz, s.semi_axes_mm, s.cell_size_mm(), stats))
    }

    /// One optics table, `angles × bins` float32: `which` is `R`, `T` or `D`.
    fn optics_table<'py>(
        &self,
        py: Python<'py>,
        which: &str,
    ) -> PyResult<Bound<'py, PyArray2<f32>>> {
        let o = self.prepared.optics().map_err(to_py_err)?;
        let data = match which {
            "R" => &o.reflectance,
            "T" => &o.transmittance,
            "D" => &o.diffuse,
            other => {
                return Err(PyValueError::new_err(format!(
                    "optics table `{other}`: choose R, T or D"
                )))
            }
        };
        Ok(
            Array2::from_shape_vec((o.angles, o.grid.bins), data.clone())
                .expect("angles × bins")
                .into_pyarray(py),
        )
    }

    /// `cos θ` inside the stone of every optics row (float64, `angles` long).
    fn optics_cos_theta<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        let o = self.prepared.optics().map_err(to_py_err)?;
        Ok(Array1::from_iter((0..o.angles).map(|i| o.row_cos_theta(i))).into_pyarray(py))
    }

    /// Centre of every wavelength bin, nm.
    fn wavelengths_nm<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyArray1<f64>>> {
        Ok(
            Array1::from(self.prepared.optics().map_err(to_py_err)?.grid.centers_nm())
                .into_pyarray(py),
        )
    }

    /// `(n_eff, d111_nm)` of the cluster.
    fn optics_info(&self) -> PyResult<(f64, f64)> {
        let o = self.prepared.optics().map_err(to_py_err)?;
        Ok((o.n_eff, o.d111_nm))
    }
}

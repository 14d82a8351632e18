//! A rendered frame as numpy arrays, and the files the CLI writes of it.

use std::path::PathBuf;

use numpy::ndarray::{Array1, Array3};
use numpy::{IntoPyArray, PyArray1, PyArray3, PyReadonlyArray3, PyUntypedArrayMethods};
use opalray::output::Provenance;
use opalray::scene::ColorConfig;
use opalray::{RgbImage, Scene, SpectralImage};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

use crate::scene::{scene_of, to_py_err};

/// One rendered frame: the spectral image, its linear RGB, the scene's colour settings (for
/// the display encoding) and the `--stats` JSON of the render.
#[pyclass(module = "opalray._opalray", frozen)]
pub struct Frame {
    pub(crate) spectral: SpectralImage,
    pub(crate) rgb: RgbImage,
    pub(crate) color: ColorConfig,
    pub(crate) stats_json: String,
    /// What made it, written into its files.
    pub(crate) provenance: Provenance,
}

/// Peak resident memory of this process so far, MiB, where the system reports it (as the
/// CLI's `--stats`).
pub fn peak_memory_mb() -> Option<f64> {
    let status = std::fs::read_to_string("/proc/self/status").ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: f64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb / 1024.0)
}

impl Frame {
    /// The frame of a core render of `scene`, with the CLI's `--stats` fields.
    pub fn new(scene: &Scene, frame: opalray::Frame, light_angle_deg: f64) -> Frame {
        let t = frame.times;
        // A scene lit by its environment alone has no light angle and traces no light rays.
        let lit = scene.light.kind != opalray::scene::LightKind::None;
        let mut stats = serde_json::json!({
            "time_s": {"structure": t.structure, "optics": t.optics, "light_pass": t.light_pass,
                       "view_pass": t.view_pass, "color": t.color, "total": t.total()},
            "image": {"width": scene.render.width, "height": scene.render.height,
                      "bins": scene.spectrum.bins},
            "light_angle_deg": lit.then_some(light_angle_deg),
            "void_ratio": frame.void_ratio(),
            "light_rays": lit.then_some(frame.light_rays()),
            "energy": frame.ledger(),
            "peak_memory_mb": peak_memory_mb(),
        });
        // Each method's own section ("path", "stored"), null but the frame's method's.
        if let serde_json::Value::Object(map) = &mut stats {
            map.extend(frame.method_stats(scene.integrator.method()));
        }
        Frame {
            provenance: Provenance::of(scene, &frame),
            spectral: frame.spectral,
            rgb: frame.rgb,
            color: scene.color.clone(),
            stats_json: stats.to_string(),
        }
    }
}

#[pymethods]
impl Frame {
    /// Rebuild a frame from its arrays (unpickling): `spectral` H × W × bins and `rgb`
    /// H × W × 3, both float32, for the scene `scene` (a dict).
    #[staticmethod]
    fn from_arrays(
        spectral: PyReadonlyArray3<'_, f32>,
        rgb: PyReadonlyArray3<'_, f32>,
        scene: &Bound<'_, PyAny>,
        stats_json: String,
    ) -> PyResult<Frame> {
        let scene = scene_of(scene)?;
        let (h, w, bins) = (
            spectral.shape()[0],
            spectral.shape()[1],
            spectral.shape()[2],
        );
        if bins != scene.spectrum.bins || rgb.shape() != [h, w, 3] {
            return Err(PyValueError::new_err(
                "spectral must be H × W × spectrum.bins and rgb H × W × 3",
            ));
        }
        let data = spectral.as_array().iter().copied().collect();
        let mut spectral = SpectralImage::new(0, 0, scene.spectrum);
        (spectral.width, spectral.height, spectral.data) = (w, h, data);
        let flat: Vec<f32> = rgb.as_array().iter().copied().collect();
        let rgb = RgbImage {
            width: w,
            height: h,
            data: flat.chunks_exact(3).map(|p| [p[0], p[1], p[2]]).collect(),
        };
        // The samples rendered, from the statistics (the method's own section), as the
        // frame's files record them.
        let stats: serde_json::Value = serde_json::from_str(&stats_json).unwrap_or_default();
        let spp = opalray::integrator::of(scene.integrator.method())
            .stats_key()
            .and_then(|key| stats[key]["spp"].as_u64())
            .and_then(|n| u32::try_from(n).ok());
        Ok(Frame {
            provenance: Provenance::of_samples(&scene, spp),
            spectral,
            rgb,
            color: scene.color,
            stats_json,
        })
    }

    /// Linear RGB, H × W × 3 float32 (scene-referred: 1 is a white reflector).
    fn rgb<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f32>> {
        let flat: Vec<f32> = self.rgb.data.iter().flatten().copied().collect();
        Array3::from_shape_vec((self.rgb.height, self.rgb.width, 3), flat)
            .expect("width × height × 3 values")
            .into_pyarray(py)
    }

    /// Display codes, H × W × 3 uint8: the bytes of an 8-bit PNG of this frame.
    fn srgb8<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<u8>> {
        let codes = opalray::to_display_rgb8(&self.rgb, &self.color);
        Array3::from_shape_vec((self.rgb.height, self.rgb.width, 3), codes)
            .expect("width × height × 3 codes")
            .into_pyarray(py)
    }

    /// The spectral image, H × W × bins float32 (radiance per nm, bin-averaged).
    fn spectral<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray3<f32>> {
        let s = &self.spectral;
        Array3::from_shape_vec((s.height, s.width, s.grid.bins), s.data.clone())
            .expect("width × height × bins values")
            .into_pyarray(py)
    }

    /// Centre of every wavelength bin, nm (float64, `bins` long).
    fn wavelengths_nm<'py>(&self, py: Python<'py>) -> Bound<'py, PyArray1<f64>> {
        Array1::from(self.spectral.grid.centers_nm()).into_pyarray(py)
    }

    /// The render's statistics as the JSON text of the CLI's `--stats`.
    fn stats_json(&self) -> String {
        self.stats_json.clone()
    }

    /// Write the frame as PNG (sRGB, `color.bit_depth` bits), exactly as `opalray render`.
    fn write_png(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        py.detach(|| opalray::output::write_png(&path, &self.rgb, &self.color, &self.provenance))
            .map_err(to_py_err)
    }

    /// Write the frame as OpenEXR, linear RGB.
    fn write_exr(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        py.detach(|| opalray::output::write_exr(&path, &self.rgb, &self.provenance))
            .map_err(to_py_err)
    }

    /// Write the spectral image as OpenEXR, one channel per bin (`S0.<λ>nm`).
    fn write_spectral_exr(&self, py: Python<'_>, path: PathBuf) -> PyResult<()> {
        py.detach(|| opalray::output::write_spectral_exr(&path, &self.spectral, &self.provenance))
            .map_err(to_py_err)
    }
}

//! A Python dict ↔ [`Scene`]: the dict is read as the TOML value it stands for and
//! deserialized by the core's own serde structs, so defaults, unknown fields and type errors
//! are exactly those of a scene file; then [`Scene::validate`] checks the ranges.

use opalray::{Error, Scene};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};

/// Where a dict's errors say they came from, as a file's path does for a scene file.
const ORIGIN: &str = "scene dict";

/// A core error as the Python exception a user expects: bad input is a `ValueError` with the
/// core's one-line message, a failed file operation an `OSError`.
pub fn to_py_err(err: Error) -> PyErr {
    match err {
        Error::Io { .. } | Error::Encode { .. } => {
            pyo3::exceptions::PyOSError::new_err(err.to_string())
        }
        _ => PyValueError::new_err(err.to_string()),
    }
}

/// The TOML value a Python object stands for; `path` is the dotted field path, for errors.
fn to_toml(obj: &Bound<'_, PyAny>, path: &str) -> PyResult<toml::Value> {
    let at = |what: &str| {
        PyValueError::new_err(format!(
            "{ORIGIN}: field `{path}`: {what}; use a number, a string, a bool, a list or a dict"
        ))
    };
    // bool before int: Python's bool is an int.
    if obj.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(obj.extract()?));
    }
    if obj.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(obj.extract()?));
    }
    if obj.is_instance_of::<PyInt>() || obj.hasattr("__index__")? {
        return match obj.extract::<i64>() {
            Ok(v) => Ok(toml::Value::Integer(v)),
            Err(_) => Err(at("the integer does not fit in 64 bits (TOML's integers)")),
        };
    }
    if obj.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(obj.extract()?));
    }
    if let Ok(dict) = obj.cast::<PyDict>() {
        let mut table = toml::map::Map::new();
        for (key, value) in dict.iter() {
            let key: String = key
                .extract()
                .map_err(|_| at("a dict key is not a string"))?;
            let sub = if path.is_empty() {
                key.clone()
            } else {
                format!("{path}.{key}")
            };
            if value.is_none() {
                // None leaves the field at its default, as leaving it out of a file does.
                continue;
            }
            table.insert(key, to_toml(&value, &sub)?);
        }
        return Ok(toml::Value::Table(table));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let items = obj
            .try_iter()?
            .enumerate()
            .map(|(k, item)| to_toml(&item?, &format!("{path}[{k}]")))
            .collect::<PyResult<Vec<_>>>()?;
        return Ok(toml::Value::Array(items));
    }
    if obj.hasattr("tolist")? {
        // A numpy array or scalar.
        return to_toml(&obj.call_method0("tolist")?, path);
    }
    if obj.hasattr("__float__")? {
        return Ok(toml::Value::Float(obj.extract()?));
    }
    let type_name = obj.get_type().name()?.to_string();
    Err(at(&format!("a Python {type_name} is not a scene value")))
}

/// The TOML value as plain Python objects (dicts, lists, numbers, strings, bools).
fn from_toml<'py>(py: Python<'py>, value: &toml::Value) -> PyResult<Bound<'py, PyAny>> {
    Ok(match value {
        toml::Value::String(s) => PyString::new(py, s).into_any(),
        toml::Value::Integer(v) => v.into_pyobject(py)?.into_any(),
        toml::Value::Float(v) => v.into_pyobject(py)?.into_any(),
        toml::Value::Boolean(v) => PyBool::new(py, *v).to_owned().into_any(),
        toml::Value::Datetime(d) => PyString::new(py, &d.to_string()).into_any(),
        toml::Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(from_toml(py, item)?)?;
            }
            list.into_any()
        }
        toml::Value::Table(table) => {
            let dict = PyDict::new(py);
            for (key, item) in table {
                dict.set_item(key, from_toml(py, item)?)?;
            }
            dict.into_any()
        }
    })
}

/// Deserialize and validate a scene from a TOML value, with the scene file's messages
/// (`field `path`: …`), less the line number a file has and a dict does not.
fn scene_of_value(value: toml::Value) -> opalray::Result<Scene> {
    let scene = Scene::from_toml_value(value, ORIGIN)?;
    // What the scene's method refuses is refused as the scene is made, as in a file.
    opalray::integrator::check(&scene)?;
    Ok(scene)
}

/// The validated [`Scene`] a Python dict describes (missing fields take the defaults).
pub fn scene_of(obj: &Bound<'_, PyAny>) -> PyResult<Scene> {
    if !obj.is_instance_of::<PyDict>() {
        let type_name = obj.get_type().name()?.to_string();
        return Err(PyValueError::new_err(format!(
            "{ORIGIN}: the scene must be a dict of sections, got a {type_name}"
        )));
    }
    scene_of_value(to_toml(obj, "")?).map_err(to_py_err)
}

/// The complete scene as a dict, every field filled in.
pub fn dict_of<'py>(py: Python<'py>, scene: &Scene) -> PyResult<Bound<'py, PyAny>> {
    let value = toml::Value::try_from(scene)
        .map_err(|e| PyValueError::new_err(format!("{ORIGIN}: cannot be written: {e}")))?;
    from_toml(py, &value)
}

/// `normalize(dict) -> dict`: the complete, validated scene a (partial) dict describes.
#[pyfunction]
pub fn normalize<'py>(obj: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    dict_of(obj.py(), &scene_of(obj)?)
}

/// `preset(name) -> dict`: a named preset scene (`paper`).
#[pyfunction]
pub fn preset<'py>(py: Python<'py>, name: &str) -> PyResult<Bound<'py, PyAny>> {
    let scene = opalray::scene::preset(name).map_err(|err| match err {
        // The core names the command's flag; Python's caller passed an argument.
        Error::InvalidArgument { message, .. } => {
            PyValueError::new_err(format!("Scene.preset(name): {message}"))
        }
        other => to_py_err(other),
    })?;
    dict_of(py, &scene)
}

/// `parse_toml(text, origin) -> dict`: a scene file's text, parsed and validated by the core.
#[pyfunction]
pub fn parse_toml<'py>(py: Python<'py>, text: &str, origin: &str) -> PyResult<Bound<'py, PyAny>> {
    let scene = Scene::from_toml_str(text, origin).map_err(to_py_err)?;
    opalray::integrator::check(&scene).map_err(to_py_err)?;
    dict_of(py, &scene)
}

/// `integrator_fields(method) -> list[str] | None`: the `[integrator]` fields `method` takes
/// besides `method` (`None` for a name that is no method: the scene's check names it).
#[pyfunction]
pub fn integrator_fields(method: &str) -> Option<Vec<&'static str>> {
    opalray::scene::Method::ALL
        .into_iter()
        .find(|m| m.name() == method)
        .map(|m| m.fields().to_vec())
}

/// `integrator_reads(method) -> dict | None`: what `method` renders and sees, as the CLI asks
/// the integrators' table: `renders_stone` (the stone model, not the paper's cell grid) and
/// `sees_environment` (`None` for a name that is no method).
#[pyfunction]
pub fn integrator_reads(method: &str) -> Option<std::collections::BTreeMap<&'static str, bool>> {
    let method = opalray::scene::Method::ALL
        .into_iter()
        .find(|m| m.name() == method)?;
    let integrator = opalray::integrator::of(method);
    Some(std::collections::BTreeMap::from([
        ("renders_stone", integrator.renders_stone()),
        ("sees_environment", integrator.sees_environment()),
    ]))
}

/// `to_toml(dict) -> str`: the complete scene as TOML text, as `opalray scene` prints it.
#[pyfunction]
pub fn to_toml_text(obj: &Bound<'_, PyAny>) -> PyResult<String> {
    Ok(scene_of(obj)?.to_toml())
}

/// `read_scene(path) -> dict`: the scene a PNG or EXR image written by opalray records in its
/// header (`opalray scene --from IMAGE`).
#[pyfunction]
pub fn read_scene<'py>(py: Python<'py>, path: std::path::PathBuf) -> PyResult<Bound<'py, PyAny>> {
    let scene = opalray::output::read_provenance(&path)
        .and_then(|p| p.scene(&path))
        .map_err(to_py_err)?;
    dict_of(py, &scene)
}

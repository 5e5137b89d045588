//! `scotopia info` for Python: `scene_info(path, params=None)`.

use std::collections::HashMap;
use std::path::PathBuf;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyList, PyString};
use scotopia_scene::{load_scene_with, LoadOptions, Resolution, SceneInfo};

/// `res` as load options: an int width (keeping the film's aspect), a
/// (width, height) pair, or a "W"/"WxH" string.
pub fn load_options(res: Option<&Bound<'_, PyAny>>) -> PyResult<LoadOptions> {
    let Some(res) = res else {
        return Ok(LoadOptions::default());
    };
    let text = if let Ok(w) = res.extract::<i64>() {
        w.to_string()
    } else if let Ok((w, h)) = res.extract::<(i64, i64)>() {
        format!("{w}x{h}")
    } else if let Ok(s) = res.extract::<String>() {
        s
    } else {
        return Err(PyValueError::new_err(
            "res: give an int width, a (width, height) pair or 'WxH'",
        ));
    };
    let resolution = Resolution::parse(&text).map_err(PyValueError::new_err)?;
    Ok(LoadOptions {
        resolution: Some(resolution),
        ..LoadOptions::default()
    })
}

/// Loads a Mitsuba 3 XML scene and returns what `scotopia info --json`
/// prints, as a dict. `params` sets `$name` parameters; `res` overrides
/// the film size as in `render`.
#[pyfunction]
#[pyo3(signature = (path, params = None, res = None))]
fn scene_info<'py>(
    py: Python<'py>,
    path: PathBuf,
    params: Option<HashMap<String, String>>,
    res: Option<Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyDict>> {
    let options = load_options(res.as_ref())?;
    let scene = load_scene_with(&path, &params.unwrap_or_default(), &options)
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    // Through a `Value`, as the CLI prints it: the same keys and numbers.
    let info = serde_json::to_value(SceneInfo::of(&scene))
        .map_err(|e| PyValueError::new_err(e.to_string()))?;
    Ok(python_value(py, &info)?.cast_into::<PyDict>()?)
}

/// A JSON value as the Python object `json.loads` would make of it.
pub(crate) fn python_value<'py>(
    py: Python<'py>,
    v: &serde_json::Value,
) -> PyResult<Bound<'py, PyAny>> {
    use serde_json::Value;
    Ok(match v {
        Value::Null => py.None().into_bound(py),
        Value::Bool(b) => PyBool::new(py, *b).to_owned().into_any(),
        Value::Number(n) => match (n.as_u64(), n.as_i64()) {
            (Some(u), _) => u.into_pyobject(py)?.into_any(),
            (None, Some(i)) => i.into_pyobject(py)?.into_any(),
            _ => n.as_f64().unwrap_or(f64::NAN).into_pyobject(py)?.into_any(),
        },
        Value::String(t) => PyString::new(py, t).into_any(),
        Value::Array(items) => {
            let list = PyList::empty(py);
            for item in items {
                list.append(python_value(py, item)?)?;
            }
            list.into_any()
        }
        Value::Object(entries) => {
            let dict = PyDict::new(py);
            for (k, item) in entries {
                dict.set_item(k, python_value(py, item)?)?;
            }
            dict.into_any()
        }
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(scene_info, m)?)?;
    Ok(())
}

//! `scotopia info` for Python: `scene_info(path, params=None)`.

use std::collections::HashMap;
use std::path::PathBuf;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
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
    let i = SceneInfo::of(&scene);
    let d = PyDict::new(py);
    d.set_item("shapes", i.shapes)?;
    d.set_item("triangles", i.triangles)?;
    d.set_item("instances", i.instances)?;
    d.set_item("materials", i.materials)?;
    d.set_item("emitters", i.emitters)?;
    let camera = PyDict::new(py);
    camera.set_item("fov_degrees", [i.fov_degrees.0, i.fov_degrees.1])?;
    camera.set_item("thin_lens", i.thin_lens)?;
    camera.set_item("irradiancemeter_shape", i.meter_shape)?;
    d.set_item("camera", camera)?;
    let film = PyDict::new(py);
    film.set_item("width", i.width)?;
    film.set_item("height", i.height)?;
    film.set_item("filter", &i.filter)?;
    d.set_item("film", film)?;
    d.set_item("samples_per_pixel", i.samples_per_pixel)?;
    d.set_item("max_depth", i.max_depth)?;
    let lights = PyList::empty(py);
    for l in &i.lights {
        let ld = PyDict::new(py);
        ld.set_item("type", l.kind)?;
        ld.set_item("watts", l.power.watts)?;
        ld.set_item("lumens", l.power.lumens)?;
        lights.append(ld)?;
    }
    d.set_item("lights", lights)?;
    let media = PyList::empty(py);
    for m in &i.media {
        let md = PyDict::new(py);
        md.set_item("type", m.kind)?;
        // A heterogeneous medium's σ_t is its largest, not at 550 nm.
        let key = if m.kind == "heterogeneous" {
            "sigma_t_max"
        } else {
            "sigma_t_550"
        };
        md.set_item(key, m.sigma_t)?;
        md.set_item("albedo_550", m.albedo)?;
        md.set_item("g", m.g)?;
        md.set_item("optical_thickness", m.optical_thickness)?;
        let grids = PyList::empty(py);
        for g in &m.grids {
            let gd = PyDict::new(py);
            gd.set_item("parameter", g.parameter)?;
            gd.set_item("cells", g.cells.to_vec())?;
            gd.set_item("channels", g.channels)?;
            grids.append(gd)?;
        }
        md.set_item("grids", grids)?;
        media.append(md)?;
    }
    d.set_item("media", media)?;
    d.set_item("warnings", &i.warnings)?;
    Ok(d)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(scene_info, m)?)?;
    Ok(())
}

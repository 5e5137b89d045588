//! `scotopia road` for Python: EN 13201-3's luminance method.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray2};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use scotopia_render::integrator::{RenderOptions, Road};
use scotopia_render::math::Vec3;

/// EN 13201-3's luminance method on a straight road of a Mitsuba 3 XML
/// scene (the `scotopia road` verb): the grid of the field that starts
/// at `start` (on the road's first edge) and runs `spacing` m along
/// `along`, `lanes` lanes of `lane_width` m across `across`; one observer
/// per lane 60 m before it, 1.5 m up, looking along the road 1° down.
/// Returns a dict: `grid` (N × 3 points), `lane`, `row` (N), `L_cdm2`,
/// `L_cdm2_se`, `SP`, `Lmes_cdm2` (observers × N: what each lane's
/// observer sees at each point) and `observers`, a list of dicts with
/// `lane`, `eye`, `L_av_cdm2`, `U_o`, `U_l` (along its lane's centre
/// line), `Lv_cdm2` (the veiling luminance of the luminaires below the
/// roof's 20° cut-off) and `TI_percent` (None for a dark road). `age`:
/// the observer's, for TI's k; `direct`: light straight from the
/// luminaires alone, as the standard counts it. The GIL is released while
/// it measures; Ctrl-C raises KeyboardInterrupt.
#[pyfunction]
#[pyo3(signature = (path, start, along, across, spacing, lanes = 2, lane_width = 3.5, up = (0.0, 1.0, 0.0), age = 23.0, direct = false, spp = None, seed = 0, params = None))]
#[allow(clippy::too_many_arguments)]
fn road<'py>(
    py: Python<'py>,
    path: PathBuf,
    start: (f32, f32, f32),
    along: (f32, f32, f32),
    across: (f32, f32, f32),
    spacing: f32,
    lanes: u32,
    lane_width: f32,
    up: (f32, f32, f32),
    age: f64,
    direct: bool,
    spp: Option<u32>,
    seed: u32,
    params: Option<HashMap<String, String>>,
) -> PyResult<Bound<'py, PyDict>> {
    let err = |e: String| PyValueError::new_err(e);
    if !(age.is_finite() && (0.0..=120.0).contains(&age)) {
        return Err(err(format!("age {age}: give years from 0 to 120")));
    }
    if spp == Some(0) {
        return Err(err("spp must be positive".into()));
    }
    let v = |(x, y, z): (f32, f32, f32)| Vec3::new(x, y, z);
    let road = Road {
        start: v(start),
        along: v(along),
        across: v(across),
        up: v(up),
        spacing,
        lanes,
        lane_width,
    }
    .checked()
    .map_err(|e| err(e.to_string()))?;
    let scene = crate::measure::sensorless_scene(&path, params)?;
    let options = RenderOptions {
        spp,
        seed,
        ..RenderOptions::default()
    };
    let cancel = AtomicBool::new(false);
    let (report, interrupted) = crate::interrupt::interruptible(py, &cancel, || {
        scotopia_cli::road::evaluate(&scene, road, &options, (age, direct), &cancel)
    });
    if let Some(e) = interrupted {
        return Err(e);
    }
    let report = report.map_err(|e| err(format!("{e:#}")))?;
    let d = PyDict::new(py);
    let n = report.grid.len();
    let grid: Vec<f64> = report
        .grid
        .iter()
        .flat_map(|g| g.p.to_array().map(f64::from))
        .collect();
    let grid = Array2::from_shape_vec((n, 3), grid).map_err(|e| err(e.to_string()))?;
    d.set_item("grid", grid.into_pyarray(py))?;
    d.set_item(
        "lane",
        report
            .grid
            .iter()
            .map(|g| g.lane)
            .collect::<Vec<u32>>()
            .into_pyarray(py),
    )?;
    d.set_item(
        "row",
        report
            .grid
            .iter()
            .map(|g| g.row)
            .collect::<Vec<u32>>()
            .into_pyarray(py),
    )?;
    let per = |k: usize| -> PyResult<Bound<'py, PyArray2<f64>>> {
        let values: Vec<f64> = report
            .observers
            .iter()
            .flat_map(|o| o.points.iter().map(move |p| p[k]))
            .collect();
        let a = Array2::from_shape_vec((report.observers.len(), n), values)
            .map_err(|e| PyValueError::new_err(e.to_string()))?;
        Ok(a.into_pyarray(py))
    };
    for (k, name) in ["L_cdm2", "L_cdm2_se", "SP", "Lmes_cdm2"]
        .into_iter()
        .enumerate()
    {
        d.set_item(name, per(k)?)?;
    }
    let observers = PyList::empty(py);
    for o in &report.observers {
        let od = PyDict::new(py);
        od.set_item("lane", o.lane)?;
        od.set_item("eye", o.eye.to_vec())?;
        od.set_item("L_av_cdm2", o.l_av)?;
        od.set_item("U_o", o.u_o)?;
        od.set_item("U_l", o.u_l)?;
        od.set_item("Lv_cdm2", o.l_v)?;
        od.set_item("TI_percent", o.ti)?;
        observers.append(od)?;
    }
    d.set_item("observers", observers)?;
    Ok(d)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(road, m)?)?;
    Ok(())
}

//! `scotopia glare` for Python: glare ratings from a fisheye luminance
//! picture.

use std::path::PathBuf;

use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::PyDict;

use crate::scene::python_value;

/// Glare ratings of the fisheye luminance picture `image` (an X, Y, Z
/// OpenEXR, Y in cd/m²), as `scotopia glare --json` prints them: a dict
/// with `Ev_lx` (vertical illuminance at the lens), `UGR` (CIE 117; None
/// without a source), `DGP` (Wienold & Christoffersen 2006), `Lveil_cdm2`
/// (CIE 146, for an observer of `age`), the mean, threshold and background
/// luminances, and `sources` (each with its luminance, solid angle,
/// direction, angle from the line of sight and position index).
/// `projection` ("angular" or "equisolid") and `fov` (degrees across the
/// width) default to the picture's metadata; sources are the pixels above
/// `threshold` times the mean luminance. `output` also writes the picture
/// with the sources outlined (PNG).
///
/// (Named `glare_ratings` in the extension, whose `glare` is the vision
/// pipeline's stage; `scotopia.glare` is this.)
#[pyfunction(name = "glare_ratings")]
#[pyo3(signature = (image, projection = None, fov = None, threshold = 5.0, age = 25.0, output = None))]
fn glare<'py>(
    py: Python<'py>,
    image: PathBuf,
    projection: Option<&str>,
    fov: Option<f64>,
    threshold: f64,
    age: f64,
    output: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let err = |e: anyhow::Error| PyValueError::new_err(format!("{e:#}"));
    let (figures, eye, lum) =
        scotopia_cli::glare::figures(&image, projection, fov, threshold, age).map_err(err)?;
    if let Some(out) = output {
        scotopia_cli::glare::write_outlined(&out, &lum, &figures, &eye).map_err(err)?;
    }
    let json = scotopia_cli::glare::to_json(&figures, &eye);
    Ok(python_value(py, &json)?.cast_into::<PyDict>()?)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(glare, m)?)?;
    Ok(())
}

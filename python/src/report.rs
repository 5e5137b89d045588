//! The Python side of `scotopia spectrum`: the colorimetry report and plot,
//! and the round-trip accuracy measurement.

use std::path::PathBuf;

use pyo3::prelude::*;
use pyo3::types::PyDict;
use scotopia_color::upsample::round_trip as measure_round_trip;
use scotopia_color::{Colorimetry, RgbSpace, UpsampleMethod};
use scotopia_image::{display_colour, plot_spectrum};

use crate::spectrum::Spectrum;
use crate::to_py;

/// The colorimetry `scotopia spectrum --json` prints, as a dict: xyz, xy,
/// vprime, sp_ratio, cct, duv, wavelengths, values. With `plot`, also draws
/// the spectrum to that PNG.
#[pyfunction]
#[pyo3(signature = (spectrum, plot = None))]
fn colorimetry<'py>(
    py: Python<'py>,
    spectrum: &Spectrum,
    plot: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let c = Colorimetry::of(&spectrum.inner);
    if let Some(path) = plot {
        let linear = RgbSpace::Srgb.def().xyz_to_rgb(c.xyzv.xyz());
        plot_spectrum(&path, &spectrum.inner, display_colour(linear))
            .map_err(|e| pyo3::exceptions::PyOSError::new_err(e.to_string()))?;
    }
    let d = PyDict::new(py);
    d.set_item("xyz", [c.xyzv.x, c.xyzv.y, c.xyzv.z])?;
    d.set_item("xy", c.xy)?;
    d.set_item("vprime", c.xyzv.v)?;
    d.set_item("sp_ratio", c.sp_ratio)?;
    d.set_item("cct", c.cct.map(|t| t.kelvin))?;
    d.set_item("duv", c.cct.map(|t| t.duv))?;
    d.set_item("wavelengths", c.wavelengths)?;
    d.set_item("values", c.values)?;
    Ok(d)
}

/// Reflectance round trip of an RGB → spectrum method on the n³ grid of the
/// RGB cube: dict of max_de, mean_de (CIEDE2000), worst_rgb, out_of_range, count.
#[pyfunction]
#[pyo3(signature = (method = "jakob2019", space = "srgb", n = 32))]
fn round_trip<'py>(
    py: Python<'py>,
    method: &str,
    space: &str,
    n: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let method = UpsampleMethod::from_name(method).map_err(to_py)?;
    let space = RgbSpace::from_name(space).map_err(to_py)?;
    let r = py
        .detach(|| measure_round_trip(method, space, n))
        .map_err(to_py)?;
    let d = PyDict::new(py);
    d.set_item("max_de", r.max_de)?;
    d.set_item("mean_de", r.mean_de)?;
    d.set_item("worst_rgb", r.worst_rgb)?;
    d.set_item("out_of_range", r.out_of_range)?;
    d.set_item("count", r.count)?;
    Ok(d)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(colorimetry, m)?)?;
    m.add_function(wrap_pyfunction!(round_trip, m)?)?;
    Ok(())
}

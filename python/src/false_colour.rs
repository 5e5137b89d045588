//! `scotopia display --false-colour` for Python.

use std::path::PathBuf;

use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3, PyReadonlyArray3};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use scotopia_vision::false_colour::{false_colour as draw, Mapped, Scale};

use crate::vision::pixels;

/// A false-colour map of an X, Y, Z, V′ array (H × W × 4) with a labelled
/// scale bar below it: `quantity` "luminance" (cd/m², of a radiance
/// render), "mesopic" (CIE 191 mesopic luminance per pixel, cd/m²) or
/// "illuminance" (lx, of a `quantity="illuminance"` render: the array
/// carries no metadata, so saying which is the caller's). `range` (lo, hi)
/// defaults to 0 to the 99th percentile (with `log`, the three decades
/// below it). Returns the picture as an (H + bar) × W × 3 uint8 array;
/// `output` also writes it as a PNG.
#[pyfunction]
#[pyo3(signature = (image, quantity = "luminance", range = None, log = false, output = None))]
fn false_colour<'py>(
    py: Python<'py>,
    image: PyReadonlyArray3<f32>,
    quantity: &str,
    range: Option<(f64, f64)>,
    log: bool,
    output: Option<PathBuf>,
) -> PyResult<Bound<'py, PyArray3<u8>>> {
    let err = |e: String| PyValueError::new_err(e);
    let mapped = Mapped::from_name(quantity)
        .ok_or_else(|| err(format!("quantity '{quantity}': use {}", Mapped::NAMES)))?;
    let (w, h, px) = pixels::<4>(&image)?;
    let values = mapped.values(&px);
    let scale = match range {
        Some((lo, hi)) => Scale { lo, hi, log },
        None => Scale::auto(&values, log),
    };
    if !scale.is_valid() {
        return Err(err(format!(
            "range ({}, {}): needs finite lo < hi{}",
            scale.lo,
            scale.hi,
            if log { ", lo > 0 with log" } else { "" }
        )));
    }
    let (pw, ph, rgb) = py.detach(|| draw(&values, w, h, &scale, mapped.unit()));
    if let Some(path) = output {
        scotopia_image::write_png_rgb8(&path, pw as u32, ph as u32, &rgb)
            .map_err(|e| err(e.to_string()))?;
    }
    let a = Array3::from_shape_vec((ph, pw, 3), rgb).map_err(|e| err(e.to_string()))?;
    Ok(a.into_pyarray(py))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(false_colour, m)?)?;
    Ok(())
}

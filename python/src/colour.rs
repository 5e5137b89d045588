//! Colour spaces, adaptation, CIELAB, CIEDE2000, Oklab and CCT for Python.

use numpy::PyArrayDyn;
use pyo3::prelude::*;
use scotopia_color::space::{self, Cat};
use scotopia_color::{cct, RgbSpace};

use crate::arrays::{map3, map3_pair, Numbers};
use crate::to_py;

fn space_def(name: &str) -> PyResult<&'static scotopia_color::RgbColorSpace> {
    Ok(RgbSpace::from_name(name).map_err(to_py)?.def())
}

/// Linear RGB of `space` → XYZ (white has Y = 1).
#[pyfunction]
#[pyo3(signature = (rgb, space = "srgb"))]
fn rgb_to_xyz<'py>(
    py: Python<'py>,
    rgb: Numbers<'py>,
    space: &str,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let d = space_def(space)?;
    map3(py, rgb, |v| d.rgb_to_xyz(v))
}

/// XYZ → linear RGB of `space`.
#[pyfunction]
#[pyo3(signature = (xyz, space = "srgb"))]
fn xyz_to_rgb<'py>(
    py: Python<'py>,
    xyz: Numbers<'py>,
    space: &str,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let d = space_def(space)?;
    map3(py, xyz, |v| d.xyz_to_rgb(v))
}

/// The 3×3 XYZ←RGB matrix of `space`, derived from its primaries and white.
#[pyfunction]
#[pyo3(signature = (space = "srgb"))]
fn rgb_to_xyz_matrix(space: &str) -> PyResult<[[f64; 3]; 3]> {
    Ok(space_def(space)?.xyz_from_rgb.0)
}

/// The white point (x, y) of `space`.
#[pyfunction]
#[pyo3(signature = (space = "srgb"))]
fn white_point(space: &str) -> PyResult<[f64; 2]> {
    Ok(space_def(space)?.white)
}

/// Adapts XYZ seen under white `src` (XYZ) to white `dst`; `method`:
/// bradford, cat02, vonkries.
#[pyfunction]
#[pyo3(signature = (xyz, src, dst, method = "bradford"))]
fn chromatic_adaptation<'py>(
    py: Python<'py>,
    xyz: Numbers<'py>,
    src: [f64; 3],
    dst: [f64; 3],
    method: &str,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let m = space::adaptation_matrix(src, dst, Cat::from_name(method).map_err(to_py)?);
    map3(py, xyz, |v| m.apply(v))
}

/// XYZ → CIELAB relative to `white` (XYZ; default D65 with Y = 1).
#[pyfunction]
#[pyo3(signature = (xyz, white = [0.3127 / 0.3290, 1.0, (1.0 - 0.3127 - 0.3290) / 0.3290]))]
fn xyz_to_lab<'py>(
    py: Python<'py>,
    xyz: Numbers<'py>,
    white: [f64; 3],
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    map3(py, xyz, |v| space::xyz_to_lab(v, white))
}

/// CIELAB → XYZ relative to `white`.
#[pyfunction]
#[pyo3(signature = (lab, white = [0.3127 / 0.3290, 1.0, (1.0 - 0.3127 - 0.3290) / 0.3290]))]
fn lab_to_xyz<'py>(
    py: Python<'py>,
    lab: Numbers<'py>,
    white: [f64; 3],
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    map3(py, lab, |v| space::lab_to_xyz(v, white))
}

/// CIEDE2000 between CIELAB arrays of the same shape (..., 3).
#[pyfunction]
fn delta_e_2000<'py>(
    py: Python<'py>,
    lab1: Numbers<'py>,
    lab2: Numbers<'py>,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    map3_pair(py, lab1, lab2, space::delta_e_2000)
}

/// XYZ → xyY (black keeps the D65 chromaticity).
#[pyfunction]
fn xyz_to_xyy<'py>(py: Python<'py>, xyz: Numbers<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    map3(py, xyz, |v| space::xyz_to_xyy(v, [0.3127, 0.3290]))
}

/// A Python function applying a per-colour conversion over arrays (..., 3).
macro_rules! unary3 {
    ($(#[doc = $doc:literal] $name:ident => $f:expr;)*) => {$(
        #[doc = $doc]
        #[pyfunction]
        fn $name<'py>(py: Python<'py>, v: Numbers<'py>) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
            map3(py, v, $f)
        }
    )*};
}

unary3! {
    /// XYZ (D65, Y = 1 for white) → Oklab.
    xyz_to_oklab => space::xyz_to_oklab;
    /// Oklab → XYZ.
    oklab_to_xyz => space::oklab_to_xyz;
    /// Oklab → OkLCh (hue in degrees).
    oklab_to_oklch => space::oklab_to_oklch;
    /// OkLCh → Oklab.
    oklch_to_oklab => space::oklch_to_oklab;
    /// xyY → XYZ.
    xyy_to_xyz => space::xyy_to_xyz;
}

/// (CCT in K, Duv) of a chromaticity (x, y), Ohno 2013; None outside 1000–100000 K.
#[pyfunction]
fn cct_from_xy(xy: [f64; 2]) -> Option<(f64, f64)> {
    cct::cct_from_xy(xy).map(|c| (c.kelvin, c.duv))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(rgb_to_xyz, m)?)?;
    m.add_function(wrap_pyfunction!(xyz_to_rgb, m)?)?;
    m.add_function(wrap_pyfunction!(rgb_to_xyz_matrix, m)?)?;
    m.add_function(wrap_pyfunction!(white_point, m)?)?;
    m.add_function(wrap_pyfunction!(chromatic_adaptation, m)?)?;
    m.add_function(wrap_pyfunction!(xyz_to_lab, m)?)?;
    m.add_function(wrap_pyfunction!(lab_to_xyz, m)?)?;
    m.add_function(wrap_pyfunction!(delta_e_2000, m)?)?;
    m.add_function(wrap_pyfunction!(xyz_to_oklab, m)?)?;
    m.add_function(wrap_pyfunction!(oklab_to_xyz, m)?)?;
    m.add_function(wrap_pyfunction!(oklab_to_oklch, m)?)?;
    m.add_function(wrap_pyfunction!(oklch_to_oklab, m)?)?;
    m.add_function(wrap_pyfunction!(cct_from_xy, m)?)?;
    m.add_function(wrap_pyfunction!(xyz_to_xyy, m)?)?;
    m.add_function(wrap_pyfunction!(xyy_to_xyz, m)?)?;
    Ok(())
}

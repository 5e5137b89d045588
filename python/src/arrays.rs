//! Applying per-colour functions over numpy arrays of shape (..., 3).

use numpy::ndarray::{ArrayD, Axis};
use numpy::{AllowTypeChange, IntoPyArray, PyArrayDyn, PyArrayLikeDyn};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// An array of numbers as the functions take it: any numeric dtype, a
/// list or a scalar, converted to float64 (a float32 image works as is).
pub type Numbers<'py> = PyArrayLikeDyn<'py, f64, AllowTypeChange>;

/// Calls `f` on each length-3 vector along the last axis of `a`.
pub fn map3<'py>(
    py: Python<'py>,
    a: Numbers<'py>,
    f: impl Fn([f64; 3]) -> [f64; 3],
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let a = a.as_array();
    if a.ndim() == 0 || a.shape()[a.ndim() - 1] != 3 {
        return Err(PyValueError::new_err(format!(
            "expected an array whose last axis has 3 components, got shape {:?}",
            a.shape()
        )));
    }
    let mut out = ArrayD::<f64>::zeros(a.shape());
    let last = Axis(a.ndim() - 1);
    for (src, mut dst) in a.lanes(last).into_iter().zip(out.lanes_mut(last)) {
        let r = f([src[0], src[1], src[2]]);
        for k in 0..3 {
            dst[k] = r[k];
        }
    }
    Ok(out.into_pyarray(py))
}

/// Calls `f` on pairs of length-3 vectors along the last axes of `a` and `b`
/// (same shape), giving one value per pair.
pub fn map3_pair<'py>(
    py: Python<'py>,
    a: Numbers<'py>,
    b: Numbers<'py>,
    f: impl Fn([f64; 3], [f64; 3]) -> f64,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    let (a, b) = (a.as_array(), b.as_array());
    if a.shape() != b.shape() || a.ndim() == 0 || a.shape()[a.ndim() - 1] != 3 {
        return Err(PyValueError::new_err(format!(
            "expected two arrays of the same shape (..., 3), got {:?} and {:?}",
            a.shape(),
            b.shape()
        )));
    }
    let last = Axis(a.ndim() - 1);
    let values: Vec<f64> = a
        .lanes(last)
        .into_iter()
        .zip(b.lanes(last))
        .map(|(x, y)| f([x[0], x[1], x[2]], [y[0], y[1], y[2]]))
        .collect();
    let shape = &a.shape()[..a.ndim() - 1];
    // The lane count equals the product of the leading dimensions.
    let out = ArrayD::from_shape_vec(shape, values).expect("lane count matches shape");
    Ok(out.into_pyarray(py))
}

/// Calls `f` on every element of `a`.
pub fn map1<'py>(
    py: Python<'py>,
    a: Numbers<'py>,
    f: impl Fn(f64) -> f64,
) -> Bound<'py, PyArrayDyn<f64>> {
    a.as_array().mapv(f).into_pyarray(py)
}

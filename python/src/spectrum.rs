//! `scotopia.Spectrum` and the observer functions.

use std::path::PathBuf;

use numpy::ndarray::ArrayD;
use numpy::{IntoPyArray, PyArrayDyn, PyReadonlyArray1};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use scotopia_color as color;
use scotopia_color::{cie, SpectrumKind, UpsampleMethod};

use crate::arrays::{map1, Numbers};
use crate::to_py;

/// A spectral function of wavelength in nm. Emission is spectral radiance in
/// W·sr⁻¹·m⁻²·nm⁻¹. Call it on a number or numpy array of wavelengths.
#[pyclass(module = "scotopia", frozen)]
pub struct Spectrum {
    pub inner: color::Spectrum,
}

#[pymethods]
impl Spectrum {
    /// The same value at every wavelength.
    #[staticmethod]
    fn constant(value: f32) -> Self {
        Self {
            inner: color::Spectrum::Constant(value),
        }
    }

    /// Piecewise linear through (wavelength, value) samples, zero outside them.
    #[staticmethod]
    fn tabulated(
        wavelengths: PyReadonlyArray1<'_, f64>,
        values: PyReadonlyArray1<'_, f64>,
    ) -> PyResult<Self> {
        let l = wavelengths.as_array().iter().map(|&v| v as f32).collect();
        let v = values.as_array().iter().map(|&v| v as f32).collect();
        Ok(Self {
            inner: color::Tabulated::new(l, v).map_err(to_py)?.into(),
        })
    }

    /// Black-body spectral radiance (W·sr⁻¹·m⁻²·nm⁻¹) at `kelvin`.
    #[staticmethod]
    fn blackbody(kelvin: f32) -> PyResult<Self> {
        Ok(Self {
            inner: color::Spectrum::blackbody(kelvin).map_err(to_py)?,
        })
    }

    /// CIE daylight (D series) at a CCT of 4000–25000 K, relative power.
    #[staticmethod]
    fn daylight(kelvin: f64) -> PyResult<Self> {
        Ok(Self {
            inner: cie::daylight(kelvin).map_err(to_py)?.into(),
        })
    }

    /// A CIE illuminant by name: A, D50, D55, D65, D75, E, F1 … F12.
    #[staticmethod]
    fn illuminant(name: &str) -> PyResult<Self> {
        Ok(Self {
            inner: cie::illuminant(name).map_err(to_py)?,
        })
    }

    /// A spectrum file (CSV or .spd, `wavelength,value` per line).
    #[staticmethod]
    fn from_file(path: PathBuf) -> PyResult<Self> {
        Ok(Self {
            inner: color::io::read_spectrum_file(&path).map_err(to_py)?.into(),
        })
    }

    /// The spectrum of a linear RGB colour. `space`: srgb, p3, rec2020,
    /// acescg; `method`: jakob2019, smits, primaries; `kind`: reflectance,
    /// unbounded, illuminant.
    #[staticmethod]
    #[pyo3(signature = (rgb, space = "srgb", method = "jakob2019", kind = "reflectance"))]
    fn from_rgb(rgb: [f32; 3], space: &str, method: &str, kind: &str) -> PyResult<Self> {
        let space = color::RgbSpace::from_name(space).map_err(to_py)?;
        let method = UpsampleMethod::from_name(method).map_err(to_py)?;
        let kind = SpectrumKind::from_name(kind).map_err(to_py)?;
        Ok(Self {
            inner: color::rgb_to_spectrum(rgb, space, method, kind).map_err(to_py)?,
        })
    }

    /// Values at `wavelengths` (nm), an array of any shape.
    fn __call__<'py>(
        &self,
        py: Python<'py>,
        wavelengths: Numbers<'py>,
    ) -> Bound<'py, PyArrayDyn<f64>> {
        map1(py, wavelengths, |l| self.inner.eval(l as f32) as f64)
    }

    /// Absolute (X, Y, Z, V′): cd/m² and scotopic cd/m².
    fn xyzv(&self) -> (f64, f64, f64, f64) {
        let c = color::photometry::spectrum_to_xyzv(&self.inner);
        (c.x, c.y, c.z, c.v)
    }

    /// The spectrum multiplied by `factor`.
    fn scaled(&self, factor: f32) -> Self {
        Self {
            inner: self.inner.scaled(factor),
        }
    }

    fn __repr__(&self) -> String {
        match &self.inner {
            color::Spectrum::Constant(v) => format!("Spectrum.constant({v})"),
            color::Spectrum::Tabulated(t) => {
                format!("Spectrum(tabulated, {} samples)", t.wavelengths().len())
            }
            color::Spectrum::Blackbody(b) => format!("Spectrum.blackbody({})", b.kelvin),
            color::Spectrum::Sigmoid(s) => format!("Spectrum(sigmoid {:?})", s.coeffs),
        }
    }
}

/// CIE 1931 2° x̄, ȳ, z̄ at `wavelengths`: an array of shape (..., 3).
#[pyfunction]
fn cmfs<'py>(py: Python<'py>, wavelengths: Numbers<'py>) -> Bound<'py, PyArrayDyn<f64>> {
    let w = wavelengths.as_array();
    let mut shape = w.shape().to_vec();
    shape.push(3);
    let values: Vec<f64> = w
        .iter()
        .flat_map(|&l| cie::xyz_bar(l as f32).map(|v| v as f64))
        .collect();
    // values holds exactly 3 per wavelength.
    ArrayD::from_shape_vec(shape, values)
        .expect("3 per wavelength")
        .into_pyarray(py)
}

/// CIE 1951 scotopic V′ at `wavelengths`.
#[pyfunction]
fn vprime<'py>(py: Python<'py>, wavelengths: Numbers<'py>) -> Bound<'py, PyArrayDyn<f64>> {
    map1(py, wavelengths, |l| cie::v_prime(l as f32) as f64)
}

/// Planck's law: spectral radiance in W·sr⁻¹·m⁻²·nm⁻¹ at `wavelengths` (nm).
#[pyfunction]
fn planck<'py>(
    py: Python<'py>,
    wavelengths: Numbers<'py>,
    kelvin: f64,
) -> PyResult<Bound<'py, PyArrayDyn<f64>>> {
    if !(kelvin.is_finite() && kelvin > 0.0) {
        return Err(PyValueError::new_err(format!(
            "temperature must be positive, got {kelvin} K"
        )));
    }
    Ok(map1(py, wavelengths, |l| {
        color::spectrum::planck(l, kelvin)
    }))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(cmfs, m)?)?;
    m.add_function(wrap_pyfunction!(vprime, m)?)?;
    m.add_function(wrap_pyfunction!(planck, m)?)?;
    Ok(())
}

//! `scotopia.bsdf`: one BSDF from Mitsuba XML, evaluated and sampled by
//! the renderer's own code, for comparison with another renderer.
//! Directions are in the local shading frame (z = normal) and both point
//! away from the surface; `eval` is f·|cos θ_o| (Mitsuba's conventions).

use numpy::ndarray::{Array1, Array2, ArrayView2};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArrayDyn,
};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use scotopia_color::{SampledWavelengths, LAMBDA_MAX, LAMBDA_MIN};
use scotopia_render::bsdf::{Bsdf as Inner, Transport};
use scotopia_render::math::Vec3;

/// The wavelengths the renderer carries together along a path.
const CLUSTER: usize = 4;

/// eval's result: f·|cos θ_o| (N × K) and pdf (N).
type Evaluated<'py> = (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>);

/// sample's result: wo (N × 3), weight (N × K), pdf (N), delta (N).
type Sampled<'py> = (
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray2<f64>>,
    Bound<'py, PyArray1<f64>>,
    Bound<'py, PyArray1<bool>>,
);

fn err(e: impl ToString) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// A BSDF built by the scene loader from one `<bsdf>` element (or a
/// `<scene>` of definitions whose last top-level `<bsdf>` is taken).
#[pyclass(module = "scotopia", frozen)]
pub struct Bsdf {
    inner: Inner,
    warnings: Vec<String>,
}

/// An N × 3 array of unit directions.
fn directions(name: &str, a: &ArrayView2<f64>, n: Option<usize>) -> PyResult<Vec<Vec3>> {
    let (rows, cols) = a.dim();
    if cols != 3 || n.is_some_and(|n| n != rows) {
        return Err(err(format!(
            "{name}: expected an N × 3 array{}, got shape {:?}",
            n.map(|n| format!(" with N = {n}")).unwrap_or_default(),
            a.shape()
        )));
    }
    a.outer_iter()
        .enumerate()
        .map(|(i, r)| {
            let v = Vec3::new(r[0] as f32, r[1] as f32, r[2] as f32);
            let len = (r[0] * r[0] + r[1] * r[1] + r[2] * r[2]).sqrt();
            if !len.is_finite() || (len - 1.0).abs() > 1e-4 {
                return Err(err(format!(
                    "{name}[{i}] = {:?} is not a unit vector (length {len})",
                    [r[0], r[1], r[2]]
                )));
            }
            Ok(v)
        })
        .collect()
}

/// Wavelengths as N rows of K values, from an array of shape (N,) or (N, K).
fn wavelengths(a: &PyReadonlyArrayDyn<f64>, n: usize) -> PyResult<Vec<Vec<f32>>> {
    let a = a.as_array();
    let k = match a.shape() {
        [rows] if *rows == n => 1,
        [rows, k] if *rows == n && *k > 0 => *k,
        s => {
            return Err(err(format!(
                "wavelengths: expected shape ({n},) or ({n}, K), got {s:?}"
            )))
        }
    };
    let flat: Vec<f64> = a.iter().copied().collect();
    if let Some(bad) = flat
        .iter()
        .find(|&&l| !(f64::from(LAMBDA_MIN)..=f64::from(LAMBDA_MAX)).contains(&l))
    {
        return Err(err(format!(
            "wavelengths: {bad} nm is outside {LAMBDA_MIN}–{LAMBDA_MAX} nm"
        )));
    }
    Ok(flat
        .chunks_exact(k)
        .map(|r| r.iter().map(|&l| l as f32).collect())
        .collect())
}

/// The renderer's clusters covering `lambdas`: groups of four, the last
/// one padded with its first wavelength.
fn clusters(lambdas: &[f32]) -> Vec<SampledWavelengths<CLUSTER>> {
    lambdas
        .chunks(CLUSTER)
        .map(|c| {
            let l = std::array::from_fn(|i| c.get(i).copied().unwrap_or(c[0]));
            SampledWavelengths::new(l, [1.0 / (LAMBDA_MAX - LAMBDA_MIN); CLUSTER])
        })
        .collect()
}

fn mode(importance: bool) -> Transport {
    if importance {
        Transport::Importance
    } else {
        Transport::Radiance
    }
}

/// Texture coordinates: N × 2, or zeros (Mitsuba's default) when absent.
fn uvs(uv: Option<PyReadonlyArray2<f64>>, n: usize) -> PyResult<Vec<[f32; 2]>> {
    let Some(uv) = uv else {
        return Ok(vec![[0.0; 2]; n]);
    };
    let uv = uv.as_array();
    if uv.dim() != (n, 2) {
        return Err(err(format!(
            "uv: expected shape ({n}, 2), got {:?}",
            uv.shape()
        )));
    }
    Ok(uv
        .outer_iter()
        .map(|r| [r[0] as f32, r[1] as f32])
        .collect())
}

fn unit_interval(name: &str, values: impl Iterator<Item = f64>) -> PyResult<()> {
    for v in values {
        if !(0.0..=1.0).contains(&v) {
            return Err(err(format!("{name}: {v} is outside [0, 1]")));
        }
    }
    Ok(())
}

#[pymethods]
impl Bsdf {
    /// Builds the BSDF of Mitsuba XML `xml` with the scene loader.
    #[new]
    fn new(xml: &str) -> PyResult<Self> {
        let (inner, warnings) = scotopia_scene::bsdf_from_xml(xml).map_err(err)?;
        Ok(Self { inner, warnings })
    }

    /// What the loader warned about (properties scotopia ignores, …).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    /// Whether every lobe is a delta (nothing to `eval`).
    #[getter]
    fn is_delta(&self) -> bool {
        self.inner.is_delta()
    }

    /// f(wi, wo)·|cos θ_o| at each row's wavelengths (N × K) and the
    /// density of `sample` producing wo (N, for each row's first
    /// wavelength). `wavelengths` has shape (N,) or (N, K), in nm.
    #[pyo3(signature = (wi, wo, wavelengths, importance = false, uv = None))]
    fn eval<'py>(
        &self,
        py: Python<'py>,
        wi: PyReadonlyArray2<'py, f64>,
        wo: PyReadonlyArray2<'py, f64>,
        wavelengths: PyReadonlyArrayDyn<'py, f64>,
        importance: bool,
        uv: Option<PyReadonlyArray2<'py, f64>>,
    ) -> PyResult<Evaluated<'py>> {
        let wi = directions("wi", &wi.as_array(), None)?;
        let n = wi.len();
        let wo = directions("wo", &wo.as_array(), Some(n))?;
        let lambdas = self::wavelengths(&wavelengths, n)?;
        let uv = uvs(uv, n)?;
        let k = lambdas.first().map_or(1, Vec::len);
        let mut value = Array2::<f64>::zeros((n, k));
        let mut pdf = Array1::<f64>::zeros(n);
        for i in 0..n {
            let cl = clusters(&lambdas[i]);
            for (c, wl) in cl.iter().enumerate() {
                let v = self.inner.eval(wl, uv[i], wi[i], wo[i], mode(importance));
                for j in 0..CLUSTER.min(k - c * CLUSTER) {
                    value[[i, c * CLUSTER + j]] = f64::from(v[j]);
                }
            }
            pdf[i] = f64::from(self.inner.pdf_at(&cl[0], uv[i], wi[i], wo[i]));
        }
        Ok((value.into_pyarray(py), pdf.into_pyarray(py)))
    }

    /// Samples a continuation per row: returns wo (N × 3), the weight
    /// f·|cos θ_o|/pdf per wavelength (N × K, K ≤ 4: one cluster), the
    /// density (1 for a delta lobe) and whether the lobe is a delta. A row
    /// without a sample has wo = 0, weight 0 and density 0.
    #[pyo3(signature = (wi, wavelengths, u_lobe, u, importance = false, uv = None))]
    #[allow(clippy::too_many_arguments)]
    fn sample<'py>(
        &self,
        py: Python<'py>,
        wi: PyReadonlyArray2<'py, f64>,
        wavelengths: PyReadonlyArrayDyn<'py, f64>,
        u_lobe: PyReadonlyArray1<'py, f64>,
        u: PyReadonlyArray2<'py, f64>,
        importance: bool,
        uv: Option<PyReadonlyArray2<'py, f64>>,
    ) -> PyResult<Sampled<'py>> {
        let wi = directions("wi", &wi.as_array(), None)?;
        let n = wi.len();
        let lambdas = self::wavelengths(&wavelengths, n)?;
        let k = lambdas.first().map_or(1, Vec::len);
        if k > CLUSTER {
            return Err(err(format!(
                "wavelengths: one sample serves at most {CLUSTER} wavelengths, got {k}"
            )));
        }
        let (u_lobe, u) = (u_lobe.as_array(), u.as_array());
        if u_lobe.len() != n || u.dim() != (n, 2) {
            return Err(err(format!(
                "u_lobe and u: expected shapes ({n},) and ({n}, 2), got {:?} and {:?}",
                u_lobe.shape(),
                u.shape()
            )));
        }
        unit_interval("u_lobe", u_lobe.iter().copied())?;
        unit_interval("u", u.iter().copied())?;
        let uv = uvs(uv, n)?;
        let mut wo = Array2::<f64>::zeros((n, 3));
        let mut weight = Array2::<f64>::zeros((n, k));
        let mut pdf = Array1::<f64>::zeros(n);
        let mut delta = Array1::<bool>::from_elem(n, false);
        for i in 0..n {
            let wl = clusters(&lambdas[i])[0];
            let s = self.inner.sample(
                &wl,
                uv[i],
                wi[i],
                u_lobe[i] as f32,
                [u[[i, 0]] as f32, u[[i, 1]] as f32],
                mode(importance),
            );
            if let Some(s) = s {
                wo[[i, 0]] = f64::from(s.wo.x);
                wo[[i, 1]] = f64::from(s.wo.y);
                wo[[i, 2]] = f64::from(s.wo.z);
                for j in 0..k {
                    weight[[i, j]] = f64::from(s.weight[j]);
                }
                pdf[i] = f64::from(s.pdf);
                delta[i] = s.delta;
            }
        }
        Ok((
            wo.into_pyarray(py),
            weight.into_pyarray(py),
            pdf.into_pyarray(py),
            delta.into_pyarray(py),
        ))
    }
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Bsdf>()?;
    Ok(())
}

//! `scotopia render` for Python: `render(path, ...)` returns the X, Y, Z,
//! V′ image as an H × W × 4 float32 array and the metadata as a dict.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::atomic::AtomicBool;
use std::time::Duration;

use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3};
use pyo3::exceptions::{PyMemoryError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use scotopia_image::Meta;
use scotopia_render::film::Checkpoint;
use scotopia_render::integrator::{
    render_resumable, time_limit, Checkpointing, Quantity, RenderError, RenderOptions, Tracer,
};
use scotopia_render::output::{render_metadata, write_spectral_exr, write_xyzv_exr};
use scotopia_render::scene::IntegratorKind;
use scotopia_render::wavelength::WavelengthStrategy;
use scotopia_scene::load_scene_with;

use crate::scene::load_options;

/// Renders a Mitsuba 3 XML scene (the `scotopia render` verb). Returns
/// `(image, metadata)`: image[y, x] = (X, Y, Z, V′) in cd/m² and scotopic
/// cd/m². `output` also writes the OpenEXR, `spectral` the spectral
/// OpenEXR (Fichet et al. 2021) with `bands` bands; `integrator` is
/// "path" or "bdpt" (default: the scene's); `res` overrides the film size
/// (an int width keeping the aspect, a (width, height) pair, or "WxH").
/// `checkpoint` names a file where the film's exact sums are saved every
/// `checkpoint_every` seconds and at the end; with `resume` the render
/// continues from it when it is there (the same scene, parameters and
/// options; `spp` may grow), bit-identical to an uninterrupted render.
/// `quantity` "illuminance" renders the illuminance (lx) at the first
/// surface each pixel sees instead of radiance. The GIL is released while
/// rendering.
#[pyfunction]
#[pyo3(signature = (path, spp = None, time = None, seed = 0, wavelengths = "swc", cluster = 4, params = None, output = None, spectral = None, bands = 47, integrator = None, res = None, checkpoint = None, checkpoint_every = 60.0, resume = false, tracer = "scalar", quantity = "radiance"))]
#[allow(clippy::too_many_arguments)]
fn render<'py>(
    py: Python<'py>,
    path: PathBuf,
    spp: Option<u32>,
    time: Option<f64>,
    seed: u32,
    wavelengths: &str,
    cluster: usize,
    params: Option<HashMap<String, String>>,
    output: Option<PathBuf>,
    spectral: Option<PathBuf>,
    bands: usize,
    integrator: Option<&str>,
    res: Option<Bound<'py, PyAny>>,
    checkpoint: Option<PathBuf>,
    checkpoint_every: f64,
    resume: bool,
    tracer: &str,
    quantity: &str,
) -> PyResult<(Bound<'py, PyArray3<f32>>, Bound<'py, PyDict>)> {
    let err = |e: String| PyValueError::new_err(e);
    let strategy = wavelength_strategy(wavelengths)?;
    let integrator = match integrator {
        Some(name) => Some(
            IntegratorKind::from_name(name)
                .ok_or_else(|| err(format!("integrator '{name}': use path or bdpt")))?,
        ),
        None => None,
    };
    let tracer = Tracer::from_name(tracer)
        .ok_or_else(|| err(format!("tracer '{tracer}': use wavefront or scalar")))?;
    let quantity = Quantity::from_name(quantity).ok_or_else(|| {
        err(format!(
            "quantity '{quantity}': use radiance or illuminance"
        ))
    })?;
    let time_limit = match time {
        Some(t) => Some(time_limit(t).map_err(|e| err(format!("time {e}")))?),
        None => None,
    };
    if !(checkpoint_every.is_finite() && (0.0..=1e9).contains(&checkpoint_every)) {
        return Err(err(format!(
            "checkpoint_every {checkpoint_every}: give 0 to 1e9 seconds"
        )));
    }
    let load = load_options(res.as_ref())?;
    let params = params.unwrap_or_default();
    let scene = load_scene_with(&path, &params, &load).map_err(|e| err(e.to_string()))?;
    let options = RenderOptions {
        spp,
        time_limit,
        seed,
        strategy,
        cluster,
        bands: spectral.is_some().then_some(bands),
        integrator,
        only_strategy: None,
        tracer,
        quantity,
    };
    let key = scotopia_scene::checkpoint_key(&path, &params, &load, &options)
        .map_err(|e| err(format!("{}: {e}", path.display())))?;
    let resume_from = match &checkpoint {
        Some(file) if resume && file.exists() => Some(Checkpoint::read(file).map_err(err)?),
        _ => None,
    };
    let save = |c: &Checkpoint| checkpoint.as_ref().map_or(Ok(()), |f| c.write(f));
    let checkpoints = checkpoint.as_ref().map(|_| Checkpointing {
        key,
        resume: resume_from,
        every: Duration::from_secs_f64(checkpoint_every),
        save: &save,
    });
    let rendered = py
        .detach(|| {
            render_resumable(
                &scene,
                &options,
                &AtomicBool::new(false),
                &|_, _| {},
                checkpoints,
            )
        })
        .map_err(|e| match e {
            RenderError::TooLarge(_) => PyMemoryError::new_err(e.to_string()),
            _ => err(e.to_string()),
        })?;
    let meta = render_metadata(
        &scene,
        &options,
        &rendered.facts(),
        &path.display().to_string(),
    );
    if let Some(out) = output {
        write_xyzv_exr(&out, &rendered, &meta).map_err(|e| err(e.to_string()))?;
    }
    if let Some(out) = spectral {
        write_spectral_exr(&out, &rendered, &meta).map_err(|e| err(e.to_string()))?;
    }
    let (w, h) = (rendered.film.width as usize, rendered.film.height as usize);
    let flat: Vec<f32> = rendered.film.xyzv().into_iter().flatten().collect();
    let image = Array3::from_shape_vec((h, w, 4), flat).map_err(|e| err(e.to_string()))?;
    let d = PyDict::new(py);
    for (k, v) in meta {
        match v {
            Meta::Text(t) => d.set_item(k, t)?,
            Meta::F32(f) => d.set_item(k, f)?,
            Meta::I32(i) => d.set_item(k, i)?,
        }
    }
    d.set_item("nonfiniteSamples", rendered.nonfinite)?;
    d.set_item("nonfiniteSplats", rendered.nonfinite_splats)?;
    d.set_item("collapsedFraction", rendered.collapsed_fraction())?;
    Ok((image.into_pyarray(py), d))
}

/// What `render` and `measure` check first: the SIMD level
/// (`SCOTOPIA_SIMD`) and the wavelength strategy's name.
pub(crate) fn wavelength_strategy(name: &str) -> PyResult<WavelengthStrategy> {
    scotopia_render::simd::Level::init().map_err(|e| PyValueError::new_err(e.to_string()))?;
    WavelengthStrategy::from_name(name).ok_or_else(|| {
        PyValueError::new_err(format!("wavelengths '{name}': use swc, hero or single"))
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(render, m)?)?;
    Ok(())
}

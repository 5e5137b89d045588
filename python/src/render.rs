//! `scotopia render` for Python: `render(path, ...)` returns the X, Y, Z,
//! V′ image as an H × W × 4 float32 array and the metadata as a dict.

use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use numpy::ndarray::{Array2, Array3};
use numpy::{IntoPyArray, PyArray3};
use pyo3::exceptions::{PyMemoryError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use scotopia_image::Meta;
use scotopia_render::film::Checkpoint;
use scotopia_render::integrator::{
    checkpoint_interval, render_with, time_limit, Checkpointing, ClusterSize, Guiding, Hooks,
    Quantity, RenderError, RenderOptions, Shard, Tracer,
};
use scotopia_render::output::{
    render_metadata, write_spectral_exr, write_xyzv_exr, write_xyzv_pixels,
};
use scotopia_render::scene::IntegratorKind;
use scotopia_render::wavelength::WavelengthStrategy;
use scotopia_scene::{load_scene_tracked, load_scene_with};

use crate::scene::load_options;

/// Renders a Mitsuba 3 XML scene (the `scotopia render` verb). Returns
/// `(image, metadata)`: image[y, x] = (X, Y, Z, V′) in cd/m² and scotopic
/// cd/m². `output` also writes the OpenEXR, `spectral` the spectral
/// OpenEXR (Fichet et al. 2021) with `bands` bands, `radiance` a Radiance
/// picture (RGBE, luminance exact in Radiance's 179 lm/W units, for
/// evalglare); `integrator` is
/// "path" or "bdpt" (default: the scene's); `res` overrides the film size
/// (an int width keeping the aspect, a (width, height) pair, or "WxH").
/// `checkpoint` names a file where the film's exact sums are saved every
/// `checkpoint_every` seconds and at the end; with `resume` the render
/// continues from it when it is there (the same scene, files it reads,
/// parameters and options; `spp` may grow), bit-identical to an
/// uninterrupted render; a damaged checkpoint, or one saved before a file
/// the scene reads was edited, is a `ValueError`.
/// `quantity` "illuminance" renders the illuminance (lx) at the first
/// surface each pixel sees instead of radiance; "melanopic-edi" the same
/// with the melanopic equivalent daylight illuminance (CIE S 026, lx) as
/// the fourth channel in place of V′. `guiding` "on" learns
/// where light arrives (the first 16 spp, kept) and draws half of each diffuse
/// bounce from it; with bdpt, half of each light path's first direction
/// (docs/guiding.md; not with the wavefront tracer or illuminance). The
/// GIL is released while
/// rendering. Ctrl-C (or any signal handler that raises) stops the render
/// at its next pass: the outputs and the checkpoint are written with what
/// it has, then KeyboardInterrupt is raised, as the CLI exits. `resume`
/// without `checkpoint` is a ValueError.
#[pyfunction]
#[pyo3(signature = (path, spp = None, time = None, seed = 0, wavelengths = "swc", cluster = 4, params = None, output = None, spectral = None, bands = 47, integrator = None, res = None, checkpoint = None, checkpoint_every = 60.0, resume = false, tracer = "scalar", quantity = "radiance", guiding = "off", radiance = None))]
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
    guiding: &str,
    radiance: Option<PathBuf>,
) -> PyResult<(Bound<'py, PyArray3<f32>>, Bound<'py, PyDict>)> {
    let err = |e: String| PyValueError::new_err(e);
    let named = Named::parse(
        wavelengths,
        cluster,
        integrator,
        [tracer, quantity, guiding],
    )?;
    let time_limit = match time {
        Some(t) => Some(time_limit(t).map_err(|e| err(format!("time {e}")))?),
        None => None,
    };
    let checkpoint_every =
        checkpoint_interval(checkpoint_every).map_err(|e| err(format!("checkpoint_every {e}")))?;
    if resume && checkpoint.is_none() {
        return Err(err(
            "resume=True needs checkpoint, the file to resume from (and to save to)".into(),
        ));
    }
    let load = load_options(res.as_ref())?;
    let params = params.unwrap_or_default();
    let (scene, files) =
        load_scene_tracked(&path, &params, &load).map_err(|e| err(e.to_string()))?;
    check_outputs(&files, [&output, &spectral, &checkpoint]).map_err(err)?;
    let options = RenderOptions {
        spp,
        time_limit,
        seed,
        bands: spectral.is_some().then_some(bands),
        ..named.options()
    };
    if let Some(file) = &checkpoint {
        Checkpoint::check_path(file).map_err(err)?;
    }
    let key = match &checkpoint {
        Some(_) => scotopia_scene::checkpoint_key(&files, &params, &load, &options).map_err(err)?,
        None => scotopia_scene::CheckpointKey {
            key: 0,
            sources: Vec::new(),
        },
    };
    let resume_from = match &checkpoint {
        Some(file) if resume && file.exists() => {
            let (c, saved) = Checkpoint::read_with(file).map_err(err)?;
            if let Some(why) = key.refusal(c.key, &saved) {
                return Err(err(format!("{}: cannot resume: {why}", file.display())));
            }
            Some(c)
        }
        _ => None,
    };
    let save = |c: &Checkpoint| {
        checkpoint
            .as_ref()
            .map_or(Ok(()), |f| c.write_with(f, &key.sources))
    };
    let checkpoints = checkpoint.as_ref().map(|_| Checkpointing {
        key: key.key,
        resume: resume_from,
        every: checkpoint_every,
        save: &save,
    });
    // Ctrl-C ends the render at its pass boundary (the checkpoint saved);
    // the outputs are written, then KeyboardInterrupt raised.
    let cancel = AtomicBool::new(false);
    let (rendered, interrupted) = crate::interrupt::interruptible(py, &cancel, || {
        let hooks = Hooks {
            checkpoints,
            ..Hooks::new(&cancel)
        };
        render_with(&scene, &options, hooks)
    });
    let rendered = rendered.map_err(|e| match e {
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
    if let Some(out) = radiance {
        let (w, h) = (rendered.film.width as usize, rendered.film.height as usize);
        let view = scotopia_render::output::radiance_view(&scene);
        let px = rendered.film.xyzv();
        scotopia_image::radiance::write_radiance_hdr(&out, w, h, &px, view.as_deref())
            .map_err(|e| err(e.to_string()))?;
    }
    if let Some(e) = interrupted {
        return Err(e);
    }
    let (w, h) = (rendered.film.width as usize, rendered.film.height as usize);
    let flat: Vec<f32> = rendered.film.xyzv().into_iter().flatten().collect();
    let image = Array3::from_shape_vec((h, w, 4), flat).map_err(|e| err(e.to_string()))?;
    let d = meta_dict(py, meta)?;
    d.set_item("nonfiniteSamples", rendered.nonfinite)?;
    d.set_item("nonfiniteSplats", rendered.nonfinite_splats)?;
    d.set_item("collapsedFraction", rendered.collapsed_fraction())?;
    if let Some(g) = rendered.guide {
        d.set_item("guidingLearnedSpp", g.learned_spp)?;
        d.set_item("guidingWorth", g.worth)?;
        d.set_item("guidingStopped", g.stopped)?;
    }
    Ok((image.into_pyarray(py), d))
}

/// The options `render` and `render_shard` take by name, parsed by the
/// library (a wrong one is a ValueError with its message).
struct Named {
    strategy: WavelengthStrategy,
    cluster: ClusterSize,
    integrator: Option<IntegratorKind>,
    tracer: Tracer,
    quantity: Quantity,
    guiding: Guiding,
}

impl Named {
    fn parse(
        wavelengths: &str,
        cluster: usize,
        integrator: Option<&str>,
        [tracer, quantity, guiding]: [&str; 3],
    ) -> PyResult<Self> {
        Ok(Self {
            strategy: wavelength_strategy(wavelengths)?,
            cluster: cluster_size(cluster)?,
            integrator: integrator.map(parsed).transpose()?,
            tracer: parsed(tracer)?,
            quantity: parsed(quantity)?,
            guiding: parsed(guiding)?,
        })
    }

    /// Render options with these, the others at their defaults.
    fn options(&self) -> RenderOptions {
        RenderOptions {
            strategy: self.strategy,
            cluster: self.cluster,
            integrator: self.integrator,
            tracer: self.tracer,
            quantity: self.quantity,
            guiding: self.guiding,
            ..RenderOptions::default()
        }
    }
}

/// An option's text as the library reads it; its error a ValueError.
fn parsed<T: std::str::FromStr>(text: &str) -> PyResult<T>
where
    T::Err: std::fmt::Display,
{
    text.parse()
        .map_err(|e: T::Err| PyValueError::new_err(e.to_string()))
}

/// `cluster`, checked by the library.
pub(crate) fn cluster_size(k: usize) -> PyResult<ClusterSize> {
    ClusterSize::try_from(k).map_err(|e| PyValueError::new_err(e.to_string()))
}

/// The metadata as a dict.
fn meta_dict<'py>(
    py: Python<'py>,
    meta: Vec<(&'static str, Meta)>,
) -> PyResult<Bound<'py, PyDict>> {
    let d = PyDict::new(py);
    for (k, v) in meta {
        match v {
            Meta::Text(t) => d.set_item(k, t)?,
            Meta::F32(f) => d.set_item(k, f)?,
            Meta::I32(i) => d.set_item(k, i)?,
        }
    }
    Ok(d)
}

/// Renders one shard of a scene for distributed rendering: sample indices
/// `samples = (i0, i1)` of the pixels in `rows = (y0, y1)` (all rows if
/// None). Returns a dict of the film's raw sums (not normalised):
/// "sums" (H × W × 4 float64, X, Y, Z, V′: each camera sample times the
/// filter's weight at every pixel it reaches, bdpt's light-tracing splats
/// included), "weights" (H × W float64, the camera samples' filter weights
/// summed: a pixel is sums / weights), "squares" (the camera samples'
/// squares times their weights, summed), "counts" (H × W uint32 camera
/// samples that landed in each pixel), "dropped", "dropped_splats",
/// "collapsed", "rays", "seconds", "width", "height", "samples", "rows"
/// and "meta" (the render's metadata). `merge_shards` adds shards up.
#[pyfunction]
#[pyo3(signature = (path, samples, rows = None, seed = 0, wavelengths = "swc", cluster = 4, params = None, integrator = None, res = None, tracer = "scalar", quantity = "radiance", guiding = "off"))]
#[allow(clippy::too_many_arguments)]
fn render_shard<'py>(
    py: Python<'py>,
    path: PathBuf,
    samples: (u32, u32),
    rows: Option<(u32, u32)>,
    seed: u32,
    wavelengths: &str,
    cluster: usize,
    params: Option<HashMap<String, String>>,
    integrator: Option<&str>,
    res: Option<Bound<'py, PyAny>>,
    tracer: &str,
    quantity: &str,
    guiding: &str,
) -> PyResult<Bound<'py, PyDict>> {
    let err = |e: String| PyValueError::new_err(e);
    let named = Named::parse(
        wavelengths,
        cluster,
        integrator,
        [tracer, quantity, guiding],
    )?;
    if samples.0 >= samples.1 {
        return Err(err(format!(
            "samples ({}, {}): give sample indices i0 < i1",
            samples.0, samples.1
        )));
    }
    let load = load_options(res.as_ref())?;
    let params = params.unwrap_or_default();
    let scene = load_scene_with(&path, &params, &load).map_err(|e| err(e.to_string()))?;
    let height = scene.camera.height;
    let rows = rows.unwrap_or((0, height));
    if rows.0 >= rows.1 || rows.1 > height {
        return Err(err(format!(
            "rows ({}, {}): give y0 < y1 ≤ {height}, the film's height",
            rows.0, rows.1
        )));
    }
    let options = RenderOptions {
        seed,
        shard: Some(Shard {
            samples: samples.0..samples.1,
            rows: Some(rows.0..rows.1),
        }),
        ..named.options()
    };
    // Ctrl-C: the shard is incomplete, so nothing of it is returned.
    let cancel = AtomicBool::new(false);
    let (rendered, interrupted) = crate::interrupt::interruptible(py, &cancel, || {
        render_with(&scene, &options, Hooks::new(&cancel))
    });
    if let Some(e) = interrupted {
        return Err(e);
    }
    let rendered = rendered.map_err(|e| match e {
        RenderError::TooLarge(_) => PyMemoryError::new_err(e.to_string()),
        _ => err(e.to_string()),
    })?;
    let film = &rendered.film;
    let (w, h) = (film.width as usize, film.height as usize);
    let sums: Vec<f64> = film.pixels.iter().flat_map(|p| p.xyzv).collect();
    let squares: Vec<f64> = film
        .kept_moments()
        .unwrap_or(&[])
        .iter()
        .flatten()
        .copied()
        .collect();
    let counts: Vec<u32> = film.pixels.iter().map(|p| p.samples).collect();
    let weights: Vec<f64> = film.pixels.iter().map(|p| p.weight).collect();
    let shape = |v: Vec<f64>| Array3::from_shape_vec((h, w, 4), v).map_err(|e| err(e.to_string()));
    let counts = Array2::from_shape_vec((h, w), counts).map_err(|e| err(e.to_string()))?;
    let weights = Array2::from_shape_vec((h, w), weights).map_err(|e| err(e.to_string()))?;
    let mut facts = rendered.facts();
    facts.spp = samples.1 - samples.0;
    let meta = render_metadata(&scene, &options, &facts, &path.display().to_string());
    let d = PyDict::new(py);
    d.set_item("sums", shape(sums)?.into_pyarray(py))?;
    d.set_item("squares", shape(squares)?.into_pyarray(py))?;
    d.set_item("counts", counts.into_pyarray(py))?;
    d.set_item("weights", weights.into_pyarray(py))?;
    d.set_item("dropped", rendered.nonfinite)?;
    d.set_item("dropped_splats", rendered.nonfinite_splats)?;
    d.set_item("collapsed", rendered.collapsed)?;
    d.set_item("rays", rendered.rays)?;
    d.set_item("seconds", rendered.elapsed.as_secs_f64())?;
    d.set_item("width", w)?;
    d.set_item("height", h)?;
    d.set_item("samples", samples)?;
    d.set_item("rows", rows)?;
    d.set_item("meta", meta_dict(py, meta)?)?;
    Ok(d)
}

/// Refuses an output (`output`, `spectral`, `checkpoint`) that is a file
/// the scene reads (`files`, the scene first) or that names one file twice.
fn check_outputs(files: &[PathBuf], outputs: [&Option<PathBuf>; 3]) -> Result<(), String> {
    let inputs: Vec<(&str, &Path)> = files
        .iter()
        .enumerate()
        .map(|(i, f)| {
            let what = if i == 0 {
                "the scene"
            } else {
                "a file the scene reads"
            };
            (what, f.as_path())
        })
        .collect();
    let outputs: Vec<(&str, &Path)> = ["output", "spectral", "checkpoint"]
        .into_iter()
        .zip(outputs)
        .filter_map(|(name, p)| Some((name, p.as_deref()?)))
        .collect();
    scotopia_image::check_outputs(&inputs, &outputs)
}

/// Writes an H × W × 4 X, Y, Z, V′ image as the OpenEXR `render` writes
/// (channels X, Y, Z, V), with the header attributes in `meta` that are
/// text, floats or integers (others are left out): for images merged
/// from shards.
#[pyfunction]
#[pyo3(signature = (path, image, meta = None))]
fn write_exr(
    path: PathBuf,
    image: numpy::PyReadonlyArray3<f32>,
    meta: Option<Bound<'_, PyDict>>,
) -> PyResult<()> {
    let (h, w, px) = crate::vision::pixels::<4>(&image)?;
    let mut header: Vec<(String, Meta)> = Vec::new();
    for (k, v) in meta.iter().flat_map(|d| d.iter()) {
        let Ok(key) = k.extract::<String>() else {
            continue;
        };
        let value = if let Ok(t) = v.extract::<String>() {
            Meta::Text(t)
        } else if v.is_instance_of::<pyo3::types::PyInt>() {
            match v.extract::<i32>() {
                Ok(i) => Meta::I32(i),
                Err(_) => Meta::Text(v.str()?.to_string()),
            }
        } else if let Ok(f) = v.extract::<f64>() {
            Meta::F32(f as f32)
        } else {
            continue;
        };
        header.push((key, value));
    }
    let header: Vec<(&str, Meta)> = header
        .iter()
        .map(|(k, v)| (k.as_str(), v.clone()))
        .collect();
    write_xyzv_pixels(&path, w, h, &px, &header).map_err(|e| match e {
        scotopia_image::ImageError::Io { .. } => {
            pyo3::exceptions::PyOSError::new_err(e.to_string())
        }
        _ => PyValueError::new_err(e.to_string()),
    })
}

/// What `render` and `measure` check first: the SIMD level
/// (`SCOTOPIA_SIMD`) and the wavelength strategy's name.
pub(crate) fn wavelength_strategy(name: &str) -> PyResult<WavelengthStrategy> {
    scotopia_render::simd::Level::init().map_err(|e| PyValueError::new_err(e.to_string()))?;
    parsed(name)
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(render, m)?)?;
    m.add_function(wrap_pyfunction!(render_shard, m)?)?;
    m.add_function(wrap_pyfunction!(write_exr, m)?)?;
    Ok(())
}

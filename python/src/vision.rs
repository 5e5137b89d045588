//! The vision pipeline for Python: each stage on numpy arrays, and the
//! whole pipeline (`scotopia display`). Images are H × W × 4 float32
//! arrays of X, Y, Z, V′ (absolute, or display-relative after tone
//! mapping); the Python layer (`scotopia.vision`) converts dtypes.

use std::path::PathBuf;

use numpy::ndarray::Array3;
use numpy::{IntoPyArray, PyArray3, PyReadonlyArray3};
use pyo3::exceptions::{PyMemoryError, PyOSError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use scotopia_color::RgbSpace;
use scotopia_image::{read_xyzv, ImageError, RgbInput};
use scotopia_vision::acuity::{degrees_per_pixel, gaussian_blur, MAX_BLUR_SIGMA};
use scotopia_vision::gamut::map_pixels_to_gamut;
use scotopia_vision::glare::{apply_glare, GlareParams, Reproduced};
use scotopia_vision::mode::{image_statistics, Adaptation, VisualState};
use scotopia_vision::multiscale::{multiscale as run_multiscale, GainAdaptation, MultiscaleParams};
use scotopia_vision::night::night_shift as shift;
use scotopia_vision::output::{
    compare_sheet, display_gamut, display_peak as peak, write_display, PngOptions,
};
use scotopia_vision::{display as run_display, DisplayParams, Observer, ToneOperator};

fn err(e: impl ToString) -> PyErr {
    PyValueError::new_err(e.to_string())
}

/// An H × W × C array as (width, height, pixels).
/// `value` (argument `name`) must be finite and within [lo, hi].
fn finite_in(name: &str, value: f64, lo: f64, hi: f64) -> PyResult<()> {
    if value.is_finite() && (lo..=hi).contains(&value) {
        Ok(())
    } else {
        Err(err(format!(
            "{name} must be finite, from {lo} to {hi}; got {value}"
        )))
    }
}

pub(crate) fn pixels<const C: usize>(
    a: &PyReadonlyArray3<f32>,
) -> PyResult<(usize, usize, Vec<[f32; C]>)> {
    let a = a.as_array();
    let (h, w, c) = a.dim();
    if c != C {
        return Err(err(format!(
            "expected an H × W × {C} array, got shape {:?}",
            a.shape()
        )));
    }
    // A C-contiguous array (the usual case) is copied straight; any other
    // layout element by element.
    let px = match a.as_slice() {
        Some(flat) => flat
            .chunks_exact(C)
            .map(|p| std::array::from_fn(|k| p[k]))
            .collect(),
        None => a
            .outer_iter()
            .flat_map(|row| {
                row.outer_iter()
                    .map(|p| std::array::from_fn(|k| p[k]))
                    .collect::<Vec<[f32; C]>>()
            })
            .collect(),
    };
    Ok((w, h, px))
}

fn array<'py, const C: usize>(
    py: Python<'py>,
    w: usize,
    h: usize,
    px: Vec<[f32; C]>,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let flat: Vec<f32> = px.into_iter().flatten().collect();
    Ok(Array3::from_shape_vec((h, w, C), flat)
        .map_err(err)?
        .into_pyarray(py))
}

/// The visual state at adaptation `luminance` (cd/m²) for a scene of S/P
/// ratio `sp_ratio`: {"s": Jensen et al.'s scotopic sensitivity, "m": CIE
/// 191's mesopic coefficient, "mode": "photopic" | "mesopic" | "scotopic"}.
#[pyfunction]
#[pyo3(signature = (luminance, sp_ratio = 2.46))]
fn visual_state<'py>(
    py: Python<'py>,
    luminance: f64,
    sp_ratio: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let s = VisualState::new(luminance, sp_ratio);
    let d = PyDict::new(py);
    d.set_item("luminance", s.luminance)?;
    d.set_item("s", s.s)?;
    d.set_item("m", s.m)?;
    d.set_item("mode", s.mode.name())?;
    Ok(d)
}

/// The image's log-average and maximum luminance and its S/P ratio.
#[pyfunction]
fn image_stats<'py>(py: Python<'py>, image: PyReadonlyArray3<f32>) -> PyResult<Bound<'py, PyDict>> {
    let (_, _, px) = pixels::<4>(&image)?;
    let s = image_statistics(&px);
    let d = PyDict::new(py);
    d.set_item("log_average", s.log_average)?;
    d.set_item("maximum", s.maximum)?;
    d.set_item("sp_ratio", s.sp_ratio)?;
    Ok(d)
}

/// Glare in absolute units (CIE 146:2002's glare spread function for an
/// observer of `age` and `pigmentation`, Spencer et al. 1995's halo for
/// scotopic sensitivity `s`): the light above `threshold` (cd/m²), or all
/// of it when `threshold` is None (the retinal image), spread by the PSF;
/// returns the new image.
#[pyfunction]
#[pyo3(signature = (image, degrees_per_pixel, threshold = None, s = 1.0, age = 25.0, pigmentation = 0.5))]
fn glare<'py>(
    py: Python<'py>,
    image: PyReadonlyArray3<f32>,
    degrees_per_pixel: f64,
    threshold: Option<f64>,
    s: f64,
    age: f64,
    pigmentation: f64,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let (w, h, mut px) = pixels::<4>(&image)?;
    if !(degrees_per_pixel.is_finite() && degrees_per_pixel > 0.0) {
        return Err(err(format!(
            "degrees_per_pixel must be positive and finite, got {degrees_per_pixel}"
        )));
    }
    finite_in("s", s, 0.0, 1.0)?;
    if threshold.is_some_and(f64::is_nan) {
        return Err(err("threshold must be a number, got NaN"));
    }
    let observer = Observer::new(age, pigmentation).map_err(|e| err(e.to_string()))?;
    let p = GlareParams {
        degrees_per_pixel,
        s,
        observer,
        reproduced: threshold.map_or(Reproduced::Nothing, Reproduced::Below),
    };
    py.detach(|| apply_glare(&mut px, w, h, &p));
    array(py, w, h, px)
}

/// The multiscale model (Pattanaik et al. 1998): display X, Y, Z in cd/m²
/// (H × W × 3). `adaptation` None: local, pooled over the field around
/// each pixel (`degrees_per_pixel` gives its size in pixels); a number:
/// one photopic adaptation luminance for the whole image. `mean_ceiling`: the
/// fraction of the peak the adaptation luminance is shown below
/// (docs/vision.md, step 6; `math.inf` for the plain brightness match).
#[pyfunction]
#[pyo3(signature = (image, display_peak = 100.0, display_adaptation = None, adaptation = None, degrees_per_pixel = 40.0 / 1024.0, mean_ceiling = 0.25))]
fn multiscale<'py>(
    py: Python<'py>,
    image: PyReadonlyArray3<f32>,
    display_peak: f64,
    display_adaptation: Option<f64>,
    adaptation: Option<f64>,
    degrees_per_pixel: f64,
    mean_ceiling: f64,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let (w, h, px) = pixels::<4>(&image)?;
    // Luminances the model uses in f32: from the smallest normal f32 (not
    // 0 there) to the largest (not ∞).
    let (lo, hi) = (f64::from(f32::MIN_POSITIVE), f64::from(f32::MAX));
    finite_in("display_peak", display_peak, lo, hi)?;
    finite_in("degrees_per_pixel", degrees_per_pixel, 1e-6, 180.0)?;
    for (name, v) in [
        ("display_adaptation", display_adaptation),
        ("adaptation", adaptation),
    ] {
        if let Some(v) = v {
            finite_in(name, v, lo, hi)?;
        }
    }
    if mean_ceiling.is_nan() || mean_ceiling <= 0.0 {
        return Err(PyValueError::new_err(format!(
            "mean_ceiling must be positive (got {mean_ceiling})"
        )));
    }
    let p = MultiscaleParams {
        degrees_per_pixel,
        display_peak,
        display_adaptation,
        adaptation: adaptation.map_or(GainAdaptation::Local, GainAdaptation::Global),
        mean_ceiling,
        ..MultiscaleParams::default()
    };
    let out = py.detach(|| run_multiscale(&px, w, h, &p));
    array(py, w, h, out)
}

/// The night-vision shift (Jensen et al. 2001) of X, Y, Z, V′ (V′ on Y's
/// scale) for scotopic sensitivity `s`: H × W × 3.
#[pyfunction]
fn night_shift<'py>(
    py: Python<'py>,
    image: PyReadonlyArray3<f32>,
    s: f64,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let (w, h, px) = pixels::<4>(&image)?;
    finite_in("s", s, 0.0, 1.0)?;
    let out = px
        .iter()
        .map(|q| shift(q.map(f64::from), s).map(|v| v as f32))
        .collect();
    array(py, w, h, out)
}

/// The scotopic acuity blur: a Gaussian of `sigma` pixels on all channels.
#[pyfunction]
fn acuity_blur<'py>(
    py: Python<'py>,
    image: PyReadonlyArray3<f32>,
    sigma: f64,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let (w, h, mut px) = pixels::<4>(&image)?;
    finite_in("sigma", sigma, 0.0, MAX_BLUR_SIGMA)?;
    py.detach(|| gaussian_blur(&mut px, w, h, sigma));
    array(py, w, h, px)
}

/// Gamut mapping (CSS Color 4, hue kept): display-relative X, Y, Z
/// (H × W × 3, white Y = 1) to linear RGB of `gamut` in [0, 1].
#[pyfunction]
#[pyo3(signature = (xyz, gamut = "srgb"))]
fn gamut_map<'py>(
    py: Python<'py>,
    xyz: PyReadonlyArray3<f32>,
    gamut: &str,
) -> PyResult<Bound<'py, PyArray3<f32>>> {
    let (w, h, px) = pixels::<3>(&xyz)?;
    let space = RgbSpace::from_name(gamut).map_err(err)?.def();
    // The pipeline's whole-image mapper (the same codes as the per-pixel
    // reference).
    let out = py.detach(|| map_pixels_to_gamut(&px, space));
    array(py, w, h, out)
}

/// Reads an X, Y, Z(, V) or R, G, B OpenEXR as absolute X, Y, Z, V′:
/// returns (image, horizontal field of view or None, notes).
#[pyfunction]
#[pyo3(signature = (path, units = None, input_space = "srgb"))]
#[allow(clippy::type_complexity)]
fn read_image<'py>(
    py: Python<'py>,
    path: PathBuf,
    units: Option<f64>,
    input_space: &str,
) -> PyResult<(Bound<'py, PyArray3<f32>>, Option<f64>, Vec<String>)> {
    let space = RgbSpace::from_name(input_space).map_err(err)?;
    let img = read_xyzv(&path, RgbInput { units, space }).map_err(|e| match e {
        ImageError::TooLarge { .. } => PyMemoryError::new_err(e.to_string()),
        ImageError::Io { .. } => PyOSError::new_err(e.to_string()),
        _ => err(e),
    })?;
    Ok((
        array(py, img.width, img.height, img.pixels)?,
        img.fov_horizontal,
        img.notes,
    ))
}

/// The whole pipeline (`scotopia display`) on an X, Y, Z, V′ array with
/// horizontal field of view `fov` degrees. Returns (linear RGB H × W × 3 in
/// [0, 1] of `gamut`, report dict). `output` writes .png/.exr; `compare` a
/// sheet of the stages. `age` (years) and `pigmentation` (CIE 146's
/// factor, 0 dark to 1 light blue eyes) describe the observer.
#[pyfunction]
#[pyo3(signature = (image, fov, display_peak = None, adaptation = "global", glare = true, night_shift = true, tonemap = "multiscale", gamut = None, hdr = false, bits = 8, output = None, compare = None, age = 25.0, pigmentation = 0.5))]
#[allow(clippy::too_many_arguments)]
fn display<'py>(
    py: Python<'py>,
    image: PyReadonlyArray3<f32>,
    fov: f64,
    display_peak: Option<f64>,
    adaptation: &str,
    glare: bool,
    night_shift: bool,
    tonemap: &str,
    gamut: Option<&str>,
    hdr: bool,
    bits: u8,
    output: Option<PathBuf>,
    compare: Option<PathBuf>,
    age: f64,
    pigmentation: f64,
) -> PyResult<(Bound<'py, PyArray3<f32>>, Bound<'py, PyDict>)> {
    let (w, h, px) = pixels::<4>(&image)?;
    let degrees_per_pixel = degrees_per_pixel(fov, w).map_err(|e| err(format!("fov {e}")))?;
    scotopia_vision::pipeline::check_size(w, h)
        .map_err(|e| PyMemoryError::new_err(e.to_string()))?;
    let adaptation = Adaptation::parse(adaptation).ok_or_else(|| {
        err(format!(
            "adaptation '{adaptation}': use 'global', 'local' or a luminance from {:e} to {:e} cd/m²",
            f32::MIN_POSITIVE,
            scotopia_vision::screen::ABSURD_LUMINANCE
        ))
    })?;
    let tonemap = ToneOperator::from_name(tonemap).ok_or_else(|| {
        err(format!(
            "tonemap '{tonemap}': use multiscale, reinhard or exposure"
        ))
    })?;
    let gamut = display_gamut(gamut, hdr).map_err(err)?;
    let png = PngOptions::new(bits, hdr).map_err(err)?;
    // "age -3: use years from 1 to 100": the message names the argument.
    let observer = Observer::new(age, pigmentation).map_err(err)?;
    let p = DisplayParams {
        degrees_per_pixel,
        display_peak: peak(display_peak, hdr).map_err(err)?,
        adaptation,
        glare,
        night_shift,
        tonemap,
        gamut,
        observer,
        ..DisplayParams::default()
    };
    let shown = py.detach(|| match &compare {
        Some(path) => {
            let (shown, (sw, sh, rgb)) = compare_sheet(&px, w, h, &p, 360);
            scotopia_image::write_png_rgb8(path, sw as u32, sh as u32, &rgb).map(|()| shown)
        }
        None => Ok(run_display(&px, w, h, &p)),
    });
    let shown = shown.map_err(err)?;
    if let Some(out) = output {
        write_display(&out, &shown, &p, png).map_err(err)?;
    }
    let r = &shown.report;
    let d = PyDict::new(py);
    d.set_item("adaptation_luminance", r.state.luminance)?;
    d.set_item("log_average", r.statistics.log_average)?;
    d.set_item("maximum", r.statistics.maximum)?;
    d.set_item("sp_ratio", r.statistics.sp_ratio)?;
    d.set_item("s", r.state.s)?;
    d.set_item("m", r.state.m)?;
    d.set_item("mode", r.state.mode.name())?;
    d.set_item("glare_applied", r.glare_applied)?;
    d.set_item("veil_adaptation", r.veil_adaptation)?;
    d.set_item("veil_centre", r.veil_centre)?;
    d.set_item("blur_pixels", r.blur_pixels)?;
    // Pixels left out of the statistics (non-finite or absurd): a sentence,
    // or None; the Python wrapper issues it as a warning.
    d.set_item("left_out", r.statistics.left_out.note())?;
    // Pixels of negative luminance (shown black): a sentence or None, a
    // warning in Python too.
    d.set_item("negative", r.statistics.negative_note())?;
    let t = PyDict::new(py);
    for (stage, secs) in &r.timings {
        t.set_item(*stage, *secs)?;
    }
    d.set_item("timings", t)?;
    Ok((array(py, w, h, shown.rgb)?, d))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(visual_state, m)?)?;
    m.add_function(wrap_pyfunction!(image_stats, m)?)?;
    m.add_function(wrap_pyfunction!(glare, m)?)?;
    m.add_function(wrap_pyfunction!(multiscale, m)?)?;
    m.add_function(wrap_pyfunction!(night_shift, m)?)?;
    m.add_function(wrap_pyfunction!(acuity_blur, m)?)?;
    m.add_function(wrap_pyfunction!(gamut_map, m)?)?;
    m.add_function(wrap_pyfunction!(read_image, m)?)?;
    m.add_function(wrap_pyfunction!(display, m)?)?;
    Ok(())
}

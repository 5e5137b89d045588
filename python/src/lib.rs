//! Python bindings: `import scotopia`. Thin wrappers over the library crates;
//! array arguments are numpy arrays whose last axis holds the three components.

mod arrays;
mod bsdf;
mod colour;
mod false_colour;
mod glare;
mod interrupt;
mod measure;
mod render;
mod report;
mod road;
mod scene;
mod spectrum;
mod view;
mod vision;

use pyo3::exceptions::{PyOSError, PyValueError};
use pyo3::prelude::*;
use scotopia_color::ColorError;

/// Maps a library error to a Python exception: OSError for files that cannot
/// be read, ValueError for everything else.
pub(crate) fn to_py(e: ColorError) -> PyErr {
    match e {
        ColorError::Io { .. } => PyOSError::new_err(e.to_string()),
        _ => PyValueError::new_err(e.to_string()),
    }
}

#[pymodule]
fn _scotopia(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("LAMBDA_MIN", scotopia_color::LAMBDA_MIN)?;
    m.add("LAMBDA_MAX", scotopia_color::LAMBDA_MAX)?;
    m.add("K_M", scotopia_color::photometry::K_M)?;
    m.add("K_M_SCOTOPIC", scotopia_color::photometry::K_M_SCOTOPIC)?;
    m.add_class::<spectrum::Spectrum>()?;
    bsdf::register(m)?;
    spectrum::register(m)?;
    colour::register(m)?;
    report::register(m)?;
    scene::register(m)?;
    render::register(m)?;
    measure::register(m)?;
    road::register(m)?;
    vision::register(m)?;
    false_colour::register(m)?;
    glare::register(m)?;
    view::register(m)?;
    Ok(())
}

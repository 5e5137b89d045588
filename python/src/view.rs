//! `scotopia.view`: the CLI's `view` (a progressive render or an image on
//! a local web page), started from Python and stopped from it.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};

use pyo3::exceptions::{PyRuntimeError, PyValueError};
use pyo3::prelude::*;

use scotopia_cli::view::{parse, start, Viewing};

/// A viewer running: `url`, `status()`, `wait()`, `stop()`.
#[pyclass(module = "scotopia")]
pub struct Viewer {
    #[pyo3(get)]
    url: String,
    cancel: Arc<AtomicBool>,
    viewing: Mutex<Option<Viewing>>,
}

fn err(e: anyhow::Error) -> PyErr {
    PyValueError::new_err(format!("{e:#}"))
}

#[pymethods]
impl Viewer {
    /// What `GET /status` answers, as a dict.
    fn status<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let text = {
            let v = self.viewing.lock().map_err(|_| closed())?;
            v.as_ref().ok_or_else(closed)?.status().to_string()
        };
        py.import("json")?.call_method1("loads", (text,))
    }

    /// Waits for the render to end (the page stays up). Ctrl-C stops the
    /// render (its film is written, as on the CLI's Ctrl-C) and raises
    /// KeyboardInterrupt.
    fn wait(&self, py: Python<'_>) -> PyResult<()> {
        let (ended, interrupted) = crate::interrupt::interruptible(py, &self.cancel, || {
            let mut v = self.viewing.lock().map_err(|_| closed())?;
            match v.as_mut() {
                Some(v) => v.wait().map_err(err),
                None => Ok(()),
            }
        });
        match interrupted {
            Some(e) => Err(e),
            None => ended,
        }
    }

    /// Stops the render (its film is written, as on Ctrl-C) and the page.
    fn stop(&self, py: Python<'_>) -> PyResult<()> {
        match py.detach(|| self.shut()) {
            // Stopping a render is what was asked: not an error.
            Err(e) if !e.to_string().starts_with("interrupted") => Err(err(e)),
            _ => Ok(()),
        }
    }
}

impl Viewer {
    /// Ends the render (at its next pass), waits for its film to be
    /// written and closes the page; what the render ended with.
    fn shut(&self) -> anyhow::Result<()> {
        self.cancel.store(true, Ordering::Relaxed);
        let taken = self
            .viewing
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .take();
        match taken {
            Some(mut v) => {
                let ended = v.wait();
                v.close();
                ended
            }
            None => Ok(()),
        }
    }
}

impl Drop for Viewer {
    /// A viewer forgotten is stopped: its render ends at the next pass and
    /// its port closes.
    fn drop(&mut self) {
        let _ = self.shut();
    }
}

fn closed() -> PyErr {
    PyRuntimeError::new_err("the viewer has been stopped")
}

/// Starts `scotopia view` with the command line's arguments after the verb.
#[pyfunction]
fn view(py: Python<'_>, argv: Vec<String>) -> PyResult<Viewer> {
    let args = parse(&argv).map_err(err)?;
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    let viewing = py.detach(|| start(args, flag)).map_err(err)?;
    Ok(Viewer {
        url: viewing.url.clone(),
        cancel,
        viewing: Mutex::new(Some(viewing)),
    })
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Viewer>()?;
    m.add_function(wrap_pyfunction!(view, m)?)
}

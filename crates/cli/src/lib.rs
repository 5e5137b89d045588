//! The `scotopia` command line as a library: each verb's arguments and
//! `run`, for the binary (`main.rs`) and for the Python module, which
//! starts `view` from Python.

pub mod display;
mod false_colour;
pub mod info;
pub mod measure;
mod numbers;
mod ray;
pub mod render;
pub mod spectrum;
mod tev;
pub mod view;

/// Writes `text` to standard output; a closed pipe (`| head`) is not an error.
pub fn print(text: &str) -> anyhow::Result<()> {
    use std::io::Write;
    match std::io::stdout().lock().write_all(text.as_bytes()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e.into()),
        _ => Ok(()),
    }
}

//! The `scotopia` command line as a library: each verb's arguments and
//! `run`, for the binary (`main.rs`) and for the Python module, which
//! starts `view` from Python.

pub mod display;
mod false_colour;
pub mod glare;
pub mod info;
pub mod measure;
mod numbers;
mod ray;
pub mod render;
pub mod road;
pub mod spectrum;
mod tev;
pub mod view;

/// `scotopia render`: here (`render::run`), or on a Ray cluster with
/// `--ray` (`ray::render`, which reuses the local render's arguments and
/// outputs, so it sits above `render`, not inside it).
pub fn run_render(args: render::Args) -> anyhow::Result<()> {
    match &args.ray {
        Some(address) => ray::render(&args, address),
        None => render::run(args),
    }
}

/// Writes `text` to standard output; a closed pipe (`| head`) is not an error.
pub fn print(text: &str) -> anyhow::Result<()> {
    use std::io::Write;
    match std::io::stdout().lock().write_all(text.as_bytes()) {
        Err(e) if e.kind() != std::io::ErrorKind::BrokenPipe => Err(e.into()),
        _ => Ok(()),
    }
}

//! The `scotopia` command line. Each verb parses its arguments, calls the
//! library, and prints or writes the result.

use scotopia_cli::{display, glare, info, measure, render, road, spectrum, view};

use std::process::ExitCode;

use clap::{Parser, Subcommand};

/// mimalloc keeps the memory it frees for the next allocation of its
/// size: with the system allocator a `display` of a full-HD image took
/// 36,000 page faults (every large buffer freed to the kernel and faulted
/// in again), ~0.1 s of a 0.3 s process; with mimalloc 400 (README,
/// benchmarks).
#[global_allocator]
static ALLOCATOR: mimalloc::MiMalloc = mimalloc::MiMalloc;
/// scotopia: a spectral renderer that shows what a human eye would see.
/// Verbs: spectrum, info, render, display, measure, glare, road and view.
#[derive(Parser)]
#[command(name = "scotopia", version, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Print the colorimetry of one spectrum: absolute X, Y, Z (cd/m²), V′
    /// (scotopic cd/m²), chromaticity, CCT and the S/P ratio.
    Spectrum(spectrum::Args),
    /// Load a Mitsuba 3 XML scene and print what it holds: shapes,
    /// triangles, materials, emitters and their power, camera, film, warnings.
    Info(info::Args),
    /// Render a scene to an OpenEXR of absolute X, Y, Z (cd/m²) and V′
    /// (scotopic cd/m²), with a spectral path tracer.
    Render(Box<render::Args>),
    /// Show an X, Y, Z, V′ image as a person would see it on a display:
    /// visual mode, glare, multiscale adaptation, night shift, gamut mapping.
    Display(display::Args),
    /// Measure photopic and scotopic illuminance (lx) at points of a scene,
    /// with standard errors and the S/P ratio: a lighting calculation grid.
    Measure(measure::Args),
    /// Glare ratings from a fisheye luminance picture, as evalglare finds
    /// them: the vertical illuminance at the lens, the glare sources, UGR
    /// (CIE 117), DGP (Wienold & Christoffersen 2006) and CIE 146's
    /// veiling luminance.
    Glare(glare::Args),
    /// EN 13201-3's luminance method on a straight road of a scene: its
    /// grid, the luminance each lane's observer sees there (the full
    /// spectral transport, or --direct), L_av, U_o, U_l and the threshold
    /// increment TI.
    Road(road::Args),
    /// Render a scene progressively (or open an X, Y, Z, V′ EXR) and show it
    /// as the eye sees it on a local web page, with the light level,
    /// adaptation, glare, night shift, tone operator, display and false
    /// colour at hand; the pixel under the cursor in cd/m².
    View(Box<view::Args>),
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    let result = match cli.command {
        Command::Spectrum(args) => spectrum::run(args),
        Command::Info(args) => info::run(args),
        Command::Render(args) => scotopia_cli::run_render(*args),
        Command::Display(args) => display::run(args),
        Command::Measure(args) => measure::run(args),
        Command::Glare(args) => glare::run(args),
        Command::Road(args) => road::run(args),
        Command::View(args) => view::run(*args),
    };
    match result {
        Ok(()) => ExitCode::SUCCESS,
        Err(e) => {
            eprintln!("scotopia: error: {e:#}");
            ExitCode::FAILURE
        }
    }
}

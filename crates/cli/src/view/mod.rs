//! `scotopia view`: a progressive render (or an X, Y, Z, V′ image) on a
//! local web page, as the eye sees it, with `display`'s settings at hand.
//! The render publishes the film at pass boundaries; each page request
//! runs only the vision pipeline on the latest film.

mod live;
mod page;
mod query;
mod respond;
mod server;

use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::sync::Arc;
use std::time::Duration;

use anyhow::{bail, Context, Result};

use scotopia_image::{read_xyzv, Meta, RgbInput, XyzvImage};
use scotopia_render::film::Film;
use scotopia_render::integrator::{render_observed, Observer, RunFacts};
use scotopia_render::output::{render_metadata, write_xyzv_exr};

use crate::render::{cancel_on_interrupt, progress_bar, Prepared, Setup};
use live::{Frame, Live, Phase};
use query::Settings;

#[derive(clap::Args)]
pub struct Args {
    /// A scene (Mitsuba 3 XML) to render progressively, or an X, Y, Z, V′
    /// OpenEXR (`*.exr`, as `render` writes) to look at.
    #[command(flatten)]
    setup: Setup,
    /// Where saving, the end of the render and Ctrl-C write the film's
    /// EXR (the page's PNG goes beside it). Default: the input's name
    /// with `.exr` (`-view.exr` for an image) in the current folder.
    #[arg(short, long, value_name = "OUT.exr")]
    output: Option<PathBuf>,
    /// The port on 127.0.0.1 (0: any free one). Default: 8650, or the
    /// next free port after it.
    #[arg(long)]
    port: Option<u16>,
    /// Do not open the page in the browser (the address is printed).
    #[arg(long)]
    no_open: bool,
    /// The page's starting settings.
    #[command(flatten)]
    settings: Settings,
}

/// How often the render shows the page its film (at pass boundaries).
const REFRESH: Duration = Duration::from_millis(500);
/// Request threads: each runs the vision pipeline for one page request.
const REQUEST_THREADS: usize = 4;

pub fn run(args: Args) -> Result<()> {
    // The starting settings, checked before anything is loaded.
    let settings = args.settings.pairs();
    query::parse(&settings)?.view()?;
    let input = args.setup.scene.clone();
    let is_image = input
        .extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("exr"));
    let output = args
        .output
        .clone()
        .unwrap_or_else(|| default_output(&input, is_image));
    if output
        .extension()
        .is_none_or(|e| !e.eq_ignore_ascii_case("exr"))
    {
        bail!(
            "-o {}: the film is saved as OpenEXR: give OUT.exr",
            output.display()
        );
    }
    let name = input.display().to_string();
    if is_image {
        let image = read_xyzv(&input, RgbInput::default())?;
        for note in &image.notes {
            eprintln!("scotopia: note: {name}: {note}");
        }
        let meta = image_metadata(&image);
        let frame = Frame {
            image,
            spp: 0,
            seconds: 0.0,
            meta,
        };
        let live = Arc::new(Live::new(frame, Phase::Image, settings, 0, name, output));
        let cancel = cancel_on_interrupt()?;
        serve(&args, live)?;
        while !cancel.load(Ordering::Relaxed) {
            std::thread::sleep(Duration::from_millis(100));
        }
        return Ok(());
    }

    let Prepared {
        scene,
        options,
        total,
        pool,
        ..
    } = args.setup.prepare(None)?;
    let (w, h) = (scene.camera.width as usize, scene.camera.height as usize);
    scotopia_vision::pipeline::check_size(w, h).with_context(|| name.clone())?;
    let snapshot = |film: &Film, facts: &RunFacts| Frame {
        image: XyzvImage {
            width: w,
            height: h,
            pixels: film.xyzv(),
            fov_horizontal: Some(scene.camera.fov_degrees().0 as f64),
            quantity: Some(quantity_name(facts).into()),
            notes: Vec::new(),
        },
        spp: facts.spp,
        seconds: facts.elapsed.as_secs_f64(),
        meta: render_metadata(&scene, &options, facts, &name),
    };
    let empty = Film::try_new(w as u32, h as u32, None)?;
    let start = RunFacts {
        spp: 0,
        rays: 0,
        elapsed: Duration::ZERO,
        cancelled: false,
        integrator: options.integrator.unwrap_or(scene.integrator.kind),
        quantity: options.quantity,
    };
    let first = snapshot(&empty, &start);
    drop(empty);
    let live = Arc::new(Live::new(
        first,
        Phase::Rendering,
        settings,
        total,
        name.clone(),
        output.clone(),
    ));
    let cancel = cancel_on_interrupt()?;
    serve(&args, live.clone())?;

    let bar = progress_bar(total as u64);
    let see = |film: &Film, facts: &RunFacts| live.publish(snapshot(film, facts));
    let observer = Observer {
        every: REFRESH,
        see: &see,
    };
    let progress = |done: u32, _: u32| bar.set_position(done as u64);
    let rendered = pool
        .install(|| render_observed(&scene, &options, &cancel, &progress, None, Some(observer)))?;
    bar.finish_and_clear();
    let meta = render_metadata(&scene, &options, &rendered.facts(), &name);
    write_xyzv_exr(&output, &rendered, &meta)?;
    if rendered.cancelled {
        live.set_phase(Phase::Interrupted);
        bail!(
            "interrupted: wrote the {} spp accumulated so far → {}",
            rendered.spp,
            output.display()
        );
    }
    live.set_phase(Phase::Done);
    eprintln!(
        "scotopia: {} spp in {:.1} s → {}; the page stays up until Ctrl-C",
        rendered.spp,
        rendered.elapsed.as_secs_f64(),
        output.display()
    );
    while !cancel.load(Ordering::Relaxed) {
        std::thread::sleep(Duration::from_millis(100));
    }
    Ok(())
}

/// Starts the server, says where, and opens the page unless told not to.
fn serve(args: &Args, live: Arc<Live>) -> Result<()> {
    let (server, port) = server::bind(args.port)?;
    let url = format!("http://127.0.0.1:{port}/");
    eprintln!(
        "scotopia: view at {url} (Ctrl-C stops; the film is saved to {})",
        live.output.display()
    );
    server::spawn(server, live, REQUEST_THREADS);
    if !args.no_open {
        if let Err(e) = webbrowser::open(&url) {
            eprintln!("scotopia: note: cannot open a browser ({e}): open {url}");
        }
    }
    Ok(())
}

fn default_output(input: &Path, is_image: bool) -> PathBuf {
    let stem = input.file_stem().unwrap_or_default().to_string_lossy();
    PathBuf::from(if is_image {
        format!("{stem}-view.exr")
    } else {
        format!("{stem}.exr")
    })
}

fn quantity_name(facts: &RunFacts) -> &'static str {
    match facts.quantity {
        scotopia_render::integrator::Quantity::Radiance => "radiance",
        scotopia_render::integrator::Quantity::Illuminance => "illuminance",
    }
}

/// What an image's EXR keeps when saved again: its field of view and
/// what its pixels hold.
fn image_metadata(image: &XyzvImage) -> Vec<(&'static str, Meta)> {
    let mut meta = Vec::new();
    if let Some(f) = image.fov_horizontal {
        meta.push(("fovHorizontalDegrees", Meta::F32(f as f32)));
    }
    if let Some(q) = &image.quantity {
        meta.push(("quantity", Meta::Text(q.clone())));
    }
    meta
}

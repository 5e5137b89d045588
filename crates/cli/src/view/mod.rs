//! `scotopia view`: a progressive render (or an X, Y, Z, V′ image) on a
//! local web page, as the eye sees it, with `display`'s settings at hand.
//! The render publishes the film at pass boundaries; each page request
//! runs only the vision pipeline on the latest film.

mod guard;
mod http;
mod live;
mod page;
mod query;
mod respond;
mod server;

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use anyhow::{bail, Context, Result};

use scotopia_image::{read_xyzv, Meta, RgbInput, XyzvImage};
use scotopia_render::film::Film;
use scotopia_render::integrator::{render_with, Hooks, Observer, RunFacts};
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
/// Request workers: each runs the vision pipeline for one page request.
const REQUEST_THREADS: usize = 4;

/// A viewer started: its page's address, and the render (if any) going on
/// in a thread of its own.
pub struct Viewing {
    pub url: String,
    live: Arc<Live>,
    render: Option<std::thread::JoinHandle<Result<()>>>,
    serving: server::Serving,
}

impl Viewing {
    /// What `GET /status` answers.
    pub fn status(&self) -> serde_json::Value {
        respond::status(&self.live)
    }

    /// Waits for the render to end (complete, or stopped by the cancel
    /// flag, its film written either way); an interrupted render is an
    /// error saying what was written. The page stays up.
    pub fn wait(&mut self) -> Result<()> {
        match self.render.take() {
            Some(thread) => match thread.join() {
                Ok(result) => result,
                Err(_) => bail!("the render thread failed"),
            },
            None => Ok(()),
        }
    }

    /// Closes the page's server (after [`Self::wait`], or the render goes
    /// on unseen).
    pub fn close(self) {
        self.serving.close();
    }
}

/// `scotopia view`: until Ctrl-C.
pub fn run(args: Args) -> Result<()> {
    let cancel = cancel_on_interrupt()?;
    let mut viewing = start(args, cancel.clone())?;
    viewing.wait()?;
    while !cancel.load(Ordering::Relaxed) {
        std::thread::sleep(Duration::from_millis(100));
    }
    Ok(())
}

/// `view`'s arguments from a command line without the verb (for Python).
pub fn parse(argv: &[String]) -> Result<Args> {
    #[derive(clap::Parser)]
    #[command(name = "scotopia view", no_binary_name = true)]
    struct Command {
        #[command(flatten)]
        args: Args,
    }
    use clap::Parser;
    Command::try_parse_from(argv)
        .map(|c| c.args)
        .map_err(|e| anyhow::anyhow!("{}", e.to_string().trim_end()))
}

/// Loads the input, starts the server and, for a scene, the render; the
/// render stops when `cancel` is set.
pub fn start(args: Args, cancel: Arc<AtomicBool>) -> Result<Viewing> {
    // The starting settings, checked before anything is loaded.
    let settings = args.settings.pairs();
    let checked = query::parse(&settings)?;
    checked.view()?;
    checked.vision.params(1, Some(45.0))?;
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
    check_saves(&output, std::slice::from_ref(&input))?;
    let name = input.display().to_string();
    // The page is told file names, no folders.
    let page_name = respond::file_name(&input);
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
        let live = Arc::new(Live::new(
            frame,
            Phase::Image,
            settings,
            0,
            page_name,
            output,
        ));
        let (url, serving) = serve(&args, live.clone())?;
        return Ok(Viewing {
            url,
            live,
            render: None,
            serving,
        });
    }

    let prepared = args.setup.prepare(None)?;
    check_saves(&output, &prepared.files)?;
    let scene = &prepared.scene;
    let (w, h) = (scene.camera.width as usize, scene.camera.height as usize);
    scotopia_vision::pipeline::check_size(w, h).with_context(|| name.clone())?;
    let empty = Film::try_new(w as u32, h as u32, None)?;
    let start = RunFacts {
        spp: 0,
        rays: 0,
        elapsed: Duration::ZERO,
        cancelled: false,
        integrator: prepared.options.integrator.unwrap_or(scene.integrator.kind),
        quantity: prepared.options.quantity,
    };
    let first = snapshot(&prepared, &name, &empty, &start);
    drop(empty);
    let live = Arc::new(Live::new(
        first,
        Phase::Rendering,
        settings,
        prepared.total,
        page_name,
        output.clone(),
    ));
    let (url, serving) = serve(&args, live.clone())?;
    let shown = live.clone();
    let render = std::thread::spawn(move || render_live(prepared, &name, &output, &shown, &cancel));
    Ok(Viewing {
        url,
        live,
        render: Some(render),
        serving,
    })
}

/// Renders, showing the page the film at pass boundaries; writes the EXR
/// at the end or when stopped.
fn render_live(
    prepared: Prepared,
    name: &str,
    output: &Path,
    live: &Live,
    cancel: &AtomicBool,
) -> Result<()> {
    let bar = progress_bar(prepared.total as u64);
    let see = |film: &Film, facts: &RunFacts| live.publish(snapshot(&prepared, name, film, facts));
    let observer = Observer {
        every: REFRESH,
        see: &see,
    };
    let progress = |done: u32, _: u32| bar.set_position(done as u64);
    let Prepared {
        scene,
        options,
        pool,
        ..
    } = &prepared;
    let rendered = pool.install(|| {
        let hooks = Hooks {
            progress: Some(&progress),
            observer: Some(observer),
            ..Hooks::new(cancel)
        };
        render_with(scene, options, hooks)
    })?;
    bar.finish_and_clear();
    let meta = render_metadata(scene, options, &rendered.facts(), name);
    write_xyzv_exr(output, &rendered, &meta)?;
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
    Ok(())
}

/// One look at the film, for the page.
fn snapshot(prepared: &Prepared, name: &str, film: &Film, facts: &RunFacts) -> Frame {
    let scene = &prepared.scene;
    Frame {
        image: XyzvImage {
            width: film.width as usize,
            height: film.height as usize,
            pixels: film.xyzv(),
            fov_horizontal: Some(scene.camera.fov_degrees().0 as f64),
            quantity: Some(facts.quantity.name().into()),
            projection: None,
            notes: Vec::new(),
        },
        spp: facts.spp,
        seconds: facts.elapsed.as_secs_f64(),
        meta: render_metadata(scene, &prepared.options, facts, name),
    }
}

/// Starts the server, says where, and opens the page unless told not to.
fn serve(args: &Args, live: Arc<Live>) -> Result<(String, server::Serving)> {
    let (listener, port) = server::bind(args.port)?;
    let session = guard::Session::new(port)?;
    let url = format!("http://127.0.0.1:{port}/");
    let output = live.output.display().to_string();
    let site = Arc::new(respond::Site { live, session });
    let serving = server::spawn(listener, site, REQUEST_THREADS)?;
    eprintln!("scotopia: view at {url} (Ctrl-C stops; the film is saved to {output})");
    if !args.no_open {
        if let Err(e) = webbrowser::open(&url) {
            eprintln!("scotopia: note: cannot open a browser ({e}): open {url}");
        }
    }
    Ok((url, serving))
}

/// Refuses a save path (the EXR at `output` and the PNG beside it) that
/// is one of `inputs` (the input first, then the files a scene reads):
/// saving would destroy it.
fn check_saves(output: &Path, inputs: &[PathBuf]) -> Result<()> {
    let png = output.with_extension("png");
    let inputs = crate::render::named_inputs("the input", inputs);
    let outputs = [("-o", output), ("the PNG saved beside -o", png.as_path())];
    scotopia_image::check_outputs(&inputs, &outputs).map_err(anyhow::Error::msg)
}

fn default_output(input: &Path, is_image: bool) -> PathBuf {
    let stem = input.file_stem().unwrap_or_default().to_string_lossy();
    PathBuf::from(if is_image {
        format!("{stem}-view.exr")
    } else {
        format!("{stem}.exr")
    })
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

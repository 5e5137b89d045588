//! `scotopia render`: a scene to an X, Y, Z, V′ OpenEXR in absolute units.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::Duration;

use anyhow::{bail, Context, Result};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use scotopia_image::{preview_srgb8, write_png_rgb8};
use scotopia_render::film::{Checkpoint, Film};
use scotopia_render::integrator::{
    checkpoint_interval, render_with, BdptStrategy, Checkpointing, ClusterSize, Guiding, Hooks,
    Observer, Quantity, RenderError, RenderOptions, RunFacts, Tracer,
};
use scotopia_render::output::{render_metadata, write_spectral_exr, write_xyzv_pixels};
use scotopia_render::scene::IntegratorKind;
use scotopia_render::scene::Scene;
use scotopia_render::wavelength::WavelengthStrategy;
use scotopia_scene::mitsuba::Parameters;
use scotopia_scene::{checkpoint_key, load_scene_tracked, LoadOptions, Resolution};

use scotopia_vision::output::PngOptions;
use scotopia_vision::DisplayParams;

use crate::display::{write_shown, VisionArgs};
use crate::info::{load_options, parameters};

#[derive(clap::Args)]
pub struct Args {
    #[command(flatten)]
    pub(crate) setup: Setup,
    /// The output: a 32-bit float OpenEXR with channels X, Y, Z (cd/m²) and
    /// V (scotopic cd/m²).
    #[arg(short, long, value_name = "OUT.exr")]
    pub(crate) output: PathBuf,
    /// Save the film's exact sums to OUT.exr.ckpt every SECONDS and at the
    /// end (complete, interrupted or out of time), so that a killed render
    /// can be resumed, or a finished one given more samples.
    #[arg(long, value_name = "SECONDS")]
    pub(crate) checkpoint: Option<f64>,
    /// Continue from OUT.exr.ckpt if it is there (same scene file, files
    /// it reads, parameters, seed and options; --spp may grow): the result
    /// is bit-identical to an uninterrupted render of as many samples. A
    /// damaged checkpoint, or one saved before a file was edited, is refused.
    #[arg(long)]
    pub(crate) resume: bool,
    /// Also write the spectral radiance image as a spectral OpenEXR
    /// (Fichet et al. 2021: channels S0.<λ>nm, W·m⁻²·sr⁻¹·nm⁻¹).
    #[arg(long, value_name = "OUT.exr")]
    pub(crate) spectral: Option<PathBuf>,
    /// Bands of the spectral image, equal over 360–830 nm (47: 10 nm).
    #[arg(long, default_value_t = 47, value_name = "N")]
    pub(crate) bands: usize,
    /// Also write a quick auto-exposed sRGB preview.
    #[arg(long, value_name = "OUT.png")]
    pub(crate) preview: Option<PathBuf>,
    /// Also write the image as a Radiance picture (RGBE in Radiance's
    /// primaries and units, W/sr/m² of 179 lm/W, so its luminance is the
    /// render's), for evalglare and Radiance's other tools; with the view
    /// (-vtv -vh -vv) of an uncropped perspective camera.
    #[arg(long, value_name = "OUT.hdr")]
    pub(crate) radiance: Option<PathBuf>,
    /// Also run the vision pipeline (as `scotopia display`, with the
    /// camera's field of view) and write what the eye would see.
    #[arg(long, value_name = "OUT.png")]
    pub(crate) display: Option<PathBuf>,
    /// Show the film in the tev image viewer while it renders, over TCP
    /// (tev's default port: 127.0.0.1:14158): channels X, Y, Z, V as in
    /// the EXR and a layer `seen` (what --display would show, linear
    /// RGB), about once a second and at the end. Nothing blocks the
    /// render: if tev is not there it says so once and retries.
    #[arg(
        long,
        value_name = "HOST:PORT",
        num_args = 0..=1,
        default_missing_value = crate::tev::DEFAULT,
        value_parser = crate::tev::address,
    )]
    pub(crate) tev: Option<crate::tev::Address>,
    /// Render on a Ray cluster (at ADDRESS, e.g. `auto` or
    /// `ray://head:10001`; default: a local Ray on this machine's cores),
    /// through the scotopia Python package with its `distributed` extra
    /// (`pip install scotopia[distributed]`; the Python is
    /// `$SCOTOPIA_PYTHON`, else `python3`). docs/distributed.md.
    #[arg(long, value_name = "ADDRESS", num_args = 0..=1, default_missing_value = "")]
    pub(crate) ray: Option<String>,
    /// With --ray: how many shards the samples are cut into (default: two
    /// per CPU of the cluster).
    #[arg(long, value_name = "N", requires = "ray")]
    pub(crate) shards: Option<u32>,
    #[command(flatten)]
    pub(crate) vision: VisionArgs,
}

/// What a render is of and how it samples: the arguments `render` and
/// `view` share.
#[derive(clap::Args)]
pub struct Setup {
    /// The scene (Mitsuba 3 XML).
    pub scene: PathBuf,
    /// Set a scene parameter, overriding its <default> (repeatable).
    #[arg(short = 'D', value_name = "NAME=VALUE")]
    pub(crate) define: Vec<String>,
    /// Override the film size: W (keeping the film's aspect) or WxH. The
    /// field of view along the film's fov_axis stays, as in Mitsuba.
    #[arg(long, value_name = "W|WxH")]
    pub(crate) res: Option<Resolution>,
    /// Samples per pixel (default: the scene's sampler).
    #[arg(long)]
    pub spp: Option<u32>,
    /// Render for this many seconds (with --spp: whichever ends first).
    #[arg(long, value_name = "SECONDS", value_parser = crate::numbers::seconds)]
    pub(crate) time: Option<Duration>,
    /// Worker threads (default: all cores; at most 4096).
    #[arg(long, value_parser = crate::numbers::threads)]
    pub(crate) threads: Option<usize>,
    /// Seed of the sample sequence: the same seed gives the same image.
    #[arg(long, default_value_t = 0)]
    pub(crate) seed: u32,
    /// How paths choose wavelengths: swc (stratified clusters from the
    /// lights' spectra), hero (rotated hero wavelengths), single.
    #[arg(long, default_value = "swc", value_name = "swc|hero|single")]
    pub(crate) wavelengths: WavelengthStrategy,
    /// Light transport: path (unidirectional, next-event estimation) or
    /// bdpt (bidirectional, every strategy weighted by MIS: for caustics,
    /// lamps in fixtures, light through small openings). Default: the
    /// scene's <integrator>.
    #[arg(long, value_name = "path|bdpt")]
    pub(crate) integrator: Option<IntegratorKind>,
    /// Bidirectional only: render strategy S,T alone without MIS (S light
    /// and T camera vertices; T=1 is light tracing), to inspect it.
    #[arg(long, value_name = "S,T")]
    pub(crate) bdpt_strategy: Option<BdptStrategy>,
    /// The path integrator's form: scalar (one path at a time, the
    /// reference, today the faster) or wavefront (batches of paths, stage
    /// by stage). Both give the same image, bit for bit. The wavefront
    /// tracer traces between surfaces only: with media, bdpt, illuminance
    /// or an irradiance meter it is an error.
    #[arg(long, default_value = "scalar", value_name = "scalar|wavefront")]
    pub(crate) tracer: Tracer,
    /// Path guiding: on learns where light arrives over the image's first
    /// 16 spp (kept in the image, the earliest weighted less), then draws
    /// half of each diffuse bounce (and of scattering in near-isotropic
    /// media) from it;
    /// with bdpt, it learns where light paths leaving each lamp reach the
    /// camera and draws half of their first directions from that (a lamp
    /// in a tube, the prism's beam) (docs/guiding.md). Not with the
    /// wavefront tracer or illuminance. Resumed renders and shards learn
    /// it again the same way, so they stay exact.
    #[arg(long, default_value = "off", value_name = "on|off")]
    pub(crate) guiding: Guiding,
    /// Wavelengths per path: 1, 2, 4, 8 or 16.
    #[arg(long, default_value = "4", value_name = "K")]
    pub(crate) cluster: ClusterSize,
    /// What each pixel holds: radiance (X, Y, Z in cd/m², V′) or
    /// illuminance (Y in lx, V′ in scotopic lx) at the first surface the
    /// pixel sees, on its side facing the camera — by the path tracer,
    /// whatever the scene's integrator; zero where no surface is seen —
    /// or melanopic-edi: that illuminance with the melanopic equivalent
    /// daylight illuminance (CIE S 026, lx) in channel mEDI in place of V
    /// (docs/lighting.md).
    #[arg(
        long,
        default_value = "radiance",
        value_name = "radiance|illuminance|melanopic-edi"
    )]
    pub(crate) quantity: Quantity,
}

/// A scene loaded and its render options checked, ready to render.
pub struct Prepared {
    pub scene: Scene,
    pub options: RenderOptions,
    pub params: Parameters,
    pub load: LoadOptions,
    /// Samples per pixel the render aims at (0: until its time is up).
    pub total: u32,
    pub pool: rayon::ThreadPool,
    /// Every file the scene read, the scene file first.
    pub files: Vec<PathBuf>,
}

impl Setup {
    /// Checks the options, loads the scene (printing its warnings) and
    /// starts the worker threads. `bands`: the spectral image's, if any.
    pub fn prepare(&self, bands: Option<usize>) -> Result<Prepared> {
        simd_level()?;
        if self.spp == Some(0) {
            bail!("--spp must be positive");
        }
        let load = load_options(self.res);
        let params = parameters(&self.define)?;
        let (scene, files) = load_scene_tracked(&self.scene, &params, &load)?;
        for w in &scene.warnings {
            eprintln!("scotopia: warning: {w}");
        }
        let options = RenderOptions {
            spp: self.spp,
            time_limit: self.time,
            seed: self.seed,
            strategy: self.wavelengths,
            cluster: self.cluster,
            bands,
            integrator: self.integrator,
            only_strategy: self.bdpt_strategy,
            tracer: self.tracer,
            quantity: self.quantity,
            shard: None,
            guiding: self.guiding,
        };
        let total = options.spp.unwrap_or(if self.time.is_some() {
            0
        } else {
            scene.samples_per_pixel
        });
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(self.threads.unwrap_or(0))
            .build()
            .context("cannot start the worker threads")?;
        Ok(Prepared {
            scene,
            options,
            params,
            load,
            total,
            pool,
            files,
        })
    }
}

/// What `render` and `measure` check before loading anything: the SIMD
/// level (`SCOTOPIA_SIMD`); clap has checked the options' text.
pub fn simd_level() -> Result<()> {
    scotopia_render::simd::Level::init().map_err(anyhow::Error::msg)?;
    Ok(())
}

/// A flag that Ctrl-C or SIGTERM sets: long work stops at its next
/// boundary and says so.
pub fn cancel_on_interrupt() -> Result<Arc<AtomicBool>> {
    let cancel = Arc::new(AtomicBool::new(false));
    let flag = cancel.clone();
    ctrlc::set_handler(move || flag.store(true, Ordering::Relaxed))
        .context("cannot install the Ctrl-C handler")?;
    Ok(cancel)
}

/// Renders here; `--ray` goes to `ray::render` instead (`crate::run_render`
/// chooses).
pub fn run(args: Args) -> Result<()> {
    check_outputs(&args, std::slice::from_ref(&args.setup.scene))?;
    let Prepared {
        scene,
        options,
        params,
        load,
        total,
        pool,
        files,
    } = args
        .setup
        .prepare(args.spectral.is_some().then_some(args.bands))?;
    check_outputs(&args, &files)?;
    // The vision pipeline's settings and size, checked before rendering.
    let display = match &args.display {
        Some(_) => {
            let (w, h) = (scene.camera.width as usize, scene.camera.height as usize);
            scotopia_vision::pipeline::check_size(w, h).context("--display")?;
            let (params, png, _) = args
                .vision
                .params(w, Some(scene.camera.fov_degrees().0 as f64))?;
            Some((params, png))
        }
        None => None,
    };

    let viewer = match &args.tev {
        Some(address) => Some(start_viewer(address, &args, &scene)?),
        None => None,
    };
    let see = |film: &Film, _: &RunFacts| {
        if let Some(v) = &viewer {
            v.see(film);
        }
    };
    let observer = viewer.as_ref().map(|_| Observer {
        every: crate::tev::every(),
        see: &see,
    });

    // Ctrl-C or SIGTERM: finish the current pass, write, exit non-zero.
    let cancel = cancel_on_interrupt()?;

    let pixels = scene.camera.width as u64 * scene.camera.height as u64;
    let bar = progress_bar(total as u64);
    // Guiding first learns (its first 16 spp): say so until the first
    // pass reports.
    if options.guiding == Guiding::On {
        bar.set_message(format!(
            "guiding: learning from {} spp",
            scotopia_render::guiding::LEARNED
        ));
    }
    let started = std::time::Instant::now();
    let terminal = std::io::IsTerminal::is_terminal(&std::io::stderr());
    let last_line = std::sync::atomic::AtomicU64::new(0);
    let progress = |done: u32, _: u32| {
        bar.set_position(done as u64);
        let secs = started.elapsed().as_secs_f64();
        let rate = done as f64 * pixels as f64 / secs.max(1e-9) * 1e-6;
        bar.set_message(format!("{rate:.2} Msamples/s"));
        // Without a terminal: a plain line every 10 seconds.
        let tick = (secs / 10.0) as u64;
        if !terminal && tick > last_line.swap(tick, Ordering::Relaxed) {
            eprintln!("scotopia: {done} spp, {secs:.0} s, {rate:.2} Msamples/s");
        }
    };
    let ckpt_path = checkpoint_path(&args.output);
    let every = match args.checkpoint {
        Some(t) => Some(checkpoint_interval(t).map_err(|e| anyhow::anyhow!("--checkpoint {e}"))?),
        None => None,
    };
    // A FIFO or device where the checkpoint goes is an error now, not at
    // the first save; the key hashes every file the scene read.
    let key = if every.is_some() || args.resume {
        Checkpoint::check_path(&ckpt_path).map_err(anyhow::Error::msg)?;
        Some(checkpoint_key(&files, &params, &load, &options).map_err(anyhow::Error::msg)?)
    } else {
        None
    };
    let resume = match &key {
        Some(key) if args.resume && ckpt_path.exists() => {
            let (c, saved) = Checkpoint::read_with(&ckpt_path).map_err(anyhow::Error::msg)?;
            if let Some(why) = key.refusal(c.key, &saved) {
                bail!("{}: cannot resume: {why}", ckpt_path.display());
            }
            eprintln!(
                "scotopia: resuming from {} ({} spp)",
                ckpt_path.display(),
                c.done
            );
            Some(c)
        }
        _ => {
            if args.resume {
                eprintln!(
                    "scotopia: no checkpoint {}: starting afresh",
                    ckpt_path.display()
                );
            }
            None
        }
    };
    let sources = key.as_ref().map_or(&[][..], |k| &k.sources[..]);
    let save = |c: &Checkpoint| c.write_with(&ckpt_path, sources);
    let checkpoints = match &key {
        Some(key) if every.is_some() || resume.is_some() => Some(Checkpointing {
            key: key.key,
            resume,
            // Resuming without --checkpoint still saves when interrupted.
            every: every.unwrap_or(Duration::MAX),
            save: &save,
        }),
        _ => None,
    };
    let saving = checkpoints.is_some();
    let rendered = pool
        .install(|| {
            let hooks = Hooks {
                progress: Some(&progress),
                checkpoints,
                observer,
                ..Hooks::new(&cancel)
            };
            render_with(&scene, &options, hooks)
        })
        .map_err(|e| match e {
            RenderError::Checkpoint(m) if !m.contains(&*ckpt_path.to_string_lossy()) => {
                anyhow::anyhow!("{}: {m}", ckpt_path.display())
            }
            e => e.into(),
        })?;
    bar.finish_and_clear();

    let meta = render_metadata(
        &scene,
        &options,
        &rendered.facts(),
        &args.setup.scene.display().to_string(),
    );
    // The means, once, for the EXR and the pictures.
    let means = rendered.film.xyzv();
    let (w, h) = (rendered.film.width as usize, rendered.film.height as usize);
    write_xyzv_pixels(&args.output, w, h, &means, &meta)?;
    if let Some(spectral) = &args.spectral {
        write_spectral_exr(spectral, &rendered, &meta)?;
    }
    if let Some(hdr) = &args.radiance {
        let view = scotopia_render::output::radiance_view(&scene);
        scotopia_image::radiance::write_radiance_hdr(hdr, w, h, &means, view.as_deref())?;
    }
    let secs = rendered.elapsed.as_secs_f64();
    eprintln!(
        "scotopia: {} spp in {secs:.1} s ({:.2} Msamples/s, {:.2} Mrays/s) → {}",
        rendered.spp,
        rendered.spp as f64 * pixels as f64 / secs.max(1e-9) * 1e-6,
        rendered.rays as f64 / secs.max(1e-9) * 1e-6,
        args.output.display()
    );
    eprintln!(
        "scotopia: {:.2} % of samples had their wavelength cluster collapsed to one wavelength (by a dispersive refraction, or by a chromatic medium in bdpt)",
        100.0 * rendered.collapsed_fraction()
    );
    if let Some(g) = rendered.guide {
        let worth = 100.0 * g.worth;
        if g.stopped && g.learned_spp == 0 {
            eprintln!(
                "scotopia: guiding declined before the first sample: a probe found it would lower the bounces' variance by about {worth:.1} % at most, less than its cost; the image is the unguided one (docs/guiding.md)"
            );
        } else if g.stopped {
            eprintln!(
                "scotopia: guiding stopped after {} spp: what it learned would lower the bounces' variance by about {worth:.1} % at most, less than its cost (docs/guiding.md)",
                g.learned_spp
            );
        } else {
            eprintln!(
                "scotopia: guiding learned from {} spp; its cells would lower the bounces' variance by about {worth:.0} %",
                g.learned_spp
            );
        }
    }
    if scene.meter.is_some() {
        // The one reading a lighting designer wants, without opening the EXR.
        let [_, y, _, v] = means[0];
        eprintln!(
            "scotopia: irradiancemeter: E = {y:.6e} lx, scotopic E′ = {v:.6e} lx (S/P {:.3})",
            if y > 0.0 { v / y } else { 0.0 }
        );
    }
    if rendered.nonfinite > 0 {
        eprintln!(
            "scotopia: warning: {} samples had NaN or infinite values and were dropped",
            rendered.nonfinite
        );
    }
    if rendered.nonfinite_splats > 0 {
        eprintln!(
            "scotopia: warning: {} light-tracing contributions had NaN or infinite values and were dropped",
            rendered.nonfinite_splats
        );
    }
    let shown = match (&args.display, &display) {
        (Some(out), Some((params, png))) => Some((out.as_path(), params, *png)),
        _ => None,
    };
    write_pictures(args.preview.as_deref(), shown, means, w, h)?;
    if let Some(v) = viewer {
        // The last frame is on its way: let it arrive, briefly.
        v.finish(Duration::from_secs(2));
    }
    if rendered.cancelled {
        let resume = if saving {
            format!("; continue with --resume (from {})", ckpt_path.display())
        } else {
            String::new()
        };
        bail!(
            "interrupted: wrote the {} spp accumulated so far{resume}",
            rendered.spp
        );
    }
    Ok(())
}

/// `--tev`: the viewer's sender, with the vision pipeline's settings for
/// its seen layer (left out, with a note, if the image is too large for
/// the pipeline).
fn start_viewer(
    address: &crate::tev::Address,
    args: &Args,
    scene: &Scene,
) -> Result<crate::tev::Viewer> {
    let (w, h) = (scene.camera.width, scene.camera.height);
    let vision = match scotopia_vision::pipeline::check_size(w as usize, h as usize) {
        Ok(()) => {
            let fov = Some(scene.camera.fov_degrees().0 as f64);
            Some(args.vision.params(w as usize, fov).context("--tev")?.0)
        }
        Err(e) => {
            eprintln!("scotopia: note: --tev: no seen layer: {e}");
            None
        }
    };
    let name = args.output.file_name().unwrap_or_default();
    let image = crate::tev::Image {
        name: name.to_string_lossy().into_owned(),
        width: w,
        height: h,
    };
    Ok(crate::tev::Viewer::start(address.clone(), image, vision))
}

/// `--preview` (auto-exposed sRGB) and `--display` (what the eye sees,
/// with its checked settings) of a finished render's means: after a local
/// render, and after `--ray` from the merged EXR.
pub(crate) fn write_pictures(
    preview: Option<&Path>,
    display: Option<(&Path, &DisplayParams, PngOptions)>,
    pixels: Vec<[f32; 4]>,
    w: usize,
    h: usize,
) -> Result<()> {
    if let Some(png) = preview {
        write_png_rgb8(png, w as u32, h as u32, &preview_srgb8(&pixels))?;
    }
    if let Some((out, params, png)) = display {
        let shown = scotopia_vision::display_owned(pixels, w, h, params);
        crate::display::say_left_out(&shown);
        write_shown(out, &shown, params, png)?;
    }
    Ok(())
}

/// Refuses outputs that are one of the run's `inputs` (the scene and the
/// files it reads) or that name one file twice.
pub(crate) fn check_outputs(args: &Args, inputs: &[PathBuf]) -> Result<()> {
    let ckpt = checkpoint_path(&args.output);
    let mut outputs: Vec<(&str, &Path)> = vec![("-o", &args.output)];
    for (flag, path) in [
        ("--spectral", &args.spectral),
        ("--preview", &args.preview),
        ("--radiance", &args.radiance),
        ("--display", &args.display),
    ] {
        if let Some(p) = path {
            outputs.push((flag, p));
        }
    }
    if args.checkpoint.is_some() || args.resume {
        // The checkpoint goes beside -o: beside /dev/null or a FIFO it
        // would be a stray file among devices, and it could not be
        // matched to the film it belongs to.
        if let Ok(m) = std::fs::metadata(&args.output) {
            if !m.is_file() {
                bail!(
                    "-o {} is {}: --checkpoint and --resume keep OUT.ckpt beside a file; give -o a file",
                    args.output.display(),
                    scotopia_image::output_file::describe(&m)
                );
            }
        }
        outputs.push(("the checkpoint", &ckpt));
    }
    let inputs = named_inputs("the scene", inputs);
    scotopia_image::check_outputs(&inputs, &outputs).map_err(anyhow::Error::msg)
}

/// A run's input files named for an error: the first as `first` (the
/// scene, or the image or scene `view` shows), the others as files the
/// scene reads.
pub(crate) fn named_inputs<'a>(
    first: &'static str,
    files: &'a [PathBuf],
) -> Vec<(&'static str, &'a Path)> {
    let what = |i: usize| {
        if i == 0 {
            first
        } else {
            "a file the scene reads"
        }
    };
    files
        .iter()
        .enumerate()
        .map(|(i, p)| (what(i), p.as_path()))
        .collect()
}

/// Where `--checkpoint` saves and `--resume` reads: beside the output.
fn checkpoint_path(output: &Path) -> PathBuf {
    let mut name = output.file_name().unwrap_or_default().to_os_string();
    name.push(".ckpt");
    output.with_file_name(name)
}

/// A bar with elapsed time, ETA and throughput on a terminal (hidden
/// elsewhere, where `run` prints plain lines instead).
pub(crate) fn progress_bar(total: u64) -> ProgressBar {
    if total == 0 {
        // Time-limited: a spinner.
        let bar = ProgressBar::new_spinner();
        if !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
            bar.set_draw_target(ProgressDrawTarget::hidden());
        }
        bar.set_style(
            ProgressStyle::with_template("{spinner} {elapsed} {pos} spp {msg}")
                .unwrap_or_else(|_| ProgressStyle::default_spinner()),
        );
        return bar;
    }
    let bar = ProgressBar::new(total);
    bar.set_style(
        ProgressStyle::with_template(
            "{bar:40} {pos}/{len} spp  {elapsed} elapsed, {eta} left  {msg}",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar()),
    );
    if !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
        bar.set_draw_target(ProgressDrawTarget::hidden());
    }
    bar
}

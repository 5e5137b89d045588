//! `render --ray`: the render on a Ray cluster. Ray's API is Python's, so
//! this runs the Python package's `python -m scotopia.distributed` with the
//! render's arguments (scotopia adds no network protocol of its own): its
//! progress and errors pass through, and the preview and what the eye
//! sees are made here from the merged EXR, as after a local render.
//!
//! An address that does not answer fails within the driver's connect
//! timeout (30 s, `SCOTOPIA_RAY_CONNECT_TIMEOUT`). Ctrl-C or SIGTERM to
//! this process is passed to the driver (which runs in its own process
//! group, so it gets it once) as SIGINT: it cancels the shards left,
//! merges and writes those that finished; a driver still running
//! `STOP_GRACE` later (stuck connecting, in Ray's C++) is killed.

use std::io::Read;
use std::process::{Child, Command, Stdio};
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use anyhow::{bail, Context, Result};
use nix::sys::signal::{kill, Signal};
use nix::unistd::Pid;

use scotopia_image::{read_xyzv, RgbInput};

use crate::render::{cancel_on_interrupt, check_outputs, write_pictures, Args};

pub fn render(args: &Args, address: &str) -> Result<()> {
    check_outputs(args, std::slice::from_ref(&args.setup.scene))?;
    let s = &args.setup;
    for (given, flag) in [
        (s.time.is_some(), "--time"),
        (s.threads.is_some(), "--threads"),
        (s.bdpt_strategy.is_some(), "--bdpt-strategy"),
        (args.checkpoint.is_some(), "--checkpoint"),
        (args.resume, "--resume"),
        (args.spectral.is_some(), "--spectral"),
        (args.tev.is_some(), "--tev"),
    ] {
        if given {
            bail!("{flag} is not available with --ray (docs/distributed.md)");
        }
    }
    if args.shards == Some(0) {
        bail!("--shards 0: give at least one shard");
    }
    let python = std::env::var("SCOTOPIA_PYTHON").unwrap_or_else(|_| "python3".into());
    let mut cmd = Command::new(&python);
    cmd.args(["-m", "scotopia.distributed"])
        .arg(&s.scene)
        .arg("-o")
        .arg(&args.output)
        .args(["--seed", &s.seed.to_string()])
        .args(["--wavelengths", &s.wavelengths.to_string()])
        .args(["--cluster", &s.cluster.to_string()])
        .args(["--tracer", &s.tracer.to_string()])
        .args(["--guiding", &s.guiding.to_string()])
        .args(["--quantity", &s.quantity.to_string()]);
    let optional = [
        ("--spp", s.spp.map(|n| n.to_string())),
        ("--integrator", s.integrator.map(|k| k.to_string())),
        ("--res", s.res.map(|r| r.to_string())),
        ("--shards", args.shards.map(|n| n.to_string())),
        (
            "--address",
            Some(address.to_string()).filter(|a| !a.is_empty()),
        ),
    ];
    for (flag, value) in optional {
        if let Some(v) = value {
            cmd.arg(flag).arg(v);
        }
    }
    for d in &s.define {
        cmd.arg("-D").arg(d);
    }
    let cancel = cancel_on_interrupt()?;
    // Its own process group: a terminal's Ctrl-C reaches this process
    // only, which passes it on once (see `wait_forwarding`).
    std::os::unix::process::CommandExt::process_group(&mut cmd, 0);
    let mut child = cmd
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::inherit())
        .spawn()
        .with_context(|| {
            format!(
                "--ray: cannot run {python}: install Python 3 and `pip install scotopia[distributed]`, or set SCOTOPIA_PYTHON"
            )
        })?;
    // Read on a thread, so that a large report never blocks the driver.
    let mut stdout = child
        .stdout
        .take()
        .context("--ray: no pipe from the driver")?;
    let reader = std::thread::spawn(move || {
        let mut bytes = Vec::new();
        stdout.read_to_end(&mut bytes).map(|_| bytes)
    });
    let (status, stopped) = wait_forwarding(&mut child, &cancel)?;
    let report = reader
        .join()
        .map_err(|_| anyhow::anyhow!("--ray: the driver's report could not be read"))?
        .context("--ray: the driver's report could not be read")?;
    if !status.success() {
        if stopped {
            bail!("interrupted: the distributed render was stopped ({python} -m scotopia.distributed: {status})");
        }
        bail!(
            "--ray: the distributed render failed ({python} -m scotopia.distributed: {status}); with Ray and the scotopia package installed (`pip install scotopia[distributed]`) its error is above",
        );
    }
    let meta: serde_json::Value = serde_json::from_slice(&report)
        .context("--ray: the distributed render's report is not JSON")?;

    // The preview and the eye's view, from the merged image.
    let image = read_xyzv(&args.output, RgbInput::default())?;
    let (w, h) = (image.width, image.height);
    let (params, png, _) = args.vision.params(w, image.fov_horizontal)?;
    let shown = args.display.as_deref().map(|out| (out, &params, png));
    write_pictures(args.preview.as_deref(), shown, image.pixels, w, h)?;
    let shards = meta["shards"].as_u64().unwrap_or(0);
    let merged = meta["shardsMerged"].as_u64().unwrap_or(shards);
    eprintln!(
        "scotopia: {} spp from {merged} of {shards} shards on Ray in {:.1} s → {}",
        meta["samplesPerPixel"],
        meta["wallSeconds"].as_f64().unwrap_or(0.0),
        args.output.display()
    );
    if meta["interrupted"].as_i64().unwrap_or(0) != 0 {
        bail!(
            "interrupted: wrote the {merged} of {shards} shards that had finished → {}",
            args.output.display()
        );
    }
    Ok(())
}

/// How long the driver has, once asked to stop, to merge what finished
/// and exit before it is killed.
pub const STOP_GRACE: Duration = Duration::from_secs(10);

/// Waits for the driver; when `cancel` is set (Ctrl-C, SIGTERM) sends it
/// SIGINT once, and SIGKILL if it is still running `STOP_GRACE` later.
/// Returns its exit status and whether it was asked to stop.
fn wait_forwarding(
    child: &mut Child,
    cancel: &AtomicBool,
) -> Result<(std::process::ExitStatus, bool)> {
    let pid = Pid::from_raw(i32::try_from(child.id()).context("--ray: the driver's process id")?);
    let mut asked: Option<Instant> = None;
    loop {
        if let Some(status) = child.try_wait().context("--ray: waiting for the driver")? {
            return Ok((status, asked.is_some()));
        }
        match asked {
            None if cancel.load(Ordering::Relaxed) => {
                eprintln!(
                    "scotopia: stopping the distributed render (merging the shards that finished)"
                );
                // Gone already: try_wait reports it next.
                let _ = kill(pid, Signal::SIGINT);
                asked = Some(Instant::now());
            }
            Some(t) if t.elapsed() > STOP_GRACE => {
                eprintln!(
                    "scotopia: the distributed render did not stop within {} s: killing it",
                    STOP_GRACE.as_secs()
                );
                let _ = child.kill();
                return Ok((child.wait().context("--ray: waiting for the driver")?, true));
            }
            _ => {}
        }
        std::thread::sleep(Duration::from_millis(50));
    }
}

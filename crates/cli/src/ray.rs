//! `render --ray`: the render on a Ray cluster. Ray's API is Python's, so
//! this runs the Python package's `python -m scotopia.distributed` with the
//! render's arguments (scotopia adds no network protocol of its own): its
//! progress and errors pass through, Ctrl-C reaches it too (it merges the
//! shards that finished and writes them), and the preview and what the
//! eye sees are made here from the merged EXR, as after a local render.

use std::process::{Command, Stdio};

use anyhow::{bail, Context, Result};

use scotopia_image::{read_xyzv, RgbInput};

use crate::render::{cancel_on_interrupt, write_pictures, Args};

pub fn render(args: &Args, address: &str) -> Result<()> {
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
        .args(["--wavelengths", &s.wavelengths])
        .args(["--cluster", &s.cluster.to_string()])
        .args(["--tracer", &s.tracer])
        .args(["--quantity", &s.quantity]);
    let optional = [
        ("--spp", s.spp.map(|n| n.to_string())),
        ("--integrator", s.integrator.clone()),
        ("--res", s.res.clone()),
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
    // Ctrl-C goes to the whole process group: the Python side stops and
    // merges; this process waits for it rather than dying first.
    let _ = cancel_on_interrupt()?;
    let out = cmd
        .stdin(Stdio::null())
        .stderr(Stdio::inherit())
        .output()
        .with_context(|| {
            format!(
                "--ray: cannot run {python}: install Python 3 and `pip install scotopia[distributed]`, or set SCOTOPIA_PYTHON"
            )
        })?;
    if !out.status.success() {
        bail!(
            "--ray: the distributed render failed ({python} -m scotopia.distributed: {}); with Ray and the scotopia package installed (`pip install scotopia[distributed]`) its error is above",
            out.status
        );
    }
    let meta: serde_json::Value = serde_json::from_slice(&out.stdout)
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

//! The pass driver: runs passes of samples over the film until the
//! samples or the time asked for are done or the render is cancelled,
//! saving checkpoints and showing the film to an observer on the way.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use crate::film::{Bands, Checkpoint, Film, SampleCounts};
use crate::scene::{IntegratorKind, Scene};

use super::{ClusterSize, Quantity, RenderError, RenderOptions, Renderer};

/// A finished (or interrupted) render.
#[derive(Debug, Clone, PartialEq)]
pub struct Rendered {
    pub film: Film,
    /// Samples per pixel completed on every pixel.
    pub spp: u32,
    /// Samples whose estimate was NaN or infinite, dropped.
    pub nonfinite: u64,
    /// Light-tracing contributions (bdpt's t = 1 splats) that were NaN or
    /// infinite, dropped; counted apart because a camera sample makes any
    /// number of them.
    pub nonfinite_splats: u64,
    /// Rays traced (camera, continuation and shadow rays).
    pub rays: u64,
    /// Samples (kept ones) whose cluster of several wavelengths collapsed
    /// to one at a dispersive refraction.
    pub collapsed: u64,
    pub elapsed: Duration,
    /// Stopped by `cancel` rather than by `spp` or time.
    pub cancelled: bool,
    /// The transport that rendered it: the options' or the scene's, or the
    /// path tracer for an irradiancemeter.
    pub integrator: IntegratorKind,
    /// What the pixels hold: `RenderOptions::quantity`, or illuminance
    /// when the scene's sensor is an irradiancemeter.
    pub quantity: Quantity,
    /// With guiding on, what the guide learned.
    pub guide: Option<GuideFacts>,
}

/// What a render's guide learned (`crate::guiding`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GuideFacts {
    /// Samples per pixel it learned from.
    pub learned_spp: u32,
    /// The share of the bounces' variance its last field was predicted
    /// to remove (`Field::worth`).
    pub worth: f32,
    /// Whether it stopped, worth too little (`guiding::STOP`).
    pub stopped: bool,
}

/// What a render has done so far (or did): for an image's metadata and
/// for observers.
#[derive(Debug, Clone, Copy)]
pub struct RunFacts {
    pub spp: u32,
    pub rays: u64,
    pub elapsed: Duration,
    pub cancelled: bool,
    pub integrator: IntegratorKind,
    pub quantity: Quantity,
}

impl Rendered {
    /// Its [`RunFacts`].
    pub fn facts(&self) -> RunFacts {
        RunFacts {
            spp: self.spp,
            rays: self.rays,
            elapsed: self.elapsed,
            cancelled: self.cancelled,
            integrator: self.integrator,
            quantity: self.quantity,
        }
    }

    /// The share of kept samples whose cluster collapsed (0 with one
    /// wavelength per path, where there is nothing to collapse).
    pub fn collapsed_fraction(&self) -> f64 {
        let kept = self.spp as u64 * self.film.width as u64 * self.film.height as u64;
        let kept = kept.saturating_sub(self.nonfinite);
        if kept == 0 {
            0.0
        } else {
            self.collapsed as f64 / kept as f64
        }
    }
}

/// Checkpoints of a long render ([`Hooks::checkpoints`]).
pub struct Checkpointing<'a> {
    /// The fingerprint of the scene and options, stored in each checkpoint.
    pub key: u64,
    /// A checkpoint of this same render to continue from.
    pub resume: Option<Checkpoint>,
    /// How often `save` is called (at the first pass boundary after).
    pub every: Duration,
    /// Stores a checkpoint; called at pass boundaries and at the end
    /// (complete, interrupted or out of time).
    pub save: &'a (dyn Fn(&Checkpoint) -> Result<(), String> + Sync),
}

/// Samples per pixel of the pass that starts after `done`: 1, 1, 2, 4, 8,
/// then 16. A function of `done` alone, so that a resumed render passes
/// the same boundaries as an uninterrupted one (light-tracing splats are
/// added at pass ends, and the order of additions fixes the bits).
fn pass_size(done: u32) -> u32 {
    match done {
        0 => 1,
        d => (1 << (31 - d.leading_zeros())).min(16),
    }
}

/// Renders `scene`. `progress(done, total)` is called after each pass
/// (samples per pixel); setting `cancel` stops after the current pass.
pub fn render(
    scene: &Scene,
    options: &RenderOptions,
    cancel: &AtomicBool,
    progress: &(dyn Fn(u32, u32) + Sync),
) -> Result<Rendered, RenderError> {
    let hooks = Hooks {
        progress: Some(progress),
        ..Hooks::new(cancel)
    };
    render_with(scene, options, hooks)
}

/// Looks at the film while a render runs (a live viewer, tev): `see(film,
/// facts)` is called at the first pass boundary after every `every` and once
/// at the end, on the rendering thread, so it should copy what it needs
/// and return.
pub struct Observer<'a> {
    pub every: Duration,
    pub see: &'a (dyn Fn(&Film, &RunFacts) + Sync),
}

/// What a render answers to and reports to as it goes.
pub struct Hooks<'a> {
    /// Setting it stops the render after the current pass.
    pub cancel: &'a AtomicBool,
    /// Called after each pass with (samples per pixel done, asked for).
    pub progress: Option<&'a (dyn Fn(u32, u32) + Sync)>,
    /// Checkpoints to save, and one to continue from: a render resumed
    /// from a checkpoint ends bit-identical to the uninterrupted render
    /// of the same scene, options and samples per pixel.
    pub checkpoints: Option<Checkpointing<'a>>,
    /// Shown the film as it converges.
    pub observer: Option<Observer<'a>>,
}

impl<'a> Hooks<'a> {
    /// Only `cancel`: no progress, checkpoints or observer.
    pub fn new(cancel: &'a AtomicBool) -> Self {
        Self {
            cancel,
            progress: None,
            checkpoints: None,
            observer: None,
        }
    }
}

/// Renders `scene` with the `hooks` given: [`render`] with checkpoints and
/// an observer.
pub fn render_with(
    scene: &Scene,
    options: &RenderOptions,
    hooks: Hooks,
) -> Result<Rendered, RenderError> {
    match options.cluster {
        ClusterSize::K1 => render_k::<1>(scene, options, hooks),
        ClusterSize::K2 => render_k::<2>(scene, options, hooks),
        ClusterSize::K4 => render_k::<4>(scene, options, hooks),
        ClusterSize::K8 => render_k::<8>(scene, options, hooks),
        ClusterSize::K16 => render_k::<16>(scene, options, hooks),
    }
}

fn render_k<const K: usize>(
    scene: &Scene,
    options: &RenderOptions,
    hooks: Hooks,
) -> Result<Rendered, RenderError> {
    let Hooks {
        cancel,
        progress,
        mut checkpoints,
        observer,
    } = hooks;
    // A time limit alone renders until the time is spent.
    let total = match (&options.shard, options.spp, options.time_limit) {
        (Some(shard), _, _) => shard.samples.end,
        (None, Some(n), _) => n,
        (None, None, Some(_)) => u32::MAX,
        (None, None, None) => scene.samples_per_pixel,
    };
    if total == 0 {
        return Err(RenderError::Spp);
    }
    let start = Instant::now();
    let mut renderer = Renderer::new(scene, options)?;
    let (integrator, quantity) = (renderer.kind, renderer.integrator.quantity());
    let first = match &options.shard {
        Some(shard) => {
            if shard.samples.is_empty() {
                return Err(RenderError::Spp);
            }
            if let Some(rows) = &shard.rows {
                renderer.rows = rows.clone();
            }
            shard.samples.start
        }
        None => 0,
    };
    let bands = match options.bands {
        Some(n) if (1..=471).contains(&n) => Some(Bands(n)),
        Some(_) => return Err(RenderError::Bands),
        None => None,
    };
    let (width, height) = (scene.camera.width, scene.camera.height);
    let mut state = match checkpoints.as_mut().and_then(|c| c.resume.take()) {
        Some(c) => {
            let key = checkpoints.as_ref().map_or(0, |c| c.key);
            if c.key != key {
                return Err(RenderError::Checkpoint(
                    "the checkpoint was saved by a render of another scene, with other options, or before a file the scene reads was edited"
                        .into(),
                ));
            }
            if (c.film.width, c.film.height, c.film.bands) != (width, height, bands) {
                return Err(RenderError::Checkpoint(format!(
                    "the checkpoint's film is {}×{}, the render's {width}×{height} (or its bands differ)",
                    c.film.width, c.film.height
                )));
            }
            if c.done > total {
                return Err(RenderError::Checkpoint(format!(
                    "the checkpoint holds {} spp, more than the {total} asked for",
                    c.done
                )));
            }
            c
        }
        None => {
            let mut film = Film::try_new(width, height, bands)
                .map_err(|e| RenderError::TooLarge(Box::new(e)))?;
            if options.shard.is_some() {
                film.keep_moments();
            }
            Checkpoint {
                key: checkpoints.as_ref().map_or(0, |c| c.key),
                done: first,
                counts: SampleCounts::default(),
                film,
            }
        }
    };
    let resumed_at = state.done;
    // With guiding, the image's first samples are the guide's learning
    // iterations (`learn.rs`); those a resumed render or a later shard
    // does not render are learned first, apart.
    if renderer.guiding.is_some() {
        renderer.catch_up::<K>(options.seed, state.done, cancel)?;
    }
    let rendering = Instant::now();
    let mut cancelled = false;
    let mut last_save = Instant::now();
    let mut last_seen = Instant::now();
    // Passes grow from 1 spp so that progress, time limits and Ctrl-C are
    // honoured early, to at most 16 spp per pass.
    while state.done < total {
        if cancel.load(Ordering::Relaxed) {
            cancelled = true;
            break;
        }
        let done = state.done;
        // A learning iteration is one pass (`learn.rs`).
        let learning = renderer.learning(done);
        let size = learning.map_or(pass_size(done), |(_, end)| end - done);
        let mut count = size.min(total - done);
        if let Some(limit) = options.time_limit {
            // Only as many samples as the time left should allow, judged by
            // the rate so far, so a time limit is met rather than overrun
            // by a whole pass (and is spent, not left half unused).
            let elapsed = start.elapsed();
            if elapsed >= limit {
                break;
            }
            if done > resumed_at {
                let per_spp = rendering.elapsed().as_secs_f64() / (done - resumed_at) as f64;
                let fits = ((limit - elapsed).as_secs_f64() / per_spp) as u32;
                if fits == 0 {
                    break;
                }
                count = count.min(fits);
            }
        }
        let c = if learning.is_some() {
            renderer.learning_pass::<K>(options.seed, &mut state.film, done, count)?
        } else {
            renderer.pass::<K>(options.seed, &mut state.film, (done, count, 1.0), None)
        };
        state.counts += c;
        state.done += count;
        if let Some(progress) = progress {
            progress(state.done, total);
        }
        if let Some(cp) = &checkpoints {
            if state.done < total && last_save.elapsed() >= cp.every {
                (cp.save)(&state).map_err(RenderError::Checkpoint)?;
                last_save = Instant::now();
            }
        }
        if let Some(o) = &observer {
            if state.done < total && last_seen.elapsed() >= o.every {
                let facts = RunFacts {
                    spp: state.done,
                    rays: state.counts.rays,
                    elapsed: start.elapsed(),
                    cancelled: false,
                    integrator,
                    quantity,
                };
                (o.see)(&state.film, &facts);
                last_seen = Instant::now();
            }
        }
    }
    if let Some(cp) = &checkpoints {
        (cp.save)(&state).map_err(RenderError::Checkpoint)?;
    }
    let Checkpoint {
        done,
        counts:
            SampleCounts {
                dropped,
                dropped_splats,
                rays,
                collapsed,
            },
        film,
        ..
    } = state;
    let guide = renderer.guiding.as_ref().map(|g| GuideFacts {
        learned_spp: crate::guiding::BOUNDARIES[g.guide.learned()],
        worth: g.guide.field().worth(),
        stopped: g.guide.stopped(),
    });
    let rendered = Rendered {
        guide,
        film,
        spp: done,
        nonfinite: dropped,
        nonfinite_splats: dropped_splats,
        rays,
        collapsed,
        elapsed: start.elapsed(),
        cancelled,
        integrator,
        quantity,
    };
    if let Some(o) = &observer {
        (o.see)(&rendered.film, &rendered.facts());
    }
    Ok(rendered)
}

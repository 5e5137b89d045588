//! Rendering a scene onto the film: the per-scene state the integrator
//! needs (`Renderer`), and the parallel driver that runs samples pixel by
//! pixel until the requested count or time is reached, or it is cancelled.

mod bdpt;
mod equiangular;
mod light_choice;
mod measure;
mod path;
mod reflectors;
mod volume;
mod wavefront;

pub use bdpt::Splat;
pub use light_choice::LightChoice;
pub use measure::{measure, Measured, Receiver};
pub use path::CameraSample;
pub use reflectors::Reflectors;

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use rayon::prelude::*;

use scotopia_color::SampledWavelengths;

use crate::accel::Aabb;
use crate::camera::Projection;
use crate::film::{Bands, Checkpoint, Film, FilterSampler};
use crate::geometry::Shape;
use crate::light::{Caster, Light, SceneExtent};
use crate::math::Vec3;
use crate::sampling::distribution::Distribution1D;
use crate::sampling::sobol::Sampler;
use crate::scene::{IntegratorKind, Scene};
use crate::wavelength::{WavelengthSampler, WavelengthStrategy};

/// Cluster sizes K the renderer is compiled for.
pub const CLUSTER_SIZES: [usize; 5] = [1, 2, 4, 8, 16];

/// What to render, beyond the scene.
#[derive(Debug, Clone, PartialEq)]
pub struct RenderOptions {
    /// Samples per pixel (the scene's when `None`).
    pub spp: Option<u32>,
    /// Stop after this long, even before `spp` is reached.
    pub time_limit: Option<Duration>,
    pub seed: u32,
    pub strategy: WavelengthStrategy,
    /// Wavelengths per path, one of `CLUSTER_SIZES`.
    pub cluster: usize,
    /// Also accumulate spectral radiance in this many bands.
    pub bands: Option<usize>,
    /// The integrator (the scene's when `None`).
    pub integrator: Option<IntegratorKind>,
    /// Bidirectional only: render strategy [s, t] alone, without MIS (a
    /// check that each strategy converges to the same image).
    pub only_strategy: Option<[usize; 2]>,
    /// Which tracer runs the path integrator.
    pub tracer: Tracer,
    /// What each pixel holds: the radiance reaching the camera, or the
    /// illuminance at the first surface the pixel sees.
    pub quantity: Quantity,
    /// Render only part of the work (distributed rendering): the film
    /// holds that part's raw sums, to be merged with the others'.
    pub shard: Option<Shard>,
}

/// A part of a render: sample indices `samples` of the pixels in `rows`
/// (all rows if `None`). A pixel's random numbers depend only on (seed,
/// pixel, index), so shards merged by adding their sums give the whole
/// render: bit for bit when each pixel's samples are in one shard (its
/// sum is the same additions in the same order), else within f64
/// rounding (the sums are added in another order).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Shard {
    pub samples: std::ops::Range<u32>,
    pub rows: Option<std::ops::Range<u32>>,
}

/// What a render measures at each pixel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Quantity {
    /// X, Y, Z (cd/m²) and V′ (scotopic cd/m²) of the light reaching the
    /// camera.
    #[default]
    Radiance,
    /// X, Y, Z (Y in lx) and V′ (scotopic lx) of the light falling on the
    /// first surface each pixel sees, on the side facing the camera (the
    /// path tracer's own transport at a virtual receiver there,
    /// `measure.rs`); zero where the pixel sees no surface.
    Illuminance,
}

impl Quantity {
    /// `radiance` or `illuminance`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "radiance" => Some(Self::Radiance),
            "illuminance" => Some(Self::Illuminance),
            _ => None,
        }
    }

    /// Its name, as `from_name` reads it and the EXR's metadata says.
    pub fn name(self) -> &'static str {
        match self {
            Self::Radiance => "radiance",
            Self::Illuminance => "illuminance",
        }
    }
}

/// The two forms of the path tracer: one path at a time (the reference)
/// or batches of paths run stage by stage (`wavefront`). They give the
/// same image, bit for bit; the bidirectional tracer has one form. The
/// scalar one is the default while it is the faster (docs/performance.md:
/// the wavefront's stages are not yet vectorised beyond its samplers).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Tracer {
    Wavefront,
    #[default]
    Scalar,
}

impl Tracer {
    /// `wavefront` or `scalar`.
    pub fn from_name(name: &str) -> Option<Self> {
        match name {
            "wavefront" => Some(Self::Wavefront),
            "scalar" => Some(Self::Scalar),
            _ => None,
        }
    }
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            spp: None,
            time_limit: None,
            seed: 0,
            strategy: WavelengthStrategy::Swc,
            cluster: 4,
            bands: None,
            integrator: None,
            only_strategy: None,
            tracer: Tracer::default(),
            quantity: Quantity::default(),
            shard: None,
        }
    }
}

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

/// What a pass counted.
#[derive(Debug, Clone, Copy, Default)]
struct PassCounts {
    /// Samples whose estimate was not finite, dropped.
    dropped: u64,
    /// Light-tracing splats that were not finite, dropped.
    dropped_splats: u64,
    rays: u64,
    /// Samples whose whole cluster collapsed at a dispersive refraction.
    collapsed: u64,
}

/// Errors in the options.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RenderError {
    #[error("cluster size {0} is not supported (use one of 1, 2, 4, 8, 16)")]
    Cluster(usize),
    #[error("samples per pixel must be positive")]
    Spp,
    #[error("spectral bands must number 1 to 471 (at least 1 nm wide)")]
    Bands,
    #[error("strategy s={0}, t={1} does not exist (t ≥ 1, s + t ≥ 2) or needs --integrator bdpt")]
    Strategy(usize, usize),
    #[error("the bidirectional tracer needs a perspective or thin-lens camera (an orthographic camera cannot be reached from a light); render with path")]
    BdptProjection,
    #[error("{0}")]
    TooLarge(Box<scotopia_image::TooLarge>),
    #[error("{0}")]
    Checkpoint(String),
    #[error("receiver {0}: its point and normal must be finite and the normal not zero")]
    Receiver(usize),
}

/// Checkpoints of a long render (`render_resumable`).
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

/// The bounding spheres of the shapes (outside shape groups) whose BSDF
/// casts caustics: where lights at infinity aim part of their light
/// subpaths (`light::emit_disk`).
fn casters(scene: &Scene) -> Vec<Caster> {
    let shapes = &scene.geometry.shapes;
    Caster::select(shapes.iter().enumerate().map(|(i, shape)| {
        let bsdf = scene
            .shape_material
            .get(i)
            .and_then(|&m| scene.materials.get(m as usize));
        let bound = match shape {
            Shape::Sphere(s) => Caster {
                center: s.center,
                radius: s.radius,
            },
            _ => {
                let b = (0..shape.primitive_count())
                    .fold(Aabb::EMPTY, |b, prim| b.union(shape.bounds(prim)));
                Caster {
                    center: b.centroid(),
                    radius: 0.5 * b.extent().length(),
                }
            }
        };
        (bound, bsdf.is_some_and(|b| b.casts_caustics()))
    }))
}

/// Where a light at a finite place is (its bounding box's centre for an
/// area light), for equi-angular sampling; `None` at infinity.
fn light_centre(light: &Light, shapes: &[Shape]) -> Option<Vec3> {
    match light {
        Light::Point(l) => Some(l.position),
        Light::Spot(l) => Some(l.position),
        Light::Goniometric(l) => Some(l.position),
        Light::Projector(l) => Some(l.position),
        Light::Area(a) => {
            let shape = shapes.get(a.shape as usize)?;
            let b = (0..shape.primitive_count())
                .fold(Aabb::EMPTY, |b, prim| b.union(shape.bounds(prim)));
            (!b.is_empty()).then(|| b.centroid())
        }
        Light::Directional(_) | Light::Constant(_) | Light::EnvMap(_) => None,
    }
}

/// Per-scene state shared by all samples.
pub struct Renderer<'a> {
    pub scene: &'a Scene,
    /// Light choice by radiant power (wavelengths, the bidirectional
    /// tracer's clusters).
    pub light_choice: Distribution1D,
    /// The path tracer's light choice for next-event estimation, by power
    /// over squared distance.
    pub nee_choice: LightChoice,
    /// Glossy surfaces lamps light brightly, which the path tracer's
    /// diffuse bounces aim at in part (`reflectors`).
    pub reflectors: Reflectors,
    pub wavelengths: WavelengthSampler,
    pub filter: FilterSampler,
    center: Vec3,
    radius: f32,
    /// The shapes light subpaths from infinity are aimed at.
    casters: Vec<Caster>,
    infinite: Vec<usize>,
    pub integrator: IntegratorKind,
    /// Bidirectional: the lights' spectra, to choose a light by cluster.
    light_spectra: Option<bdpt::LightSpectra>,
    only_strategy: Option<[usize; 2]>,
    tracer: Tracer,
    quantity: Quantity,
    /// The film rows a pass renders (a shard's; all by default).
    rows: std::ops::Range<u32>,
    /// The white Lambertian surface of virtual receivers (`measure.rs`).
    white: crate::bsdf::Bsdf,
    /// The lights equi-angular sampling aims at in media (empty when
    /// media are not traced).
    targets: equiangular::Targets,
    /// Whether paths are traced through media (`volume.rs`): the
    /// integrator traces them and the scene has media or surfaces that
    /// pass light (null lobes, which such an integrator treats as media
    /// boundaries).
    volumetric: bool,
}

impl<'a> Renderer<'a> {
    /// The scene's integrator with `strategy`.
    pub fn new(scene: &'a Scene, strategy: WavelengthStrategy) -> Self {
        Self::with_integrator(scene, strategy, scene.integrator.kind)
    }

    pub fn with_integrator(
        scene: &'a Scene,
        strategy: WavelengthStrategy,
        integrator: IntegratorKind,
    ) -> Self {
        let bounds = scene.geometry.bounds();
        let (center, radius) = if bounds.is_empty() {
            (Vec3::ZERO, 1.0)
        } else {
            (
                bounds.centroid(),
                (0.5 * bounds.extent().length()).max(1e-3),
            )
        };
        let extent = SceneExtent {
            shapes: &scene.geometry.shapes,
            center,
            radius,
            casters: &[],
        };
        let power: Vec<f32> = scene
            .lights
            .iter()
            .map(|l| l.power(&extent).watts as f32)
            .collect();
        // The path tracer draws some wavelengths from fluorescent
        // emission; the bidirectional tracer reaches them by re-emission
        // on its light subpaths and draws from the lights alone.
        let fluorescent: Vec<_> = match integrator {
            IntegratorKind::Path => scene
                .materials
                .iter()
                .filter_map(|m| m.fluorescent())
                .collect(),
            IntegratorKind::Bdpt => Vec::new(),
        };
        let light_choice = Distribution1D::new(power.clone());
        let light_spectra = (integrator == IntegratorKind::Bdpt).then(|| {
            let p = (0..scene.lights.len())
                .map(|i| light_choice.probability(i))
                .collect();
            bdpt::LightSpectra::new(&scene.lights, p)
        });
        let nee_choice = LightChoice::new(&scene.lights, &power, &extent);
        let reflectors = Reflectors::new(
            &scene.materials,
            &scene.shape_material,
            &scene.shape_light,
            &scene.lights,
            &power,
            &extent,
        );
        let volumetric = scene.integrator.media
            && (!scene.media.is_empty() || scene.materials.iter().any(|m| m.may_pass()));
        let targets = if volumetric {
            equiangular::Targets::new(
                (0..scene.lights.len())
                    .filter_map(|i| {
                        let c = light_centre(&scene.lights[i], &scene.geometry.shapes)?;
                        Some((c, light_choice.probability(i)))
                    })
                    .collect(),
                radius,
            )
        } else {
            equiangular::Targets::default()
        };
        Self {
            nee_choice,
            reflectors,
            wavelengths: WavelengthSampler::new(strategy, &scene.lights, &power, &fluorescent),
            light_choice,
            integrator,
            light_spectra,
            only_strategy: None,
            tracer: Tracer::default(),
            quantity: Quantity::default(),
            rows: 0..u32::MAX,
            white: measure::white(),
            targets,
            volumetric,
            filter: FilterSampler::new(scene.filter),
            infinite: (0..scene.lights.len())
                .filter(|&i| scene.lights[i].is_infinite())
                .collect(),
            casters: if scene.integrator.aim_at_casters {
                casters(scene)
            } else {
                Vec::new()
            },
            scene,
            center,
            radius,
        }
    }

    /// The scene facts lights need.
    pub fn extent(&self) -> SceneExtent<'_> {
        SceneExtent {
            shapes: &self.scene.geometry.shapes,
            center: self.center,
            radius: self.radius,
            casters: &self.casters,
        }
    }

    /// What every camera sample starts with, from the sampler's first two
    /// sets: the film position (filter offset included), the lens point,
    /// the cluster — rotated so that the member a dispersive refraction
    /// keeps is uniform over it (stratum 0 alone would bias towards the
    /// blue) — and the spare fourth number of the second set.
    fn start_sample<const K: usize>(
        &self,
        sampler: &mut Sampler,
        pixel: [u32; 2],
        index: u32,
    ) -> ([f32; 2], [f32; 2], SampledWavelengths<K>, f32) {
        sampler.start(pixel, index);
        let sets = sampler.get_two_4d();
        self.start_sample_with(pixel, sets)
    }

    /// [`Self::start_sample`] from the sample's first two sets, drawn
    /// already (the wavefront tracer draws them for many samples at once).
    fn start_sample_with<const K: usize>(
        &self,
        pixel: [u32; 2],
        [[fx, fy, u_choice, u_wl], [lx, ly, u_first, spare]]: [[f32; 4]; 2],
    ) -> ([f32; 2], [f32; 2], SampledWavelengths<K>, f32) {
        let offset = self.filter.sample([fx, fy]);
        let film = [
            pixel[0] as f32 + 0.5 + offset[0],
            pixel[1] as f32 + 0.5 + offset[1],
        ];
        let mut wl: SampledWavelengths<K> = self.wavelengths.sample(u_choice, u_wl);
        if !wl.secondary_terminated() {
            wl.rotate_to_front(((u_first * K as f32) as usize).min(K - 1));
        }
        (film, [lx, ly], wl, spare)
    }

    /// Lights at infinity with their indices.
    fn infinite_lights(&self) -> impl Iterator<Item = (usize, &Light)> {
        self.infinite.iter().map(|&i| (i, &self.scene.lights[i]))
    }

    /// Adds samples `first..first + count` to every pixel of the film.
    fn pass<const K: usize>(
        &self,
        seed: u32,
        film: &mut Film,
        first: u32,
        count: u32,
    ) -> PassCounts {
        let width = film.width as usize;
        let stride = film.row_stride();
        let moment_stride = film.moment_stride();
        let moments_kept = film.kept_moments().is_some();
        let bands = film.bands;
        let rows: Vec<(PassCounts, Vec<Splat<K>>)> = film
            .pixels
            .par_chunks_mut(width)
            .zip(film.spectral.par_chunks_mut(stride))
            .zip(film.moments.par_chunks_mut(moment_stride))
            .enumerate()
            .map(|(y, ((row, spectral), moments))| {
                if !self.rows.contains(&(y as u32)) {
                    return (PassCounts::default(), Vec::new());
                }
                let mut sampler = Sampler::new(seed);
                let mut counts = PassCounts::default();
                let mut scratch = bdpt::Scratch::<K>::default();
                let mut splats = Vec::new();
                let mut batch = (self.integrator == IntegratorKind::Path
                    && self.tracer == Tracer::Wavefront
                    && !self.volumetric
                    && self.quantity == Quantity::Radiance)
                    .then(|| {
                        let work = wavefront::RowWork {
                            seed,
                            y: y as u32,
                            width: width as u32,
                            first,
                            count,
                        };
                        wavefront::trace_row::<K>(self, work, &mut counts.rays).into_iter()
                    });
                for (x, px) in row.iter_mut().enumerate() {
                    for i in first..first + count {
                        let pixel = [x as u32, y as u32];
                        let sample = match (&mut batch, self.integrator) {
                            (Some(done), _) => done.next().flatten(),
                            _ if self.scene.meter.is_some() => {
                                self.sample_meter::<K>(&mut sampler, pixel, i, &mut counts.rays)
                            }
                            _ if self.quantity == Quantity::Illuminance => self
                                .sample_illuminance::<K>(&mut sampler, pixel, i, &mut counts.rays),
                            (None, IntegratorKind::Path) => {
                                self.sample_pixel::<K>(&mut sampler, pixel, i, &mut counts.rays)
                            }
                            (None, IntegratorKind::Bdpt) => {
                                let mut c = bdpt::SampleCounts::default();
                                let s = self.sample_pixel_bdpt::<K>(
                                    &mut sampler,
                                    pixel,
                                    i,
                                    &mut scratch,
                                    &mut splats,
                                    &mut c,
                                );
                                counts.rays += c.rays;
                                counts.dropped_splats += c.dropped_splats;
                                s
                            }
                        };
                        match sample {
                            Some(s) => {
                                counts.collapsed += s.collapsed as u64;
                                px.add(s.xyzv);
                                if let Some(m) = moments.get_mut(x).filter(|_| moments_kept) {
                                    for (m, v) in m.iter_mut().zip(s.xyzv) {
                                        *m += f64::from(v) * f64::from(v);
                                    }
                                }
                                if let Some(b) = bands {
                                    let sums = &mut spectral[x * b.0..(x + 1) * b.0];
                                    b.add(sums, &s.radiance, &s.wl);
                                }
                            }
                            None => counts.dropped += 1,
                        }
                    }
                }
                (counts, splats)
            })
            .collect();
        // Light-tracing splats land on any pixel: added after the pass, row
        // by row in order, so the sums do not depend on the threads.
        let mut total = PassCounts::default();
        for (c, splats) in rows {
            total.dropped += c.dropped;
            total.dropped_splats += c.dropped_splats;
            total.rays += c.rays;
            total.collapsed += c.collapsed;
            for sp in &splats {
                film.splat(&self.filter, sp.raster, sp.xyzv, &sp.radiance, &sp.wl);
            }
        }
        total
    }
}

/// The longest time limit accepted, seconds (≈ 31.7 years): longer ones
/// would overflow the clock's arithmetic, and no render is meant to last
/// them.
pub const MAX_TIME_LIMIT_SECONDS: f64 = 1e9;

/// A render time limit of `seconds`, or why it cannot be one (not a
/// positive finite number, or over `MAX_TIME_LIMIT_SECONDS`).
pub fn time_limit(seconds: f64) -> Result<Duration, String> {
    if !(seconds.is_finite() && seconds > 0.0) {
        return Err(format!("{seconds}: must be a positive number of seconds"));
    }
    if seconds > MAX_TIME_LIMIT_SECONDS {
        return Err(format!(
            "{seconds:e}: must be at most {MAX_TIME_LIMIT_SECONDS:e} seconds (about 31 years)"
        ));
    }
    Duration::try_from_secs_f64(seconds).map_err(|e| format!("{seconds}: {e}"))
}

/// Renders `scene`. `progress(done, total)` is called after each pass
/// (samples per pixel); setting `cancel` stops after the current pass.
pub fn render(
    scene: &Scene,
    options: &RenderOptions,
    cancel: &AtomicBool,
    progress: &(dyn Fn(u32, u32) + Sync),
) -> Result<Rendered, RenderError> {
    render_resumable(scene, options, cancel, progress, None)
}

/// `render`, saving checkpoints and continuing from one: a render resumed
/// from a checkpoint ends bit-identical to the uninterrupted render of the
/// same scene, options and samples per pixel.
pub fn render_resumable(
    scene: &Scene,
    options: &RenderOptions,
    cancel: &AtomicBool,
    progress: &(dyn Fn(u32, u32) + Sync),
    checkpoints: Option<Checkpointing>,
) -> Result<Rendered, RenderError> {
    render_observed(scene, options, cancel, progress, checkpoints, None)
}

/// Looks at the film while a render runs (a live viewer, tev): `see(film,
/// facts)` is called at the first pass boundary after every `every` and once
/// at the end, on the rendering thread, so it should copy what it needs
/// and return.
pub struct Observer<'a> {
    pub every: Duration,
    pub see: &'a (dyn Fn(&Film, &RunFacts) + Sync),
}

/// `render_resumable`, showing the film to `observer` as it converges.
pub fn render_observed(
    scene: &Scene,
    options: &RenderOptions,
    cancel: &AtomicBool,
    progress: &(dyn Fn(u32, u32) + Sync),
    checkpoints: Option<Checkpointing>,
    observer: Option<Observer>,
) -> Result<Rendered, RenderError> {
    let hooks = (progress, checkpoints, observer);
    match options.cluster {
        1 => render_k::<1>(scene, options, cancel, hooks),
        2 => render_k::<2>(scene, options, cancel, hooks),
        4 => render_k::<4>(scene, options, cancel, hooks),
        8 => render_k::<8>(scene, options, cancel, hooks),
        16 => render_k::<16>(scene, options, cancel, hooks),
        k => Err(RenderError::Cluster(k)),
    }
}

/// What a render reports to as it goes: progress, checkpoints, an observer.
type Hooks<'a, 'b> = (
    &'a (dyn Fn(u32, u32) + Sync),
    Option<Checkpointing<'b>>,
    Option<Observer<'b>>,
);

fn render_k<const K: usize>(
    scene: &Scene,
    options: &RenderOptions,
    cancel: &AtomicBool,
    (progress, mut checkpoints, observer): Hooks,
) -> Result<Rendered, RenderError> {
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
    // An irradiancemeter is measured by the path tracer's receiver, in lx.
    let (integrator, quantity) = match scene.meter {
        Some(_) => (IntegratorKind::Path, Quantity::Illuminance),
        None => (
            options.integrator.unwrap_or(scene.integrator.kind),
            options.quantity,
        ),
    };
    if integrator == IntegratorKind::Bdpt && scene.camera.projection != Projection::Perspective {
        return Err(RenderError::BdptProjection);
    }
    let mut renderer = Renderer::with_integrator(scene, options.strategy, integrator);
    if let Some([s, t]) = options.only_strategy {
        if integrator != IntegratorKind::Bdpt || t == 0 || s + t < 2 {
            return Err(RenderError::Strategy(s, t));
        }
        renderer.only_strategy = Some([s, t]);
    }
    renderer.tracer = options.tracer;
    renderer.quantity = quantity;
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
                counts: [0; 4],
                film,
            }
        }
    };
    let resumed_at = state.done;
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
        let mut count = pass_size(done).min(total - done);
        if let Some(limit) = options.time_limit {
            // Only as many samples as the time left should allow, judged by
            // the rate so far, so a time limit is met rather than overrun
            // by a whole pass (and is spent, not left half unused).
            let elapsed = start.elapsed();
            if elapsed >= limit {
                break;
            }
            if done > resumed_at {
                let per_spp = elapsed.as_secs_f64() / (done - resumed_at) as f64;
                let fits = ((limit - elapsed).as_secs_f64() / per_spp) as u32;
                if fits == 0 {
                    break;
                }
                count = count.min(fits);
            }
        }
        let c = renderer.pass::<K>(options.seed, &mut state.film, done, count);
        let n = &mut state.counts;
        n[0] += c.dropped;
        n[1] += c.dropped_splats;
        n[2] += c.rays;
        n[3] += c.collapsed;
        state.done += count;
        progress(state.done, total);
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
                    rays: state.counts[2],
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
        counts: [dropped, dropped_splats, rays, collapsed],
        film,
        ..
    } = state;
    let rendered = Rendered {
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

#[cfg(test)]
mod time_limit_tests {
    use super::*;

    #[test]
    fn time_limits_out_of_range_are_errors_not_panics() {
        assert_eq!(time_limit(2.5), Ok(Duration::from_millis(2500)));
        assert!(time_limit(MAX_TIME_LIMIT_SECONDS).is_ok());
        for t in [1e20, 1e30, f64::INFINITY] {
            let e = time_limit(t).unwrap_err();
            assert!(e.contains("at most") || e.contains("positive"), "{t}: {e}");
        }
        for t in [0.0, -1.0, f64::NAN, f64::NEG_INFINITY] {
            assert!(time_limit(t).unwrap_err().contains("positive"), "{t}");
        }
    }
}

//! The per-scene state every sample shares (`Renderer`), and a pass of
//! samples over the film.

use scotopia_color::SampledWavelengths;

use crate::accel::Aabb;
use crate::film::{FilterSampler, SampleCounts};
use crate::geometry::Shape;
use crate::light::{Caster, Light, SceneExtent};
use crate::math::Vec3;
use crate::sampling::sobol::Sampler;
use crate::scene::{IntegratorKind, Scene};
use crate::wavelength::{WavelengthSampler, WavelengthStrategy};

use super::guided::GuideState;
use super::manifold::Lenses;
use super::select::{Integrator, Receivers};
use super::{
    bdpt, CameraSample, Guiding, LightChoice, Reflectors, RenderError, RenderOptions, Splat, Tracer,
};
use crate::guiding::Guide;

/// The bounding spheres of the shapes (outside shape groups) whose BSDF
/// casts caustics: where lights at infinity aim part of their light
/// subpaths (`light::emit_disk`).
pub(super) fn casters(scene: &Scene) -> Vec<Caster> {
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

/// The scene's lights as every integrator sees them: the scene's bounds,
/// each light's radiant power (W) and the light choice made from them.
struct SceneLights {
    bounds: SceneBounds,
    power: Vec<f32>,
    choice: LightChoice,
}

impl SceneLights {
    fn of(scene: &Scene) -> Self {
        let bounds = SceneBounds::of(scene);
        let extent = extent(scene, &bounds);
        let power: Vec<f32> = scene
            .lights
            .iter()
            .map(|l| l.power(&extent).watts as f32)
            .collect();
        let choice = LightChoice::new(&scene.lights, &power, &extent);
        Self {
            bounds,
            power,
            choice,
        }
    }
}

/// The scene facts lights need, before the casters are known.
fn extent<'s>(scene: &'s Scene, bounds: &SceneBounds) -> SceneExtent<'s> {
    SceneExtent {
        shapes: &scene.geometry.shapes,
        center: bounds.center,
        radius: bounds.radius,
        casters: &[],
    }
}

/// The scene's bounding sphere (a unit sphere at the origin for an empty
/// scene): where lights at infinity are placed and how far away they are.
#[derive(Debug, Clone, Copy)]
pub(super) struct SceneBounds {
    pub center: Vec3,
    pub radius: f32,
}

impl SceneBounds {
    fn of(scene: &Scene) -> Self {
        let bounds = scene.geometry.bounds();
        if bounds.is_empty() {
            Self {
                center: Vec3::ZERO,
                radius: 1.0,
            }
        } else {
            Self {
                center: bounds.centroid(),
                radius: (0.5 * bounds.extent().length()).max(1e-3),
            }
        }
    }
}

/// Per-scene state shared by all samples, and the integrator that runs
/// with its own.
pub struct Renderer<'a> {
    pub scene: &'a Scene,
    /// Which light next-event estimation samples and SWC draws the
    /// cluster from (by power; at a point, by power over squared
    /// distance).
    pub lights: LightChoice,
    /// Glossy surfaces lamps light brightly, which the path tracer's
    /// diffuse bounces aim at in part (`reflectors`).
    pub reflectors: Reflectors,
    /// The glass balls the path tracer finds light through (`manifold`).
    pub(super) lenses: Lenses,
    pub wavelengths: WavelengthSampler,
    pub filter: FilterSampler,
    pub(super) bounds: SceneBounds,
    /// The shapes light subpaths from infinity are aimed at.
    pub(super) casters: Vec<Caster>,
    pub(super) infinite: Vec<usize>,
    /// The integrator that runs, with its own state.
    pub integrator: Integrator,
    /// The integrator as an image's metadata reports it (the options' or
    /// the scene's; the path tracer for an irradiance meter).
    pub(super) kind: IntegratorKind,
    /// The film rows a pass renders (a shard's; all by default).
    pub(super) rows: std::ops::Range<u32>,
    /// Of those, a pass renders every `row_step`-th (1 but for the
    /// guide's probe, `learn.rs`).
    pub(super) row_step: u32,
    /// The light field learned so far, with `--guiding on`.
    pub(super) guiding: Option<GuideState>,
    /// The path tracer's longest path in segments (−1: unlimited): the
    /// scene's, or `measure --direct`'s.
    pub(super) max_depth: i32,
}

impl<'a> Renderer<'a> {
    /// The integrator `options` ask of `scene`, built with its state, or
    /// why it cannot run.
    pub fn new(scene: &'a Scene, options: &RenderOptions) -> Result<Self, RenderError> {
        let lit = SceneLights::of(scene);
        let (kind, integrator) = Integrator::new(scene, options, &lit.choice, lit.bounds.radius)?;
        let mut renderer = Self::with(scene, options.strategy, kind, integrator, lit);
        if options.guiding == Guiding::On {
            let refused = match &renderer.integrator {
                Integrator::Path(Tracer::Scalar) | Integrator::VolPath(_) | Integrator::Bdpt(_) => {
                    None
                }
                Integrator::Path(Tracer::Wavefront) => Some("the wavefront tracer"),
                Integrator::Illuminance(_) | Integrator::Meter(_) => Some("illuminance"),
            };
            if let Some(what) = refused {
                return Err(RenderError::Guiding(what));
            }
            let b = scene.geometry.bounds();
            let (lo, hi) = if b.is_empty() {
                (Vec3::splat(-1.0), Vec3::splat(1.0))
            } else {
                // A margin, so points on the box's faces fall inside.
                let m = b.extent() * 1e-3 + Vec3::splat(1e-4);
                (b.min - m, b.max + m)
            };
            renderer.guiding = Some(GuideState {
                guide: Guide::new(lo, hi),
                learning: false,
                probed: false,
            });
        }
        Ok(renderer)
    }

    /// The illuminance at virtual receivers (`measure`): the path tracer's
    /// transport, with `strategy`'s wavelengths.
    pub(super) fn receivers(scene: &'a Scene, strategy: WavelengthStrategy) -> Self {
        let lit = SceneLights::of(scene);
        let receivers = Receivers::of(scene, &lit.choice, lit.bounds.radius);
        let integrator = Integrator::Illuminance(receivers);
        Self::with(scene, strategy, IntegratorKind::Path, integrator, lit)
    }

    /// The state every integrator shares, for `kind`'s wavelengths.
    fn with(
        scene: &'a Scene,
        strategy: WavelengthStrategy,
        kind: IntegratorKind,
        integrator: Integrator,
        lit: SceneLights,
    ) -> Self {
        let SceneLights {
            bounds,
            power,
            choice,
        } = lit;
        // The path tracer draws some wavelengths from fluorescent
        // emission; the bidirectional tracer reaches them by re-emission
        // on its light subpaths and draws from the lights alone.
        let fluorescent: Vec<_> = match kind {
            IntegratorKind::Path => scene
                .materials
                .iter()
                .filter_map(|m| m.fluorescent())
                .collect(),
            IntegratorKind::Bdpt => Vec::new(),
        };
        let reflectors = Reflectors::new(
            &scene.materials,
            &scene.shape_material,
            &scene.shape_light,
            &scene.lights,
            &power,
            &extent(scene, &bounds),
        );
        Self {
            lights: choice,
            reflectors,
            lenses: Lenses::of(scene),
            wavelengths: WavelengthSampler::new(strategy, &scene.lights, &power, &fluorescent),
            integrator,
            kind,
            rows: 0..u32::MAX,
            row_step: 1,
            guiding: None,
            max_depth: scene.integrator.max_depth,
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
            bounds,
        }
    }

    /// The scene facts lights need.
    pub fn extent(&self) -> SceneExtent<'_> {
        SceneExtent {
            shapes: &self.scene.geometry.shapes,
            center: self.bounds.center,
            radius: self.bounds.radius,
            casters: &self.casters,
        }
    }

    /// What every camera sample starts with ([`SampleStart`]), from the
    /// sampler's first two sets.
    pub(super) fn start_sample<const K: usize>(
        &self,
        sampler: &mut Sampler,
        pixel: [u32; 2],
        index: u32,
    ) -> SampleStart<K> {
        sampler.start(pixel, index);
        let sets = sampler.get_two_4d();
        self.start_sample_with(pixel, sets)
    }

    /// [`Self::start_sample`] from the sample's first two sets, drawn
    /// already (the wavefront tracer draws them for many samples at once).
    pub(super) fn start_sample_with<const K: usize>(
        &self,
        pixel: [u32; 2],
        [[fx, fy, u_choice, u_wl], [lx, ly, u_first, spare]]: [[f32; 4]; 2],
    ) -> SampleStart<K> {
        let offset = self.filter.sample([fx, fy]);
        let film = [
            pixel[0] as f32 + 0.5 + offset[0],
            pixel[1] as f32 + 0.5 + offset[1],
        ];
        let mut wl: SampledWavelengths<K> = self.wavelengths.sample(u_choice, u_wl);
        if !wl.secondary_terminated() {
            wl.rotate_to_front(((u_first * K as f32) as usize).min(K - 1));
        }
        SampleStart {
            film,
            lens: [lx, ly],
            wl,
            spare,
        }
    }

    /// Lights at infinity with their indices.
    pub(super) fn infinite_lights(&self) -> impl Iterator<Item = (usize, &Light)> {
        self.infinite.iter().map(|&i| (i, &self.scene.lights[i]))
    }

    /// One camera sample of `pixel` by the integrator that runs (the
    /// wavefront tracer's come a row at a time, `wavefront::trace_row`).
    #[inline]
    pub(super) fn estimate<const K: usize>(
        &self,
        sampler: &mut Sampler,
        pixel: [u32; 2],
        index: u32,
        to: Scratchpad<'_, K>,
    ) -> Option<CameraSample<K>> {
        let rays = &mut to.counts.rays;
        let records = to.records;
        match &self.integrator {
            Integrator::Meter(r) => self.sample_meter::<K>(r, sampler, pixel, index, rays),
            Integrator::Illuminance(r) => {
                self.sample_illuminance::<K>(r, sampler, pixel, index, rays)
            }
            Integrator::Path(_) => {
                self.sample_pixel::<K>(None, sampler, pixel, index, rays, records)
            }
            Integrator::VolPath(m) => {
                self.sample_pixel::<K>(Some(m), sampler, pixel, index, rays, records)
            }
            Integrator::Bdpt(b) => {
                let to = Scratchpad { records, ..to };
                self.sample_pixel_bdpt::<K>(b, sampler, pixel, index, to)
            }
        }
    }
}

/// What a camera sample starts with.
pub(super) struct SampleStart<const K: usize> {
    /// The film position, the filter's offset included.
    pub film: [f32; 2],
    /// The lens sample.
    pub lens: [f32; 2],
    /// The cluster, rotated so that the member a dispersive refraction
    /// keeps is uniform over it (stratum 0 alone would bias towards the
    /// blue).
    pub wl: SampledWavelengths<K>,
    /// The second set's spare fourth number.
    pub spare: f32,
}

/// Where a row's samples keep their work: the bidirectional tracer's
/// subpaths and light-tracing splats, and the pass's counts.
pub(super) struct Scratchpad<'a, const K: usize> {
    pub scratch: &'a mut bdpt::Scratch<K>,
    pub splats: &'a mut Vec<Splat<K>>,
    pub counts: &'a mut SampleCounts,
    /// The guide's records, while it learns.
    pub records: &'a mut Vec<(u32, f32)>,
}

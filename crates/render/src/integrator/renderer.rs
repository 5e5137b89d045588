//! The per-scene state every sample shares (`Renderer`), and a pass of
//! samples over the film.

use rayon::prelude::*;

use scotopia_color::SampledWavelengths;

use crate::accel::Aabb;
use crate::film::{Film, FilterSampler, SampleCounts};
use crate::geometry::Shape;
use crate::light::{Caster, Light, SceneExtent};
use crate::math::Vec3;
use crate::sampling::distribution::Distribution1D;
use crate::sampling::sobol::Sampler;
use crate::scene::{IntegratorKind, Scene};
use crate::wavelength::{WavelengthSampler, WavelengthStrategy};

use super::select::{traces_media, Bidirectional, Choice, Integrator, Run};
use super::{
    bdpt, equiangular, measure, wavefront, CameraSample, LightChoice, Reflectors, RenderError,
    RenderOptions, Splat, Tracer,
};

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

/// Where a light at a finite place is (its bounding box's centre for an
/// area light), for equi-angular sampling; `None` at infinity.
pub(super) fn light_centre(light: &Light, shapes: &[Shape]) -> Option<Vec3> {
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
    pub(super) center: Vec3,
    pub(super) radius: f32,
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
    /// The white Lambertian surface of virtual receivers (`measure.rs`).
    pub(super) white: crate::bsdf::Bsdf,
    /// The lights equi-angular sampling aims at in media (empty when
    /// media are not traced).
    pub(super) targets: equiangular::Targets,
    /// Whether paths are traced through media (`volume.rs`): the
    /// integrator traces them and the scene has media or surfaces that
    /// pass light (null lobes, which such an integrator treats as media
    /// boundaries).
    pub(super) volumetric: bool,
}

impl<'a> Renderer<'a> {
    /// The integrator `options` ask of `scene`, built with its state, or
    /// why it cannot run.
    pub fn new(scene: &'a Scene, options: &RenderOptions) -> Result<Self, RenderError> {
        let choice = Choice::new(scene, options)?;
        let mut r = Self::shared(scene, options.strategy, choice.kind);
        r.integrator = match choice.run {
            Run::Path(tracer) => Integrator::Path(tracer),
            Run::VolPath => Integrator::VolPath,
            Run::Illuminance => Integrator::Illuminance,
            Run::Meter => Integrator::Meter,
            Run::Bdpt(only) => {
                let p = (0..scene.lights.len())
                    .map(|i| r.light_choice.probability(i))
                    .collect();
                let spectra = bdpt::LightSpectra::new(&scene.lights, p);
                Integrator::Bdpt(Box::new(Bidirectional { spectra, only }))
            }
        };
        Ok(r)
    }

    /// The state every integrator shares, for `kind`'s wavelengths; the
    /// virtual receivers of `measure` use it as it is.
    pub(super) fn shared(
        scene: &'a Scene,
        strategy: WavelengthStrategy,
        kind: IntegratorKind,
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
        let fluorescent: Vec<_> = match kind {
            IntegratorKind::Path => scene
                .materials
                .iter()
                .filter_map(|m| m.fluorescent())
                .collect(),
            IntegratorKind::Bdpt => Vec::new(),
        };
        let light_choice = Distribution1D::new(power.clone());
        let nee_choice = LightChoice::new(&scene.lights, &power, &extent);
        let reflectors = Reflectors::new(
            &scene.materials,
            &scene.shape_material,
            &scene.shape_light,
            &scene.lights,
            &power,
            &extent,
        );
        let volumetric = traces_media(scene);
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
            integrator: Integrator::Path(Tracer::Scalar),
            kind,
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
    pub(super) fn start_sample<const K: usize>(
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
    pub(super) fn start_sample_with<const K: usize>(
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
    pub(super) fn infinite_lights(&self) -> impl Iterator<Item = (usize, &Light)> {
        self.infinite.iter().map(|&i| (i, &self.scene.lights[i]))
    }

    /// Adds samples `first..first + count` to every pixel of the film.
    pub(super) fn pass<const K: usize>(
        &self,
        seed: u32,
        film: &mut Film,
        first: u32,
        count: u32,
    ) -> SampleCounts {
        let width = film.width as usize;
        let stride = film.row_stride();
        let moment_stride = film.moment_stride();
        let moments_kept = film.kept_moments().is_some();
        let bands = film.bands;
        let rows: Vec<(SampleCounts, Vec<Splat<K>>)> = film
            .pixels
            .par_chunks_mut(width)
            .zip(film.spectral.par_chunks_mut(stride))
            .zip(film.moments.par_chunks_mut(moment_stride))
            .enumerate()
            .map(|(y, ((row, spectral), moments))| {
                if !self.rows.contains(&(y as u32)) {
                    return (SampleCounts::default(), Vec::new());
                }
                let mut sampler = Sampler::new(seed);
                let mut counts = SampleCounts::default();
                let mut scratch = bdpt::Scratch::<K>::default();
                let mut splats = Vec::new();
                let mut batch = matches!(self.integrator, Integrator::Path(Tracer::Wavefront))
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
                        let sample = match &mut batch {
                            Some(done) => done.next().flatten(),
                            None => {
                                let to = Scratchpad {
                                    scratch: &mut scratch,
                                    splats: &mut splats,
                                    counts: &mut counts,
                                };
                                self.estimate::<K>(&mut sampler, pixel, i, to)
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
        let mut total = SampleCounts::default();
        for (c, splats) in rows {
            total += c;
            for sp in &splats {
                film.splat(&self.filter, sp.raster, sp.xyzv, &sp.radiance, &sp.wl);
            }
        }
        total
    }

    /// One camera sample of `pixel` by the integrator that runs (the
    /// wavefront tracer's come a row at a time, `wavefront::trace_row`).
    #[inline]
    fn estimate<const K: usize>(
        &self,
        sampler: &mut Sampler,
        pixel: [u32; 2],
        index: u32,
        to: Scratchpad<'_, K>,
    ) -> Option<CameraSample<K>> {
        match &self.integrator {
            Integrator::Meter => self.sample_meter::<K>(sampler, pixel, index, &mut to.counts.rays),
            Integrator::Illuminance => {
                self.sample_illuminance::<K>(sampler, pixel, index, &mut to.counts.rays)
            }
            Integrator::Path(_) | Integrator::VolPath => {
                self.sample_pixel::<K>(sampler, pixel, index, &mut to.counts.rays)
            }
            Integrator::Bdpt(b) => self.sample_pixel_bdpt::<K>(b, sampler, pixel, index, to),
        }
    }
}

/// Where a row's samples keep their work: the bidirectional tracer's
/// subpaths and light-tracing splats, and the pass's counts.
pub(super) struct Scratchpad<'a, const K: usize> {
    pub scratch: &'a mut bdpt::Scratch<K>,
    pub splats: &'a mut Vec<Splat<K>>,
    pub counts: &'a mut SampleCounts,
}

//! Unidirectional path tracing with next-event estimation and multiple
//! importance sampling (Veach 1997, power heuristic β = 2), Russian
//! roulette, and cluster collapse at dispersive refraction (pbrt-v4's
//! `TerminateSecondary`). Mitsuba's depth convention: a path of depth d has
//! d segments; `max_depth` 1 sees emitters only, 2 adds direct light.

use scotopia_color::photometry::estimate_xyzv;
use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::bdpt::Splat;
use super::direct::{power_heuristic, spawn};
use super::guided::{Pending, Trail};
use super::manifold::{area_density, shares_at, Caustic, Passage, Shares, SHORTEST};
use super::renderer::SampleStart;
use super::select::Media;
use super::Renderer;
use crate::bsdf::{Bsdf, ShadingPoint, Transport};
use crate::geometry::{Hit, Surface};
use crate::light::Light;
use crate::math::{Frame, Ray, Vec3};
use crate::sampling::sobol::Sampler;
use crate::sampling::splitmix::SplitMix;

/// What one camera sample found.
pub struct CameraSample<const K: usize> {
    pub xyzv: [f32; 4],
    pub radiance: SampledSpectrum<K>,
    pub wl: SampledWavelengths<K>,
    /// The path started with several wavelengths and a dispersive
    /// refraction collapsed them to one.
    pub collapsed: bool,
    /// Its light subpath's light as the camera sees it, on another pixel
    /// (`manifold::seen`).
    pub seen: Option<Splat<K>>,
}

/// One path in flight: everything the next bounce needs. The scalar
/// tracer keeps one on its stack; the wavefront tracer keeps a batch.
#[derive(Clone, Copy)]
pub struct PathState<const K: usize> {
    /// The ray to trace next.
    pub ray: Ray,
    /// Radiance gathered so far, and the throughput.
    pub l: SampledSpectrum<K>,
    pub beta: SampledSpectrum<K>,
    /// The wavelengths the estimate is of (a dispersive refraction may
    /// collapse them to one).
    pub wl: SampledWavelengths<K>,
    /// The wavelengths the path carries now. Fluorescence moves members
    /// away from `wl` (the light absorbed at one wavelength reaches the
    /// eye at another).
    pub now: SampledWavelengths<K>,
    /// The previous bounce: whether it was a delta lobe, its direction
    /// density, and where it left from (for MIS on emitters hit).
    pub delta: bool,
    pub bsdf_pdf: f32,
    pub prev: Vec3,
    /// The previous vertex's geometric normal (`None` in a medium or at
    /// the camera), for the light choice's density there.
    pub prev_n: Option<Vec3>,
    /// Segments so far, counting the one being traced.
    pub depth: i32,
    /// Whether the cluster had several wavelengths at the start.
    pub whole: bool,
    /// The medium the ray travels in (`Scene::media`), when media are
    /// traced (`volume.rs`).
    pub medium: Option<u32>,
    /// Each wavelength's density of the path's medium events relative to
    /// the others, scaled to a mean of 1 over the live wavelengths: the
    /// cluster's one-sample MIS along the whole path (`volume.rs`). All 1
    /// in clear air.
    pub ratio: SampledSpectrum<K>,
    /// Numbers for tracking walks through heterogeneous media.
    pub rng: SplitMix,
    /// The vertices waiting for their record while the guide learns
    /// (`guided.rs`).
    pub trail: Trail,
    /// The path's way through a glass ball since its last diffuse vertex
    /// (`manifold`).
    pub passage: Passage,
    /// The light subpath through a glass ball its vertices join
    /// (`manifold::connect`).
    pub caustic: Caustic,
    /// Its light subpath's light as the camera sees it (`manifold::seen`).
    pub seen: Option<Splat<K>>,
}

/// Where a path scatters at a surface: the point, its geometric normal,
/// and the shading frame and point of its BSDF.
#[derive(Clone, Copy)]
pub(super) struct ScatterPoint {
    pub p: Vec3,
    pub ng: Vec3,
    pub frame: Frame,
    pub at: ShadingPoint,
}

impl ScatterPoint {
    /// Where a path scatters on `surface`, hit at `hit`.
    pub(super) fn of(surface: &Surface, hit: &Hit) -> Self {
        let (frame, at) = ShadingPoint::at(
            surface.tex(hit),
            surface.n_shading,
            surface.n_geometric,
            surface.dpdu,
            surface.dpdv,
        );
        Self {
            p: surface.p,
            ng: surface.n_geometric,
            frame,
            at,
        }
    }
}

/// What a bounce leaves to do: a shadow ray whose contribution counts if
/// it is not occluded, and whether the path goes on (along `ray`).
pub struct Bounce<const K: usize> {
    pub shadow: Option<(Ray, SampledSpectrum<K>)>,
    /// The medium the shadow ray starts in.
    pub shadow_medium: Option<u32>,
    pub goes_on: bool,
    /// The bounce's mark, while the guide learns (`guided.rs`).
    pub record: Option<Pending>,
    /// Rays the bounce traced itself (`manifold`).
    pub traced: u32,
}

impl<const K: usize> Bounce<K> {
    /// The path ends here, without a shadow ray.
    pub(super) const STOP: Self = Self {
        shadow: None,
        shadow_medium: None,
        goes_on: false,
        record: None,
        traced: 0,
    };
}

impl Renderer<'_> {
    /// One camera sample of `pixel`, traced in clear air or through
    /// `media`: its X, Y, Z, V′ estimate and the cluster's radiance, or
    /// `None` when the estimate is not finite (counted by the caller).
    /// Adds the rays it traced to `rays`, and while the guide learns, the
    /// path's records to `records`.
    pub(super) fn sample_pixel<const K: usize>(
        &self,
        media: Option<&Media>,
        sampler: &mut Sampler,
        pixel: [u32; 2],
        index: u32,
        rays: &mut u64,
        records: &mut Vec<(u32, f32)>,
    ) -> Option<CameraSample<K>> {
        let mut path = self.start_path::<K>(sampler, pixel, index);
        if media.is_none() {
            *rays += self.draw_caustic(&mut path) as u64;
        }
        match media {
            None => self.trace(sampler, &mut path, rays),
            Some(media) => self.trace_media(media, sampler, &mut path, rays),
        }
        let sample = Self::finish(&path);
        if sample.is_some() {
            path.trail.records(path.l.0.iter().sum(), records);
        }
        sample
    }

    /// Follows `path` from its ray to its end, in clear air.
    pub(super) fn trace<const K: usize>(
        &self,
        sampler: &mut Sampler,
        path: &mut PathState<K>,
        rays: &mut u64,
    ) {
        loop {
            *rays += 1;
            let hit = self.scene.geometry.intersect(&path.ray);
            if !self.arrive::<K, false>(sampler, path, hit, rays) {
                return;
            }
        }
    }

    /// The path's ray reached `hit`, or escaped the scene: the light found
    /// there and the bounce (`MEDIA`: through media); whether the path
    /// goes on.
    #[inline]
    pub(super) fn arrive<const K: usize, const MEDIA: bool>(
        &self,
        sampler: &mut Sampler,
        path: &mut PathState<K>,
        hit: Option<Hit>,
        rays: &mut u64,
    ) -> bool {
        let Some(hit) = hit else {
            self.escape(path);
            return false;
        };
        let b = self.bounce::<K, MEDIA>(path, sampler.get_two_4d(), &hit);
        self.settle::<K, MEDIA>(path, b, rays)
    }

    /// Adds a bounce's light if its shadow ray is clear (through media:
    /// times the transmittance along it); whether the path goes on.
    pub(super) fn settle<const K: usize, const MEDIA: bool>(
        &self,
        path: &mut PathState<K>,
        b: Bounce<K>,
        rays: &mut u64,
    ) -> bool {
        *rays += b.traced as u64;
        if let Some((shadow, contribution)) = b.shadow {
            if MEDIA {
                let (now, rng) = (&path.now, &mut path.rng);
                let tr = self.through_media(shadow, b.shadow_medium, now, rng, rays);
                path.l += contribution * tr;
            } else if self.visible(&shadow, rays) {
                path.l += contribution;
            }
        }
        match b.record {
            Some(r) => path.trail.push(r, path.l.0.iter().sum()),
            None => path.trail.unmarked(),
        }
        b.goes_on
    }

    /// A camera sample's path before its first segment.
    pub(super) fn start_path<const K: usize>(
        &self,
        sampler: &mut Sampler,
        pixel: [u32; 2],
        index: u32,
    ) -> PathState<K> {
        sampler.start(pixel, index);
        let sets = sampler.get_two_4d();
        let mut path = self.start_path_with(pixel, sets);
        path.rng = sampler.stream();
        path
    }

    /// [`Self::start_path`] from the sample's first two sets.
    pub(super) fn start_path_with<const K: usize>(
        &self,
        pixel: [u32; 2],
        sets: [[f32; 4]; 2],
    ) -> PathState<K> {
        let SampleStart { film, lens, wl, .. } = self.start_sample_with::<K>(pixel, sets);
        let ray = self.scene.camera.generate_ray(film, lens);
        let mut path = PathState::new(ray, wl, 1);
        path.medium = self.scene.camera_medium;
        if !self.scene.camera.sees(film) {
            // Outside a fisheye's circle: an empty ray that carries nothing.
            path.beta = SampledSpectrum::splat(0.0);
        }
        path
    }

    /// The estimate of a finished path, or `None` when it is not finite.
    pub(super) fn finish<const K: usize>(path: &PathState<K>) -> Option<CameraSample<K>> {
        let xyzv = estimate_xyzv(&path.l, &path.wl);
        let finite = xyzv.iter().all(|v| v.is_finite()) && path.l.0.iter().all(|v| v.is_finite());
        finite.then_some(CameraSample {
            xyzv,
            radiance: path.l,
            wl: path.wl,
            collapsed: path.whole && path.wl.secondary_terminated(),
            seen: path.seen,
        })
    }

    /// The path escaped the scene along its ray: lights at infinity.
    pub(super) fn escape<const K: usize>(&self, path: &mut PathState<K>) {
        let d = path.ray.d;
        for (i, light) in self.infinite_lights() {
            let le = light.radiance_at_infinity(&path.now, d);
            if le.is_zero() {
                continue;
            }
            let w = if path.delta {
                1.0
            } else {
                let p_light = self.lights.probability(path.prev, path.prev_n, i)
                    * light.pdf_li_at_infinity(d);
                power_heuristic(path.bsdf_pdf, p_light)
            };
            let light = path.beta * le * w;
            path.l += light;
            path.trail.direct(&light);
        }
    }

    /// The path's ray hit `hit`: emission there, next-event estimation
    /// (a shadow ray left to the caller), and the next direction by
    /// sampling the BSDF, with Russian roulette. `u`: the path's next two
    /// 4-dimensional sets of its sampler. `MEDIA`: whether the path is
    /// traced through media (`volume.rs`).
    pub(super) fn bounce<const K: usize, const MEDIA: bool>(
        &self,
        path: &mut PathState<K>,
        u: [[f32; 4]; 2],
        hit: &Hit,
    ) -> Bounce<K> {
        let scene = self.scene;
        let ray = path.ray;
        let surface = scene.geometry.surface(hit, &ray);
        let wo_world = -ray.d;
        // Emission of an area light we landed on.
        if let Some(li) = scene.shape_light[hit.shape as usize] {
            if let Light::Area(area) = &scene.lights[li as usize] {
                let le = area.radiance(&path.now, surface.uv, surface.n_geometric, wo_world);
                if !le.is_zero() {
                    let w = if path.delta {
                        let at_y = (surface.p, surface.n_geometric, ray.d);
                        self.passage_weight(&path.passage, li as usize, at_y)
                    } else {
                        let p_light = self.lights.probability(path.prev, path.prev_n, li as usize)
                            * area.pdf_li(path.prev, surface.p, surface.n_geometric);
                        power_heuristic(path.bsdf_pdf, p_light)
                    };
                    let light = path.beta * le * w;
                    path.l += light;
                    path.trail.direct(&light);
                }
            }
        }
        let bsdf = &scene.materials[scene.shape_material[hit.shape as usize] as usize];
        // A volume path tracer passes a null surface (a medium's boundary)
        // without a vertex, so a path at its last segment goes on through
        // it to what lies beyond: an emitter there is a path of the same
        // length, which next-event estimation's MIS weight counts on
        // (Mitsuba's volpath likewise).
        let passes = MEDIA && matches!(bsdf, Bsdf::Null(_));
        if !self.within(path.depth + 1) && !passes {
            return Bounce::STOP;
        }
        let point = ScatterPoint::of(&surface, hit);
        let ng = point.ng;
        let mut b = self.scatter::<K, MEDIA>(path, u, &point, bsdf);
        if path.delta && b.goes_on {
            let d = path.ray.d;
            self.follow_passage(&mut path.passage, hit, surface.p, wo_world, d);
        }
        // Rays leaving a medium boundary enter the medium on their side.
        if MEDIA {
            if let Some(sides) = self.shape_media(hit.shape) {
                if let Some((shadow, _)) = &b.shadow {
                    b.shadow_medium = sides.target(shadow.d, ng);
                }
                path.medium = sides.target(path.ray.d, ng);
            }
        }
        b
    }

    /// How many more segments a path of `depth` segments may have.
    #[inline]
    pub(super) fn room(&self, depth: i32) -> i32 {
        let max_depth = self.max_depth;
        if max_depth < 0 {
            i32::MAX
        } else {
            max_depth - depth
        }
    }

    /// Whether a path of `depth` segments is within `max_depth`.
    #[inline]
    pub(super) fn within(&self, depth: i32) -> bool {
        let max_depth = self.max_depth;
        max_depth < 0 || depth <= max_depth
    }

    /// What the path does at a point `p` (geometric normal `ng`) of `bsdf`,
    /// reached along `path.ray`: fluorescence, next-event estimation and
    /// the next direction. The camera's hits come here through
    /// [`Self::bounce`], the virtual receivers of illuminance measurement
    /// directly (`measure.rs`). `MEDIA`: whether the path is traced
    /// through media, where a dispersive collapse rescales the cluster's
    /// densities and null lobes are passed, not scattered at.
    pub(super) fn scatter<const K: usize, const MEDIA: bool>(
        &self,
        path: &mut PathState<K>,
        u: [[f32; 4]; 2],
        point: &ScatterPoint,
        bsdf: &Bsdf,
    ) -> Bounce<K> {
        let ScatterPoint { p, ng, frame, at } = *point;
        let scene = self.scene;
        let stop = Bounce::STOP;
        let wo_world = -path.ray.d;
        let wi = frame.to_local(wo_world);
        let uv = at.tex();
        let [[u_light, u_select, u_l0, u_l1], [u_lobe, u_rr, u_b0, u_b1]] = u;
        // Whether the last vertex could have joined a light subpath that
        // lands here, and the density its bounce gives this point per area
        // (for the MIS weights of the paths through glass balls, which are
        // weighed only where the estimator can run).
        let joins = !MEDIA && path.caustic.is_on() && bsdf.fluorescent().is_none();
        let joins = joins && !bsdf.is_delta() && self.within(path.depth + SHORTEST);
        // The camera's own ray reaches a first hit that light subpaths
        // are seen at (`manifold::seen`).
        let joined = match (joins && path.delta, path.depth == 1) {
            (true, true) => self.camera_density(&path.ray, p, ng),
            (true, false) => self.joined_through(&path.passage, p, ng),
            (false, _) => area_density(
                joins && path.prev_n.is_some(),
                path.bsdf_pdf,
                path.prev,
                p,
                ng,
            ),
        };
        // Fluorescence: members move to their excitation wavelengths
        // before light is sampled there.
        if let Some(f) = bsdf.reradiate(&mut path.now, uv, u_lobe) {
            path.beta *= f;
            if path.beta.is_zero() {
                return stop;
            }
        }
        let now = path.now;
        let facing = if ng.dot(wo_world) < 0.0 { -ng } else { ng };
        let spot = self.spot(p, Some(facing));
        let guide = self.surface_guide(spot, bsdf);

        // Next-event estimation: one light, chosen by its power over its
        // squared distance (`light_choice`).
        let mut shadow = None;
        let choice = if bsdf.is_delta() {
            None
        } else {
            self.lights.sample(p, Some(ng), u_light)
        };
        if let Some((i, p_choice)) = choice {
            let light = self.sample_direct(i, p_choice, &now, p, Some(ng), [u_select, u_l0, u_l1]);
            if let Some(d) = light {
                let (ls, pdf) = (&d.ls, d.pdf);
                let wo = frame.to_local(ls.wi);
                let f = bsdf.eval(&now, at, wi, wo, Transport::Radiance);
                if !f.is_zero() {
                    let ray = d.ray(scene.geometry.offset_unit());
                    let w = if ls.delta {
                        1.0
                    } else {
                        let p_bsdf = bsdf.pdf_at(&now, at, wi, wo);
                        power_heuristic(pdf, self.bounce_pdf(guide, bsdf, p, ls.wi, p_bsdf))
                    };
                    shadow = Some((ray, path.beta * f * ls.radiance * (w / pdf)));
                }
            }
        }
        // The same light by way of glass balls (`manifold`), where a path
        // could reach it that way within the depth.
        let mut traced = 0;
        let shares = match MEDIA || self.lenses.is_empty() {
            true => Shares::default(),
            false => shares_at(joined).fitting(self.room(path.depth)),
        };
        if let (true, Some(choice)) = (shares.any(), choice) {
            let chance = if shares.by_chance() {
                path.rng.next_f32()
            } else {
                0.0
            };
            let at_x = (bsdf, guide, wi);
            let u = ([u_select, u_l0, u_l1], joined);
            let (beta, traced) = (&path.beta, &mut traced);
            let run = (choice, (shares, chance));
            path.l += self.through_lenses(&now, beta, point, at_x, run, u, traced);
        }
        // The caustic as a light: the path's light subpath through a ball,
        // joined here where the estimator would run at its vertex (a
        // straight leg; legs by way of a ball check their own depth).
        if !MEDIA
            && path.caustic.is_on()
            && !bsdf.is_delta()
            && self.within(path.depth + 1 + SHORTEST)
        {
            let light = self.join_caustic(path, point, (bsdf, guide, wi), &mut traced);
            path.l += light;
        }
        let mut stop = Bounce {
            shadow,
            shadow_medium: path.medium,
            goes_on: false,
            record: None,
            traced,
        };

        // Continue by sampling the BSDF (at diffuse vertices, partly
        // towards lamp-lit glossy surfaces: `reflectors`; where guided,
        // half from the guide: `guided`).
        let u_b = [u_lobe, u_b0, u_b1];
        let Some(bs) = self.sample_bounce(guide, bsdf, &now, point, wi, u_b) else {
            return stop;
        };
        if bs.collapse {
            path.wl.terminate_secondary();
            path.now.terminate_secondary();
            if MEDIA && !path.renormalise() {
                return stop;
            }
        }
        path.beta *= bs.weight;
        if path.beta.is_zero() || !path.beta.max_value().is_finite() {
            return stop;
        }
        // Through a null lobe (a medium's boundary, `null`, the slab of a
        // thin dielectric) a volume path tracer does not scatter: the
        // depth and the last vertex for MIS stay those before it
        // (Mitsuba's volpath).
        let passes = MEDIA && bs.passes_through(wi);
        let d = if passes {
            path.ray.d
        } else {
            path.delta = bs.delta;
            path.bsdf_pdf = bs.pdf;
            path.prev = p;
            path.prev_n = Some(ng);
            path.depth += 1;
            frame.to_world(bs.wo)
        };
        if !bs.delta {
            path.passage = match shares.any() && !bsdf.is_delta() {
                true => Passage::left((p, ng), d, bs.pdf, (shares, joined)),
                false => Passage::default(),
            };
        }
        if !passes && !bs.delta {
            let at = (p, Some(facing));
            stop.record = self.pending(at, d, bs.pdf, &path.beta, &mut path.rng);
        }
        path.ray = spawn(p, ng, d, scene.geometry.offset_unit());
        self.onwards(path, u_rr, stop)
    }

    /// `stop`'s shadow ray, and the path going on along its new ray
    /// unless Russian roulette ends it.
    #[inline]
    pub(super) fn onwards<const K: usize>(
        &self,
        path: &mut PathState<K>,
        u_rr: f32,
        stop: Bounce<K>,
    ) -> Bounce<K> {
        let goes_on = self.roulette(path, u_rr);
        Bounce { goes_on, ..stop }
    }

    /// Russian roulette from rr_depth on (Mitsuba's rule: survive with
    /// the throughput's largest value, at most 0.95, but here at least
    /// [`MIN_SURVIVAL`]); whether the path survives.
    #[inline]
    pub(super) fn roulette<const K: usize>(&self, path: &mut PathState<K>, u_rr: f32) -> bool {
        if path.depth > self.scene.integrator.rr_depth.max(1) {
            let q = path.beta.max_value().clamp(MIN_SURVIVAL, 0.95);
            if u_rr >= q {
                return false;
            }
            path.beta /= q;
        }
        true
    }
}

/// The least probability with which Russian roulette lets a path go on,
/// so that a survivor's throughput grows at most 20-fold. Mitsuba's rule
/// alone lets a path whose throughput a bounce aimed at a small bright
/// target made small (the fog's bounce aimed at a lamp-lit pole, f/q ≈
/// 0.016) survive with that small probability and carry the whole
/// light it then finds: on the foggy street, a path of throughput 0.003
/// survived ×300 and hit the LED beside the pole, 2 000× its pixel's
/// value.
pub const MIN_SURVIVAL: f32 = 0.05;

impl<const K: usize> PathState<K> {
    /// A path on cluster `wl` about to follow `ray` (from its origin, in
    /// clear air), with `depth` segments counted so far.
    pub(super) fn new(ray: Ray, wl: SampledWavelengths<K>, depth: i32) -> Self {
        Self {
            ray,
            l: SampledSpectrum::splat(0.0),
            beta: SampledSpectrum::splat(1.0),
            wl,
            now: wl,
            delta: true,
            bsdf_pdf: 0.0,
            prev: ray.o,
            prev_n: None,
            depth,
            whole: !wl.secondary_terminated(),
            medium: None,
            ratio: SampledSpectrum::splat(1.0),
            rng: SplitMix(0),
            trail: Trail::default(),
            passage: Passage::default(),
            caustic: Caustic::Off,
            seen: None,
        }
    }
}

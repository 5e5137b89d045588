//! The path tracer through participating media (Mitsuba's `volpath`):
//! free flights drawn between surfaces, scattering by the phase function
//! with next-event estimation (MIS against phase sampling, power
//! heuristic on the directional densities as at surfaces), shadow rays
//! attenuated by the media they cross and passing null surfaces, which
//! bound media without counting as bounces.
//!
//! Chromatic media: each free flight is drawn for the cluster's first
//! wavelength, and the path keeps every wavelength's density of its medium
//! events relative to the others (`PathState::ratio`). Dividing the
//! throughput by their mean is the one-sample MIS over the cluster (the
//! balance heuristic; Wilkie et al. 2014, §4; pbrt-v4 §14.2.2 keeps the
//! same ratios as r_u): every wavelength's estimate is unbiased and none
//! is lost where its extinction differs from the sampled one's. The mean
//! is kept at 1 by rescaling both after every event, so the throughput is
//! always the weighted one and clear-air paths are untouched. The cluster
//! is a uniform choice of its first member (`start_sample` rotates it),
//! which the MIS needs.

use scotopia_color::SampledSpectrum;

use super::path::{Bounce, PathState};
use super::select::Media;
use super::{equiangular, Renderer};
use crate::guiding::DTree;
use crate::math::{Ray, Vec3};
use crate::medium::{Homogeneous, Medium, MediumEvent, Phase, ShapeMedia};
use crate::sampling::sobol::Sampler;

impl Renderer<'_> {
    /// [`Self::trace`] through media.
    pub(super) fn trace_media<const K: usize>(
        &self,
        media: &Media,
        sampler: &mut Sampler,
        path: &mut PathState<K>,
        rays: &mut u64,
    ) {
        let targets = &media.targets;
        let scene = self.scene;
        loop {
            *rays += 1;
            let hit = scene.geometry.intersect(&path.ray);
            if let Some(m) = path.medium {
                let medium = &scene.media[m as usize];
                let t_max = hit.as_ref().map_or(f32::INFINITY, |h| h.t);
                let u_t = sampler.get_1d();
                let (ray, ratio) = (path.ray, path.ratio);
                // Equi-angular sampling's extra scattering point, for a
                // homogeneous medium (whose free-flight density is known).
                let aimed = match medium {
                    Medium::Homogeneous(h)
                        if !targets.is_empty() && self.within(path.depth + 1) =>
                    {
                        let st = h.sigma_t(&path.now);
                        self.equiangular_light(targets, path, h, &st, t_max, rays);
                        Some(st)
                    }
                    _ => None,
                };
                let event = medium.sample_event(&ray, t_max, &path.now, u_t, &mut path.rng);
                if !path.add_event(&event) {
                    return;
                }
                if event.scattered {
                    let p = ray.o + ray.d * event.t;
                    // How much likelier equi-angular sampling was to put
                    // the point here, squared (0 without it).
                    let q2 = aimed.map_or(0.0, |st| {
                        let free = free_flight_pdf(&st, path, &ratio, event.t);
                        let q = targets.pdf(&ray, t_max, event.t) / free;
                        if q.is_finite() {
                            q * q
                        } else {
                            f32::MAX
                        }
                    });
                    let u = sampler.get_two_4d();
                    let b = self.scatter_in_medium(path, u, p, medium.phase(), q2);
                    if !self.settle::<K, true>(path, b, rays) {
                        return;
                    }
                    continue;
                }
            }
            if !self.arrive::<K, true>(sampler, path, hit, rays) {
                return;
            }
        }
    }

    /// Direct light at a scattering point drawn equi-angularly on the
    /// path's current segment (up to `t_max`) in homogeneous medium `h`
    /// (σ_t on the path's wavelengths `st`),
    /// weighted against free flights by the power heuristic; added to the
    /// path's light at once. The path itself is not moved.
    fn equiangular_light<const K: usize>(
        &self,
        targets: &equiangular::Targets,
        path: &mut PathState<K>,
        h: &Homogeneous,
        st: &SampledSpectrum<K>,
        t_max: f32,
        rays: &mut u64,
    ) {
        let ray = path.ray;
        let mut u = || path.rng.next_f32();
        let (u_pick, u_t) = (u(), u());
        let nee = [u(), u(), u(), u()];
        let Some((t, pdf)) = targets.sample(&ray, t_max, u_pick, u_t) else {
            return;
        };
        let q = pdf / free_flight_pdf(st, path, &path.ratio, t);
        let q2 = if q.is_finite() { q * q } else { f32::MAX };
        let albedo = h.albedo.sample(&path.now).map(|a| a.clamp(0.0, 1.0));
        // T(t) σ_s per wavelength, over the density of t.
        let segment = SampledSpectrum::from_fn(|k| {
            let tr = if st.0[k] > 0.0 {
                (-st.0[k] * t).exp()
            } else {
                1.0
            };
            tr * st.0[k] * albedo.0[k]
        }) * pdf.recip();
        let beta = path.beta * segment;
        if beta.is_zero() {
            return;
        }
        let p = ray.o + ray.d * t;
        let guide = self.phase_guide(self.spot(p, None), &h.phase);
        let aimed = Mis::Aimed(q2);
        if let Some((shadow, c)) = self.medium_nee(path, beta, p, (h.phase, guide), nee, aimed) {
            let tr = self.through_media(shadow, path.medium, &path.now, &mut path.rng, rays);
            path.l += c * tr;
        }
    }

    /// Next-event estimation at medium point `p` reached along the path's
    /// ray with throughput `beta`, drawn as `mis` says: the shadow ray and
    /// what it brings if clear.
    fn medium_nee<const K: usize>(
        &self,
        path: &PathState<K>,
        beta: SampledSpectrum<K>,
        p: Vec3,
        (phase, guide): (Phase, Option<&DTree>),
        [u_light, u_select, u_l0, u_l1]: [f32; 4],
        mis: Mis,
    ) -> Option<(Ray, SampledSpectrum<K>)> {
        let wi = -path.ray.d;
        let (i, p_choice) = self.lights.sample(p, None, u_light)?;
        let d = self.sample_direct(i, p_choice, &path.now, p, None, [u_select, u_l0, u_l1])?;
        let f = phase.eval(wi, d.ls.wi);
        if f.is_nan() || f <= 0.0 {
            return None;
        }
        let w = mis.light_weight(d.pdf, self.phase_pdf(guide, p, f, d.ls.wi), d.ls.delta);
        let unit = self.scene.geometry.offset_unit();
        (w > 0.0).then(|| (d.ray(unit), beta * d.ls.radiance * (f * w / d.pdf)))
    }

    /// A scattering event in a medium at `p` (phase function `phase`),
    /// reached by a free flight that equi-angular sampling would have drawn
    /// with `q2` times the squared density (0 without it): next-event
    /// estimation and the next direction, drawn from the phase function.
    /// `u`: the path's next two 4-dimensional sets.
    fn scatter_in_medium<const K: usize>(
        &self,
        path: &mut PathState<K>,
        u: [[f32; 4]; 2],
        p: Vec3,
        phase: &Phase,
        q2: f32,
    ) -> Bounce<K> {
        if !self.within(path.depth + 1) {
            return Bounce::STOP;
        }
        let [nee, [u_p0, u_rr, u_p1, u_pick]] = u;
        let wi = -path.ray.d;
        let spot = self.spot(p, None);
        let guide = self.phase_guide(spot, phase);
        let shadow = self.medium_nee(path, path.beta, p, (*phase, guide), nee, Mis::Free(q2));
        let mut stop = Bounce {
            shadow,
            shadow_medium: path.medium,
            goes_on: false,
            record: None,
            traced: 0,
        };
        // The phase function's direction, or where guided, half of them
        // the guide's (`guided`), a share aimed at the lamps' halos
        // (`halo`) and one at lamp-lit reflectors (`reflectors`): f/q.
        let Some((wo, f, pdf)) = self.sample_phase(guide, (phase, p), wi, u_pick, [u_p0, u_p1])
        else {
            return stop;
        };
        if f != pdf {
            path.beta *= f / pdf;
            if path.beta.is_zero() || !path.beta.max_value().is_finite() {
                return stop;
            }
        }
        stop.record = self.pending((p, None), wo, pdf, &path.beta, &mut path.rng);
        path.delta = false;
        // A light this direction hits weighs it against next-event
        // estimation from both distance strategies: the power heuristic
        // q²/(q² + p_l²(1 + q_d²)) with q the direction's density and q_d
        // the distances' ratio, which `bounce` and `escape` compute from
        // q/√(1 + q_d²).
        path.bsdf_pdf = pdf / (1.0 + q2).sqrt();
        path.prev = p;
        path.prev_n = None;
        path.ray = Ray::new(p, wo);
        path.depth += 1;
        self.onwards(path, u_rr, stop)
    }

    /// The media either side of shape `shape`, when it bounds any.
    #[inline]
    pub(super) fn shape_media(&self, shape: u32) -> Option<ShapeMedia> {
        self.scene
            .shape_media
            .get(shape as usize)
            .copied()
            .filter(ShapeMedia::is_transition)
    }
}

impl<const K: usize> PathState<K> {
    /// Takes a medium event into the throughput and the cluster's
    /// densities; whether the path still carries light.
    fn add_event(&mut self, e: &MediumEvent<K>) -> bool {
        self.beta = self.beta * e.own * e.density;
        self.ratio *= e.density;
        self.renormalise()
    }

    /// Rescales the densities to a mean of 1 over the live wavelengths
    /// (all, or the first alone once the cluster collapsed), and the
    /// throughput with them; whether the path still carries light.
    pub(super) fn renormalise(&mut self) -> bool {
        let live = if self.wl.secondary_terminated() { 1 } else { K };
        let mean = self.ratio.0[..live].iter().sum::<f32>() / live as f32;
        if !(mean > 0.0 && mean.is_finite()) {
            self.beta = SampledSpectrum::splat(0.0);
            return false;
        }
        self.ratio /= mean;
        self.beta /= mean;
        !self.beta.is_zero() && self.beta.max_value().is_finite()
    }
}

/// The density per unit length with which the path's free flight in a
/// homogeneous medium of extinction `st` (on the path's wavelengths)
/// reaches a scattering event at `t`: the mixture over the live
/// wavelengths, each weighted by its share `ratio` of the path's density
/// so far (the estimate the cluster's MIS makes is the one of this
/// mixture).
fn free_flight_pdf<const K: usize>(
    st: &SampledSpectrum<K>,
    path: &PathState<K>,
    ratio: &SampledSpectrum<K>,
    t: f32,
) -> f32 {
    let live = if path.wl.secondary_terminated() { 1 } else { K };
    let sum: f32 = (0..live)
        .map(|k| {
            let s = st.0[k];
            if s > 0.0 {
                ratio.0[k] * s * (-s * t).exp()
            } else {
                0.0
            }
        })
        .sum();
    sum / live as f32
}

/// How a next-event estimate in a medium was reached, for its MIS weight
/// among the three ways to the same light: a free flight then the light
/// sampled (A), a free flight then the phase function's direction (B), an
/// equi-angular distance then the light sampled (C). With q the ratio of
/// the equi-angular to the free-flight distance density at the point, the
/// power heuristic gives A p_l²/D and C q² p_l²/D with D = p_l²(1 + q²) +
/// f², and B f²/D (`scatter_in_medium`); a delta light cannot be hit, so
/// A and C share it as 1 : q².
#[derive(Clone, Copy)]
enum Mis {
    /// A free-flight point; q² (0 without equi-angular sampling).
    Free(f32),
    /// An equi-angular point; q².
    Aimed(f32),
}

impl Mis {
    fn light_weight(self, p_light: f32, f: f32, delta: bool) -> f32 {
        let (num, q2) = match self {
            Mis::Free(q2) => (1.0, q2),
            Mis::Aimed(q2) => (q2, q2),
        };
        let w = if delta {
            num / (1.0 + q2)
        } else {
            let l2 = p_light * p_light;
            num * l2 / (l2 * (1.0 + q2) + f * f)
        };
        if w.is_finite() {
            w
        } else {
            // q² overflowed: the aimed strategy takes it all.
            match self {
                Mis::Free(_) => 0.0,
                Mis::Aimed(_) => 1.0,
            }
        }
    }
}

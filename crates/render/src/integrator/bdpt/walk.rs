//! Building the two subpaths: a camera subpath from the lens, a light
//! subpath from a light, each continued by BSDF sampling with Russian
//! roulette, storing on every vertex the densities MIS needs.

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::connect::Draw;
use super::media::take_event;
use super::vertex::{shading_correction, Kind, Vertex, MAX_VERTICES};
use crate::bsdf::Transport;
use crate::integrator::direct::spawn;
use crate::integrator::light_choice::ClusterChoice;
use crate::integrator::path::MIN_SURVIVAL;
use crate::integrator::Renderer;
use crate::math::{Ray, Vec3};

impl Renderer<'_> {
    /// Camera subpath along camera ray `ray` from lens point `lens_point`:
    /// z₀ on the lens, then up to `max` vertices in all. Returns whether its
    /// cluster collapsed.
    pub(super) fn camera_subpath<const K: usize>(
        &self,
        draw: &mut Draw<'_>,
        wl: &SampledWavelengths<K>,
        ray: Ray,
        lens_point: Vec3,
        max: usize,
        path: &mut Vec<Vertex<K>>,
    ) -> bool {
        path.clear();
        let camera = &self.scene.camera;
        let mut z0 = Vertex::new(Kind::Camera, lens_point, SampledSpectrum::splat(1.0));
        z0.pdf_fwd = camera.pdf_lens();
        z0.medium = self.start_medium(draw);
        path.push(z0);
        let leaving = Leaving {
            ray,
            medium: z0.medium,
            beta: SampledSpectrum::splat(1.0),
            pdf: camera.pdf_direction(lens_point, ray.d),
        };
        let mut wl = *wl;
        self.walk(draw, &mut wl, leaving, Transport::Radiance, max, path)
    }

    /// The camera's medium, when media are traced.
    fn start_medium(&self, draw: &Draw<'_>) -> Option<u32> {
        self.scene.camera_medium.filter(|_| draw.media)
    }

    /// Light subpath of at most `max` vertices from a light chosen by
    /// `choice`, carrying cluster `wl` (whose members fluorescence moves).
    /// Returns whether its cluster collapsed; empty when no light emits.
    pub(super) fn light_subpath<const K: usize>(
        &self,
        draw: &mut Draw<'_>,
        lens_point: Vec3,
        wl: &mut SampledWavelengths<K>,
        choice: &ClusterChoice,
        max: usize,
        path: &mut Vec<Vertex<K>>,
    ) -> bool {
        path.clear();
        let [u_choice, u_select, u_p0, u_p1] = draw.sampler.get_4d();
        let [u_d0, u_d1] = draw.sampler.get_2d();
        if max == 0 {
            return false;
        }
        let Some((l, q)) = choice.sample(u_choice) else {
            return false;
        };
        let light = &self.scene.lights[l];
        let extent = self.extent();
        let Some(e) = light
            .sample_le(&extent, wl, u_select, [u_p0, u_p1], [u_d0, u_d1])
            .and_then(|e| self.guide_emission(light, e, wl, [u_d0, u_d1], draw.rng))
        else {
            return false;
        };
        if !(e.pdf_pos > 0.0 && e.pdf_dir > 0.0) || e.le.is_zero() {
            return false;
        }
        let kind = if light.is_infinite() {
            Kind::Infinite
        } else {
            Kind::Light
        };
        let mut y0 = Vertex::new(kind, e.p, SampledSpectrum::splat(1.0 / (q * e.pdf_pos)));
        y0.index = l as u32;
        y0.at_infinity = light.is_infinite() || light.is_delta_direction();
        if let Some(n) = e.n {
            y0.ng = n;
            y0.ns = n;
        }
        y0.tex = e.uv.into();
        y0.wi = -e.d;
        y0.pdf_fwd = self.origin_density(|i| choice.probability(i), &y0);
        if draw.media {
            // The medium around the light (`media`): an area light on a
            // shape bounding media emits into the medium on its side.
            let camera_medium = self.start_medium(draw);
            y0.medium = self.medium_at(lens_point, camera_medium, e.p, draw.rays);
            if y0.at_infinity && y0.medium.is_some() {
                return false;
            }
        }
        path.push(y0);
        let cos = e.n.map_or(1.0, |n| n.dot(e.d).abs());
        let beta = e.le * (cos / (q * e.pdf_pos * e.pdf_dir));
        let pdf = if y0.at_infinity { e.pdf_pos } else { e.pdf_dir };
        let ray = match e.n {
            Some(n) => spawn(e.p, n, e.d, self.scene.geometry.offset_unit()),
            None => Ray::new(e.p, e.d),
        };
        let leaving = Leaving {
            ray,
            medium: self.medium_towards(&y0, e.d),
            beta,
            pdf,
        };
        self.walk(draw, wl, leaving, Transport::Importance, max, path)
    }

    /// Extends `path` from its last vertex as `from` leaves it, to at most
    /// `max` vertices. Returns whether the cluster collapsed.
    fn walk<const K: usize>(
        &self,
        draw: &mut Draw<'_>,
        wl: &mut SampledWavelengths<K>,
        from: Leaving<K>,
        mode: Transport,
        max: usize,
        path: &mut Vec<Vertex<K>>,
    ) -> bool {
        let Leaving {
            mut ray,
            mut medium,
            mut beta,
            mut pdf,
        } = from;
        let Draw {
            sampler,
            rng,
            rays,
            media,
        } = draw;
        let media = *media;
        let scene = self.scene;
        let max = max.min(MAX_VERTICES);
        let mut collapsed = false;
        // Roulette compares the throughput with where it started (a light
        // path's is in watts).
        let start = beta.max_value();
        let mut passes = 0usize;
        while path.len() < max {
            **rays += 1;
            let prev = *path.last().expect("a subpath starts with its endpoint");
            let hit = scene.geometry.intersect(&ray);
            // A free flight through the medium the ray travels in.
            if let (true, Some(m)) = (media, medium) {
                let t_max = hit.as_ref().map_or(f32::INFINITY, |h| h.t);
                let u = sampler.get_1d();
                let e = scene.media[m as usize].sample_event(&ray, t_max, wl, u, rng);
                if !take_event(&mut beta, &e, &mut collapsed) {
                    break;
                }
                if e.scattered {
                    let mut v = Vertex::new(Kind::Medium, ray.o + ray.d * e.t, beta);
                    v.index = m;
                    v.medium = Some(m);
                    v.collapsed = collapsed;
                    v.wi = -ray.d;
                    v.pdf_fwd = prev.convert(pdf, &v);
                    v.run_in = prev.run_out;
                    v.run_out = prev.run_out;
                    let i = path.len();
                    path.push(v);
                    if path.len() >= max {
                        break;
                    }
                    // The phase function is sampled exactly (f/p = 1) and
                    // is symmetric: its reverse density is its value.
                    let [u_p0, u_p1, u_rr, _] = sampler.get_4d();
                    let phase = scene.media[m as usize].phase();
                    let (wo, pdf_wo) = phase.sample(v.wi, [u_p0, u_p1]);
                    path[i - 1].pdf_rev = v.convert(pdf_wo, &path[i - 1]);
                    pdf = pdf_wo;
                    ray = Ray::new(v.p, wo);
                    if !self.roulette_bdpt(&mut beta, start, i, u_rr) {
                        break;
                    }
                    continue;
                }
            }
            let Some(hit) = hit else {
                // A camera ray that escapes ends on the lights at infinity.
                if mode == Transport::Radiance && self.has_infinite_lights() {
                    let mut v = Vertex::new(
                        Kind::Infinite,
                        ray.o + ray.d * (2.0 * self.bounds.radius),
                        beta,
                    );
                    v.wi = ray.d;
                    v.at_infinity = true;
                    v.pdf_fwd = pdf;
                    v.medium = medium;
                    v.collapsed = collapsed;
                    path.push(v);
                }
                break;
            };
            let surface = scene.geometry.surface(&hit, &ray);
            let mut v = Vertex::new(Kind::Surface, surface.p, beta);
            v.ng = surface.n_geometric;
            v.ns = surface.n_shading;
            v.tex = surface.tex(&hit);
            v.dpdu = surface.dpdu;
            v.dpdv = surface.dpdv;
            v.index = hit.shape;
            v.wi = -ray.d;
            v.medium = medium;
            v.collapsed = collapsed;
            v.run_in = prev.run_out;
            v.run_out = prev.run_out;
            let bsdf = &scene.materials[scene.shape_material[hit.shape as usize] as usize];
            let (frame, at) = v.shading();
            let wi = frame.to_local(v.wi);
            let [u_lobe, u_rr, u_b0, u_b1] = sampler.get_4d();

            // Through media, a null lobe is no vertex: the subpath passes
            // the surface into the medium beyond (as the path tracer does).
            // (Drawn here, before the vertex is kept; fluorescent BSDFs,
            // which move wavelengths first, have no null lobe.)
            let early = (media && bsdf.may_pass() && bsdf.fluorescent().is_none())
                .then(|| bsdf.sample(wl, at, wi, u_lobe, [u_b0, u_b1], mode));
            if let Some(Some(bs)) = &early {
                if bs.passes_through(wi) && passes < MAX_PASSES {
                    passes += 1;
                    beta *= bs.weight;
                    if beta.is_zero() || !beta.max_value().is_finite() {
                        break;
                    }
                    if let Some(sides) = self.shape_media(hit.shape) {
                        medium = sides.target(ray.d, v.ng);
                    }
                    let (d, t_max) = (ray.d, ray.t_max);
                    ray = spawn(v.p, v.ng, d, scene.geometry.offset_unit());
                    ray.t_max = t_max;
                    continue;
                }
            }
            v.pdf_fwd = prev.convert(pdf, &v);
            let i = path.len();
            path.push(v);
            if path.len() >= max {
                break;
            }

            // Scatter: fluorescence first (light paths move wavelengths,
            // camera paths see the elastic part), then the BSDF.
            if let Some(f) = bsdf.fluorescent() {
                match mode {
                    Transport::Radiance => beta *= f.reflectance.eval(wl, v.tex),
                    Transport::Importance => {
                        let u = sampler.get_1d();
                        let (factor, moved) = f.reradiate_forward(wl, &beta, v.tex, u);
                        let last = &mut path[i];
                        for k in (0..K).filter(|&k| moved[k]) {
                            last.run_out[k] = i as u8;
                            last.shift.0[k] = factor.0[k];
                            last.lambda_out[k] = wl.lambda(k);
                        }
                        beta *= factor;
                    }
                }
                if beta.is_zero() {
                    break;
                }
            }
            let drawn = match early {
                Some(bs) => bs,
                None => bsdf.sample(wl, at, wi, u_lobe, [u_b0, u_b1], mode),
            };
            let Some(bs) = drawn else {
                break;
            };
            let wo = frame.to_world(bs.wo);
            let mut weight = bs.weight;
            if mode == Transport::Importance {
                weight *= shading_correction(v.ng, v.ns, v.wi, wo);
            }
            if bs.collapse && K > 1 && !collapsed {
                // Only the first member's direction was sampled: it goes
                // on for all K (pbrt-v4's TerminateSecondary).
                collapsed = true;
                beta =
                    SampledSpectrum::from_fn(|k| if k == 0 { beta.0[0] * K as f32 } else { 0.0 });
            }
            beta *= weight;
            let (pdf_fwd, pdf_rev) = if bs.delta {
                (0.0, 0.0)
            } else {
                (bs.pdf, bsdf.pdf_at(wl, at, bs.wo, wi))
            };
            path[i].delta = bs.delta;
            path[i - 1].pdf_rev = path[i].convert(pdf_rev, &path[i - 1]);
            pdf = pdf_fwd;
            if beta.is_zero() || !beta.max_value().is_finite() {
                break;
            }
            ray = spawn(v.p, v.ng, wo, scene.geometry.offset_unit());
            if media {
                if let Some(sides) = self.shape_media(hit.shape) {
                    medium = sides.target(wo, v.ng);
                }
            }
            if !self.roulette_bdpt(&mut beta, start, i, u_rr) {
                break;
            }
        }
        collapsed
    }

    /// Russian roulette from rr_depth on, as the path tracer does, for a
    /// subpath leaving vertex `i` (throughput `beta`, `start` at its
    /// endpoint); whether it goes on.
    fn roulette_bdpt<const K: usize>(
        &self,
        beta: &mut SampledSpectrum<K>,
        start: f32,
        i: usize,
        u_rr: f32,
    ) -> bool {
        if i as i32 + 1 > self.scene.integrator.rr_depth.max(1) {
            let q = (beta.max_value() / start).clamp(MIN_SURVIVAL, 0.95);
            if u_rr >= q {
                return false;
            }
            *beta /= q;
        }
        true
    }
}

/// How a subpath leaves its last vertex: along `ray`, into `medium`, with
/// throughput `beta` and density `pdf` (per solid angle, or per disk
/// area for a light at infinity).
struct Leaving<const K: usize> {
    ray: Ray,
    medium: Option<u32>,
    beta: SampledSpectrum<K>,
    pdf: f32,
}

/// Most null surfaces a subpath passes between two vertices.
const MAX_PASSES: usize = 1024;

//! Building the two subpaths: a camera subpath from the lens, a light
//! subpath from a light, each continued by BSDF sampling with Russian
//! roulette, storing on every vertex the densities MIS needs.

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::clusters::LightChoice;
use super::vertex::{Kind, Vertex, MAX_VERTICES};
use crate::bsdf::Transport;
use crate::integrator::path::spawn;
use crate::integrator::Renderer;
use crate::math::{Ray, Vec3};
use crate::sampling::sobol::Sampler;

/// The factor that makes shading normals symmetric for light paths
/// (Veach 1997, §5.3, eq. 5.19): |wi·ns||wo·ng| / (|wi·ng||wo·ns|), with
/// `wi` towards where the light came from and `wo` where it goes.
#[inline]
pub(super) fn shading_correction(ng: Vec3, ns: Vec3, wi: Vec3, wo: Vec3) -> f32 {
    let den = wi.dot(ng).abs() * wo.dot(ns).abs();
    if den == 0.0 {
        0.0
    } else {
        wi.dot(ns).abs() * wo.dot(ng).abs() / den
    }
}

impl Renderer<'_> {
    /// Camera subpath through film position `film`: z₀ on the lens, then
    /// up to `max` vertices in all. Returns whether its cluster collapsed.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn camera_subpath<const K: usize>(
        &self,
        sampler: &mut Sampler,
        wl: &SampledWavelengths<K>,
        film: [f32; 2],
        lens: [f32; 2],
        max: usize,
        path: &mut Vec<Vertex<K>>,
        rays: &mut u64,
    ) -> bool {
        path.clear();
        let camera = &self.scene.camera;
        let (ray, lens_point) = camera.generate_ray_from_lens(film, lens);
        let mut z0 = Vertex::new(Kind::Camera, lens_point, SampledSpectrum::splat(1.0));
        z0.pdf_fwd = camera.pdf_lens();
        path.push(z0);
        let pdf = camera.pdf_direction(lens_point, ray.d);
        self.walk(
            sampler,
            &mut wl.clone(),
            ray,
            SampledSpectrum::splat(1.0),
            pdf,
            Transport::Radiance,
            max,
            path,
            rays,
        )
    }

    /// Light subpath of at most `max` vertices from a light chosen by
    /// `choice`, carrying cluster `wl` (whose members fluorescence moves).
    /// Returns whether its cluster collapsed; empty when no light emits.
    #[allow(clippy::too_many_arguments)]
    pub(super) fn light_subpath<const K: usize>(
        &self,
        sampler: &mut Sampler,
        wl: &mut SampledWavelengths<K>,
        choice: &LightChoice,
        max: usize,
        path: &mut Vec<Vertex<K>>,
        rays: &mut u64,
    ) -> bool {
        path.clear();
        let [u_choice, u_select, u_p0, u_p1] = sampler.get_4d();
        let [u_d0, u_d1] = sampler.get_2d();
        if max == 0 {
            return false;
        }
        let Some((l, q)) = choice.sample(u_choice) else {
            return false;
        };
        let light = &self.scene.lights[l];
        let extent = self.extent();
        let Some(e) = light.sample_le(&extent, wl, u_select, [u_p0, u_p1], [u_d0, u_d1]) else {
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
        y0.pdf_fwd = self.origin_density(choice, &y0);
        path.push(y0);
        let cos = e.n.map_or(1.0, |n| n.dot(e.d).abs());
        let beta = e.le * (cos / (q * e.pdf_pos * e.pdf_dir));
        let pdf = if y0.at_infinity { e.pdf_pos } else { e.pdf_dir };
        let ray = match e.n {
            Some(n) => spawn(e.p, n, e.d, self.scene.geometry.offset_unit()),
            None => Ray::new(e.p, e.d),
        };
        self.walk(
            sampler,
            wl,
            ray,
            beta,
            pdf,
            Transport::Importance,
            max,
            path,
            rays,
        )
    }

    /// Extends `path` from its last vertex along `ray` (left with density
    /// `pdf`, per solid angle or per disk area for a light at infinity),
    /// to at most `max` vertices. Returns whether the cluster collapsed.
    #[allow(clippy::too_many_arguments)]
    fn walk<const K: usize>(
        &self,
        sampler: &mut Sampler,
        wl: &mut SampledWavelengths<K>,
        mut ray: Ray,
        mut beta: SampledSpectrum<K>,
        mut pdf: f32,
        mode: Transport,
        max: usize,
        path: &mut Vec<Vertex<K>>,
        rays: &mut u64,
    ) -> bool {
        let scene = self.scene;
        let max = max.min(MAX_VERTICES);
        let mut collapsed = false;
        // Roulette compares the throughput with where it started (a light
        // path's is in watts).
        let start = beta.max_value();
        while path.len() < max {
            *rays += 1;
            let prev = *path.last().expect("a subpath starts with its endpoint");
            let Some(hit) = scene.geometry.intersect(&ray) else {
                // A camera ray that escapes ends on the lights at infinity.
                if mode == Transport::Radiance && self.has_infinite_lights() {
                    let mut v =
                        Vertex::new(Kind::Infinite, ray.o + ray.d * (2.0 * self.radius), beta);
                    v.wi = ray.d;
                    v.at_infinity = true;
                    v.pdf_fwd = pdf;
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
            v.pdf_fwd = prev.convert(pdf, &v);
            v.run_in = prev.run_out;
            v.run_out = prev.run_out;
            let i = path.len();
            path.push(v);
            if path.len() >= max {
                break;
            }

            // Scatter: fluorescence first (light paths move wavelengths,
            // camera paths see the elastic part), then the BSDF.
            let bsdf = &scene.materials[scene.shape_material[hit.shape as usize] as usize];
            let (frame, at) = v.shading();
            let wi = frame.to_local(v.wi);
            let [u_lobe, u_rr, u_b0, u_b1] = sampler.get_4d();
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
            let Some(bs) = bsdf.sample(wl, at, wi, u_lobe, [u_b0, u_b1], mode) else {
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
            // Russian roulette from rr_depth on, as the path tracer does.
            if i as i32 + 1 > scene.integrator.rr_depth.max(1) {
                let q = (beta.max_value() / start).min(0.95);
                if u_rr >= q {
                    break;
                }
                beta /= q;
            }
        }
        collapsed
    }
}

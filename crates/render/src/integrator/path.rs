//! Unidirectional path tracing with next-event estimation and multiple
//! importance sampling (Veach 1997, power heuristic β = 2), Russian
//! roulette, and cluster collapse at dispersive refraction (pbrt-v4's
//! `TerminateSecondary`). Mitsuba's depth convention: a path of depth d has
//! d segments; `max_depth` 1 sees emitters only, 2 adds direct light.

use scotopia_color::photometry::estimate_xyzv;
use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::Renderer;
use crate::bsdf::{ShadingPoint, Transport};
use crate::light::{Light, LightSample};
use crate::math::{offset_ray_origin, Ray, Vec3};
use crate::sampling::sobol::Sampler;

/// What one camera sample found.
pub struct CameraSample<const K: usize> {
    pub xyzv: [f32; 4],
    pub radiance: SampledSpectrum<K>,
    pub wl: SampledWavelengths<K>,
    /// The path started with several wavelengths and a dispersive
    /// refraction collapsed them to one.
    pub collapsed: bool,
}

/// The power heuristic's weight of a strategy with density `a` against `b`.
#[inline]
fn power_heuristic(a: f32, b: f32) -> f32 {
    let (a2, b2) = (a * a, b * b);
    if a2 + b2 > 0.0 && a2.is_finite() {
        a2 / (a2 + b2)
    } else if a.is_infinite() {
        1.0
    } else {
        0.0
    }
}

/// A ray leaving `p` (geometric normal `n`) in direction `d`.
#[inline]
/// `unit`: the scene's [`crate::accel::Aggregate::offset_unit`].
pub(super) fn spawn(p: Vec3, n: Vec3, d: Vec3, unit: f32) -> Ray {
    let side = if d.dot(n) >= 0.0 { n } else { -n };
    Ray::new(offset_ray_origin(p, side, unit), d)
}

/// The ray that tests whether light sample `ls` reaches `p`. It starts
/// at the offset origin and stops just short of the light's point as seen
/// from there: measured from `p` instead, a grazing ray would reach the
/// light's own surface before its end and count as shadowed.
pub(super) fn shadow_ray<const K: usize>(p: Vec3, n: Vec3, ls: &LightSample<K>, unit: f32) -> Ray {
    let mut ray = spawn(p, n, ls.wi, unit);
    if ls.distance.is_finite() {
        let to = p + ls.wi * ls.distance;
        let d = to - ray.o;
        let dist = d.length();
        ray.d = d / dist;
        ray.t_max = dist * (1.0 - SHADOW_EPSILON);
    }
    ray
}

/// Relative margin a shadow ray stops short of the light's surface.
const SHADOW_EPSILON: f32 = 1e-4;

impl Renderer<'_> {
    /// One camera sample of `pixel`: its X, Y, Z, V′ estimate and the
    /// cluster's radiance, or `None` when the estimate is not finite
    /// (counted by the caller). Adds the rays it traced to `rays`.
    pub fn sample_pixel<const K: usize>(
        &self,
        sampler: &mut Sampler,
        pixel: [u32; 2],
        index: u32,
        rays: &mut u64,
    ) -> Option<CameraSample<K>> {
        let (film, lens, mut wl, _) = self.start_sample::<K>(sampler, pixel, index);
        let whole = !wl.secondary_terminated();
        let ray = self.scene.camera.generate_ray(film, lens);
        let radiance = self.trace(sampler, &mut wl, ray, rays);
        let xyzv = estimate_xyzv(&radiance, &wl);
        let finite = xyzv.iter().all(|v| v.is_finite()) && radiance.0.iter().all(|v| v.is_finite());
        let collapsed = whole && wl.secondary_terminated();
        finite.then_some(CameraSample {
            xyzv,
            radiance,
            wl,
            collapsed,
        })
    }

    /// Radiance arriving along `ray` on the cluster `wl` (which a
    /// dispersive refraction may collapse), counting rays traced.
    fn trace<const K: usize>(
        &self,
        sampler: &mut Sampler,
        wl: &mut SampledWavelengths<K>,
        mut ray: Ray,
        rays: &mut u64,
    ) -> SampledSpectrum<K> {
        let scene = self.scene;
        let max_depth = scene.integrator.max_depth;
        let within = |depth: i32| max_depth < 0 || depth <= max_depth;
        let mut l = SampledSpectrum::<K>::splat(0.0);
        let mut beta = SampledSpectrum::<K>::splat(1.0);
        // The previous bounce: whether it was a delta lobe, its direction
        // density, and where it left from (for MIS on emitters hit).
        let mut delta = true;
        let mut bsdf_pdf = 0.0f32;
        let mut prev = ray.o;
        let mut depth = 1;
        // The wavelengths the path carries now. Fluorescence moves members
        // away from `wl`, the wavelengths the estimate is of (the light
        // absorbed at one wavelength reaches the eye at another).
        let mut now = *wl;
        loop {
            *rays += 1;
            let Some(hit) = scene.geometry.intersect(&ray) else {
                // Escaped: lights at infinity.
                for (i, light) in self.infinite_lights() {
                    let le = light.radiance_at_infinity(&now, ray.d);
                    if le.is_zero() {
                        continue;
                    }
                    let w = if delta {
                        1.0
                    } else {
                        let p_light =
                            self.light_choice.probability(i) * light.pdf_li_at_infinity(ray.d);
                        power_heuristic(bsdf_pdf, p_light)
                    };
                    l += beta * le * w;
                }
                break;
            };
            let surface = scene.geometry.surface(&hit, &ray);
            let wo_world = -ray.d;
            // Emission of an area light we landed on.
            if let Some(li) = scene.shape_light[hit.shape as usize] {
                if let Light::Area(area) = &scene.lights[li as usize] {
                    let le = area.radiance(&now, surface.uv, surface.n_geometric, wo_world);
                    if !le.is_zero() {
                        let w = if delta {
                            1.0
                        } else {
                            let p_light = self.light_choice.probability(li as usize)
                                * area.pdf_li(prev, surface.p, surface.n_geometric);
                            power_heuristic(bsdf_pdf, p_light)
                        };
                        l += beta * le * w;
                    }
                }
            }
            if !within(depth + 1) {
                break;
            }
            let bsdf = &scene.materials[scene.shape_material[hit.shape as usize] as usize];
            let (frame, at) = ShadingPoint::at(
                surface.tex(&hit),
                surface.n_shading,
                surface.n_geometric,
                surface.dpdu,
                surface.dpdv,
            );
            let wi = frame.to_local(wo_world);
            let uv = at.tex();
            let [u_light, u_select, u_l0, u_l1] = sampler.get_4d();
            let [u_lobe, u_rr, u_b0, u_b1] = sampler.get_4d();
            // Fluorescence: members move to their excitation wavelengths
            // before light is sampled there.
            if let Some(f) = bsdf.reradiate(&mut now, uv, u_lobe) {
                beta *= f;
                if beta.is_zero() {
                    break;
                }
            }

            // Next-event estimation: one light chosen by power.
            if !bsdf.is_delta() {
                if let Some((i, p_choice, _)) = self.light_choice.sample_discrete(u_light) {
                    let light = &scene.lights[i];
                    if let Some(ls) =
                        light.sample_li(&self.extent(), &now, surface.p, u_select, [u_l0, u_l1])
                    {
                        let wo = frame.to_local(ls.wi);
                        let f = bsdf.eval(&now, at, wi, wo, Transport::Radiance);
                        if ls.pdf > 0.0 && !f.is_zero() && !ls.radiance.is_zero() {
                            let shadow = shadow_ray(
                                surface.p,
                                surface.n_geometric,
                                &ls,
                                scene.geometry.offset_unit(),
                            );
                            *rays += 1;
                            if !scene.geometry.occluded(&shadow) {
                                let p_light = p_choice * ls.pdf;
                                let w = if ls.delta {
                                    1.0
                                } else {
                                    power_heuristic(p_light, bsdf.pdf_at(&now, at, wi, wo))
                                };
                                l += beta * f * ls.radiance * (w / p_light);
                            }
                        }
                    }
                }
            }

            // Continue by sampling the BSDF.
            let Some(bs) = bsdf.sample(&now, at, wi, u_lobe, [u_b0, u_b1], Transport::Radiance)
            else {
                break;
            };
            if bs.collapse {
                wl.terminate_secondary();
                now.terminate_secondary();
            }
            beta *= bs.weight;
            if beta.is_zero() || !beta.max_value().is_finite() {
                break;
            }
            delta = bs.delta;
            bsdf_pdf = bs.pdf;
            prev = surface.p;
            let d = frame.to_world(bs.wo);
            ray = spawn(
                surface.p,
                surface.n_geometric,
                d,
                scene.geometry.offset_unit(),
            );
            depth += 1;
            // Russian roulette from rr_depth on (Mitsuba's rule: survive
            // with the throughput's largest value, at most 0.95).
            if depth > scene.integrator.rr_depth.max(1) {
                let q = beta.max_value().min(0.95);
                if u_rr >= q {
                    break;
                }
                beta /= q;
            }
        }
        l
    }
}

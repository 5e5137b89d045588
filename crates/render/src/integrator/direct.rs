//! Next-event estimation's shared pieces, used by every integrator: a
//! light sampled towards a point with the ray that tests whether it is
//! seen (`Renderer::sample_direct`), the rays leaving a surface, and the
//! power heuristic that weighs light sampling against the path's own
//! direction, and what passes along a shadow ray: clear air or media and
//! the null surfaces between them (`Renderer::transmittance`). Each
//! integrator chooses the light its own way (the path tracers by power
//! over squared distance, the bidirectional tracer by the cluster: both
//! `light_choice`) and evaluates its scattering (BSDF or phase function).

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use crate::bsdf::ShadingPoint;
use crate::light::LightSample;
use crate::math::{offset_ray_origin, Ray, Vec3};
use crate::sampling::splitmix::SplitMix;

use super::Renderer;

/// What a shadow ray may cross on its way.
pub(super) enum Crossing<'r> {
    /// Clear air: it is seen or not.
    Clear,
    /// Media, from `medium` on, and null surfaces; `rng` draws the media's
    /// estimates.
    Media {
        medium: Option<u32>,
        rng: &'r mut SplitMix,
    },
}

/// A light sampled for next-event estimation.
pub(super) struct DirectSample<const K: usize> {
    /// The light's sample: direction, radiance, distance, density.
    pub ls: LightSample<K>,
    /// The density of the light point: the light's choice times its own
    /// sampling density.
    pub pdf: f32,
    /// Where it was sampled from, and the normal whose side the shadow
    /// ray leaves on (the light's direction in a medium).
    p: Vec3,
    n: Vec3,
}

impl<const K: usize> DirectSample<K> {
    /// The ray that tests whether the sampled point is seen: made only
    /// once the scattering towards it is known not to be zero.
    pub fn ray(&self, unit: f32) -> Ray {
        shadow_ray(self.p, self.n, &self.ls, unit)
    }
}

impl Renderer<'_> {
    /// A point of light `i`, chosen with probability `p_choice`, sampled
    /// towards `p` on wavelengths `wl` (`u`: the light's three numbers),
    /// and the ray from `p` that tests it: it leaves on the side of `n`
    /// the light is on, or along the light's direction where there is no
    /// surface (`None`: a point in a medium). `None` when the light gives
    /// nothing there.
    #[inline]
    pub(super) fn sample_direct<const K: usize>(
        &self,
        i: usize,
        p_choice: f32,
        wl: &SampledWavelengths<K>,
        p: Vec3,
        n: Option<Vec3>,
        [u_select, u0, u1]: [f32; 3],
    ) -> Option<DirectSample<K>> {
        let light = &self.scene.lights[i];
        let ls = light.sample_li(&self.extent(), wl, p, u_select, [u0, u1])?;
        if ls.pdf.is_nan() || ls.pdf <= 0.0 || ls.radiance.is_zero() {
            return None;
        }
        let pdf = p_choice * ls.pdf;
        let n = n.unwrap_or(ls.wi);
        Some(DirectSample { ls, pdf, p, n })
    }

    /// Whether shadow ray `ray` reaches its end in clear air; counts it in
    /// `rays`.
    #[inline]
    pub(super) fn visible(&self, ray: &Ray, rays: &mut u64) -> bool {
        *rays += 1;
        !self.scene.geometry.occluded(ray)
    }

    /// The fraction of light on wavelengths `now` that travels along
    /// shadow ray `ray` as `crossing` says: 1 or 0 in clear air, else
    /// [`Self::through_media`].
    pub(super) fn transmittance<const K: usize>(
        &self,
        ray: Ray,
        crossing: Crossing<'_>,
        now: &SampledWavelengths<K>,
        rays: &mut u64,
    ) -> SampledSpectrum<K> {
        match crossing {
            Crossing::Clear => {
                SampledSpectrum::splat(if self.visible(&ray, rays) { 1.0 } else { 0.0 })
            }
            Crossing::Media { medium, rng } => self.through_media(ray, medium, now, rng, rays),
        }
    }

    /// The fraction of light on wavelengths `now` that travels along
    /// shadow ray `ray`, which starts in `medium`: the media's
    /// transmittance (estimated with `rng`), times what null surfaces on
    /// the way let through; 0 when anything else is in the way. Counts the
    /// segments it traces in `rays`.
    pub(super) fn through_media<const K: usize>(
        &self,
        ray: Ray,
        mut medium: Option<u32>,
        now: &SampledWavelengths<K>,
        rng: &mut SplitMix,
        rays: &mut u64,
    ) -> SampledSpectrum<K> {
        let scene = self.scene;
        let geometry = &scene.geometry;
        let end = ray.o + ray.d * ray.t_max;
        let finite = ray.t_max.is_finite();
        let mut ray = ray;
        let mut tr = SampledSpectrum::splat(1.0);
        loop {
            *rays += 1;
            let hit = geometry.intersect(&ray);
            if let Some(m) = medium {
                let t = hit.as_ref().map_or(ray.t_max, |h| h.t);
                tr *= scene.media[m as usize].transmittance(&ray, t, now, rng);
                if tr.is_zero() {
                    return tr;
                }
            }
            let Some(hit) = hit else {
                return tr;
            };
            let bsdf = &scene.materials[scene.shape_material[hit.shape as usize] as usize];
            if !bsdf.may_pass() {
                return SampledSpectrum::splat(0.0);
            }
            let surface = geometry.surface(&hit, &ray);
            let ng = surface.n_geometric;
            let (frame, at) = ShadingPoint::at(
                surface.tex(&hit),
                surface.n_shading,
                ng,
                surface.dpdu,
                surface.dpdv,
            );
            let cos = frame.to_local(ray.d).z.abs();
            tr *= bsdf.null_transmission(now, at.tex(), cos);
            if tr.is_zero() {
                return tr;
            }
            if let Some(sides) = self.shape_media(hit.shape) {
                medium = sides.target(ray.d, ng);
            }
            let d = ray.d;
            ray = spawn(surface.p, ng, d, geometry.offset_unit());
            if finite {
                let left = (end - ray.o).dot(d);
                if left <= 0.0 {
                    return tr;
                }
                ray.t_max = left;
            }
        }
    }
}

/// The power heuristic's weight of a strategy with density `a` against `b`.
#[inline]
pub(super) fn power_heuristic(a: f32, b: f32) -> f32 {
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
/// light's own surface before its end and count as shadowed. A light
/// point at the offset origin itself gives an empty ray along the light's
/// direction: nothing lies between.
pub(super) fn shadow_ray<const K: usize>(p: Vec3, n: Vec3, ls: &LightSample<K>, unit: f32) -> Ray {
    let mut ray = spawn(p, n, ls.wi, unit);
    if ls.distance.is_finite() {
        let to = p + ls.wi * ls.distance;
        let d = to - ray.o;
        let dist = d.length();
        if dist > 0.0 {
            ray.d = d / dist;
            ray.t_max = dist * (1.0 - SHADOW_EPSILON);
        } else {
            // A point as close to the light as its offset (in fog, a
            // scattering point a tenth of a millimetre from a lamp): d / 0
            // would be a NaN direction, which no query can trace.
            ray.t_max = 0.0;
        }
    }
    ray
}

/// Relative margin a shadow ray stops short of the light's surface.
const SHADOW_EPSILON: f32 = 1e-4;

#[cfg(test)]
mod tests {
    use super::*;

    /// A light sample from `p` along `wi` at `distance` (what `shadow_ray`
    /// reads of it).
    fn sample(wi: Vec3, distance: f32) -> LightSample<4> {
        LightSample {
            wi,
            distance,
            radiance: SampledSpectrum::splat(1.0),
            pdf: 1.0,
            delta: false,
            n: -wi,
        }
    }

    /// The light's point is the offset origin itself: the shadow ray is an
    /// empty segment along the light's direction, not a NaN direction
    /// (which sent the BVH walk round its root until the stack overflowed:
    /// the foggy street at 320×180, seed 99, past 704 spp).
    #[test]
    fn a_light_point_at_the_offset_origin_gives_an_empty_shadow_ray() {
        // In a medium (n = wi), as at a scattering point a hair from a
        // lamp. First the foggy street's: a point 0.12 mm from a sodium
        // globe, whose 256-ULP offset (scene unit 1) lands on the sampled
        // point in every coordinate. Then one by construction: z = 1 moves
        // by 256 ULPs, 2⁻¹⁵, and the light is that far along +z.
        let cases = [
            (
                Vec3::new(-4.06667, 6.565697, -7.9934573),
                Vec3::new(0.78239095, 0.348164, -0.51637805),
                0.0001218923,
            ),
            (
                Vec3::new(0.0, 0.0, 1.0),
                Vec3::new(0.0, 0.0, 1.0),
                2f32.powi(-15),
            ),
        ];
        for (p, wi, distance) in cases {
            let ls = sample(wi, distance);
            assert_eq!(
                offset_ray_origin(p, wi, 1.0),
                p + wi * distance,
                "the case must put the light at the offset origin"
            );
            let ray = shadow_ray(p, wi, &ls, 1.0);
            assert!(ray.o.is_finite() && ray.d.is_finite(), "{ray:?}");
            assert_eq!(ray.d, wi);
            assert_eq!(ray.t_max, 0.0);
        }
    }

    /// A light point beyond the offset origin: the ray runs from the
    /// offset origin towards it and stops just short.
    #[test]
    fn a_shadow_ray_stops_just_short_of_the_light_point() {
        let (p, wi) = (Vec3::new(0.0, 0.0, 1.0), Vec3::new(0.0, 0.0, 1.0));
        let ray = shadow_ray(p, wi, &sample(wi, 0.5), 1.0);
        assert_eq!(ray.d, wi);
        let end = ray.o + ray.d * ray.t_max;
        assert!(end.z < 1.5 && end.z > 1.5 - 1e-3, "{end:?}");
    }
}

//! Next-event estimation's shared pieces, used by every integrator: a
//! light sampled towards a point with the ray that tests whether it is
//! seen (`Renderer::sample_direct`), the rays leaving a surface, and the
//! power heuristic that weighs light sampling against the path's own
//! direction. Each integrator chooses the light its own way (the path
//! tracers by power over squared distance, `light_choice`; the
//! bidirectional tracer by the cluster, `bdpt/clusters`), evaluates its
//! scattering (BSDF or phase function) and carries the shadow ray through
//! its media.

use crate::light::LightSample;
use crate::math::{offset_ray_origin, Ray, Vec3};

use super::Renderer;

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
        wl: &scotopia_color::SampledWavelengths<K>,
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

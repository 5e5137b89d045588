//! A nested BSDF seen through a perturbed shading frame, as Mitsuba 3's
//! `normalmap` and `bumpmap` evaluate theirs: directions move into the
//! new frame, a direction on different sides of the old and the new
//! normal scatters nothing, and the shadowing term of Estevez et al. 2019
//! ("A Microfacet-Based Shadowing Function to Solve the Bump Terminator
//! Problem", Ray Tracing Gems ch. 12) softens the terminator.
//!
//! The new normal is mirrored towards the viewer where it faces away
//! (`flip_invalid_normals`): the frame depends on the camera-side
//! direction — `wi` for radiance, `wo` for importance — so that the
//! bidirectional tracer reads the same BSDF as the path tracer. Sampling
//! and `pdf` take the frame of their first direction, as their densities
//! are used; an importance sample whose direction would see the other
//! frame is weighted by eval/pdf.

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::{Bsdf, BsdfSample, ShadingPoint, Transport};
use crate::math::{Frame, Vec3};

/// The perturbed frame in the coordinates of the original one.
#[derive(Debug, Clone, Copy)]
pub(super) struct Perturbation {
    pub frame: Frame,
    /// Apply the shadowing term.
    pub shadowing: bool,
}

/// tan²θ of unit `w` in the frame (∞ in the tangent plane).
#[inline]
fn tan2(w: Vec3) -> f32 {
    let c2 = w.z * w.z;
    (1.0 - c2).max(0.0) / c2
}

/// Estevez et al. 2019, eq. 3–4: G = 2 / (1 + √(1 + α² tan²θ_w)) with
/// α² = min(⅛ tan²θ_n, 1), for the perturbed normal `n` and the
/// direction `w` towards the light, both in the original frame.
#[inline]
fn shadow_terminator(n: Vec3, w: Vec3) -> f32 {
    let alpha2 = (0.125 * tan2(n)).min(1.0);
    let t = tan2(w);
    if t.is_infinite() {
        return if alpha2 > 0.0 { 0.0 } else { 1.0 };
    }
    2.0 / (1.0 + (1.0 + alpha2 * t).sqrt())
}

/// The frame around `n` (in the original frame's coordinates, any
/// length) with its x axis along `tangent`'s part perpendicular to it;
/// the original frame itself when `n` is zero or not finite.
pub(super) fn frame_around(n: Vec3, tangent: Vec3) -> Frame {
    let len2 = n.length_squared();
    if !(len2 > 0.0 && len2.is_finite()) {
        return Frame {
            s: Vec3::new(1.0, 0.0, 0.0),
            t: Vec3::new(0.0, 1.0, 0.0),
            n: Vec3::new(0.0, 0.0, 1.0),
        };
    }
    Frame::from_normal_tangent(n / len2.sqrt(), tangent)
}

/// Mirrors a perturbed normal to the side `wi` sees (Mitsuba's
/// `flip_invalid_normals`, after Schüssler et al. 2017).
#[inline]
pub(super) fn flip_towards(n: Vec3, wi: Vec3) -> Vec3 {
    if wi.z * wi.dot(n) <= 0.0 {
        Vec3::new(-n.x, -n.y, n.z)
    } else {
        n
    }
}

/// A BSDF that perturbs its inner BSDF's shading frame (normal and bump
/// maps): the frame for a direction and the inner BSDF are all it gives;
/// eval, pdf and sample follow from them.
pub(super) trait Perturbs {
    /// The perturbed frame seen from direction `w` (local coordinates).
    fn perturbation(&self, at: ShadingPoint, w: Vec3) -> Perturbation;
    fn inner(&self) -> &Bsdf;

    fn eval<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        at: ShadingPoint,
        wi: Vec3,
        wo: Vec3,
        mode: Transport,
    ) -> SampledSpectrum<K> {
        eval(
            |w| self.perturbation(at, w),
            self.inner(),
            wl,
            at,
            wi,
            wo,
            mode,
        )
    }

    fn pdf<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        at: ShadingPoint,
        wi: Vec3,
        wo: Vec3,
    ) -> f32 {
        pdf(|w| self.perturbation(at, w), self.inner(), wl, at, wi, wo)
    }

    #[allow(clippy::too_many_arguments)]
    fn sample<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        at: ShadingPoint,
        wi: Vec3,
        u_lobe: f32,
        u: [f32; 2],
        mode: Transport,
    ) -> Option<BsdfSample<K>> {
        sample(
            |w| self.perturbation(at, w),
            self.inner(),
            wl,
            at,
            wi,
            u_lobe,
            u,
            mode,
        )
    }
}

/// eval with the frame `frame_for` gives for the camera-side direction.
#[allow(clippy::too_many_arguments)]
pub(super) fn eval<const K: usize>(
    frame_for: impl Fn(Vec3) -> Perturbation,
    inner: &Bsdf,
    wl: &SampledWavelengths<K>,
    at: ShadingPoint,
    wi: Vec3,
    wo: Vec3,
    mode: Transport,
) -> SampledSpectrum<K> {
    let camera_side = match mode {
        Transport::Radiance => wi,
        Transport::Importance => wo,
    };
    frame_for(camera_side).eval(inner, wl, at, wi, wo, mode)
}

/// The density of sampling `wo` from `wi` (in `wi`'s frame).
pub(super) fn pdf<const K: usize>(
    frame_for: impl Fn(Vec3) -> Perturbation,
    inner: &Bsdf,
    wl: &SampledWavelengths<K>,
    at: ShadingPoint,
    wi: Vec3,
    wo: Vec3,
) -> f32 {
    frame_for(wi).pdf(inner, wl, at, wi, wo)
}

/// A sample in `wi`'s frame, weighted by eval/pdf.
#[allow(clippy::too_many_arguments)]
pub(super) fn sample<const K: usize>(
    frame_for: impl Fn(Vec3) -> Perturbation,
    inner: &Bsdf,
    wl: &SampledWavelengths<K>,
    at: ShadingPoint,
    wi: Vec3,
    u_lobe: f32,
    u: [f32; 2],
    mode: Transport,
) -> Option<BsdfSample<K>> {
    let p = frame_for(wi);
    let mut s = p.sample(inner, wl, at, wi, u_lobe, u, mode)?;
    if mode == Transport::Importance && !s.delta {
        // The value is the camera side's (`wo`'s) frame's.
        let q = frame_for(s.wo);
        if q.frame != p.frame {
            s.weight = q.eval(inner, wl, at, wi, s.wo, mode) / s.pdf;
        }
    }
    Some(s)
}

impl Perturbation {
    /// The shading point as the nested BSDF sees it.
    #[inline]
    fn inner_point(&self, at: ShadingPoint) -> ShadingPoint {
        let f = &self.frame;
        ShadingPoint {
            dpdu: f.to_local(at.dpdu),
            dpdv: f.to_local(at.dpdv),
            ng: f.to_local(at.ng),
            ..at
        }
    }

    /// What the nested value is multiplied by for the pair (wi, wo) in
    /// the original frame: the shadowing term of the direction towards
    /// the light and, for importance, the ratio of Veach's (1997, eq.
    /// 5.19) shading-normal factors of the new normal to the old, which
    /// the tracer applies with the unperturbed one.
    #[inline]
    fn factor(&self, wi: Vec3, wo: Vec3, mode: Transport) -> f32 {
        let n = self.frame.n;
        let to_light = match mode {
            Transport::Radiance => wo,
            Transport::Importance => wi,
        };
        let shadow = if self.shadowing {
            shadow_terminator(n, to_light)
        } else {
            1.0
        };
        match mode {
            Transport::Radiance => shadow,
            Transport::Importance => {
                let den = wo.dot(n).abs() * wi.z.abs();
                if den > 0.0 {
                    shadow * wi.dot(n).abs() * wo.z.abs() / den
                } else {
                    0.0
                }
            }
        }
    }

    pub fn eval<const K: usize>(
        &self,
        inner: &Bsdf,
        wl: &SampledWavelengths<K>,
        at: ShadingPoint,
        wi: Vec3,
        wo: Vec3,
        mode: Transport,
    ) -> SampledSpectrum<K> {
        let (pi, po) = (self.frame.to_local(wi), self.frame.to_local(wo));
        if wo.z * po.z <= 0.0 {
            return SampledSpectrum::splat(0.0);
        }
        let f = self.factor(wi, wo, mode);
        inner.eval(wl, self.inner_point(at), pi, po, mode) * f
    }

    pub fn pdf<const K: usize>(
        &self,
        inner: &Bsdf,
        wl: &SampledWavelengths<K>,
        at: ShadingPoint,
        wi: Vec3,
        wo: Vec3,
    ) -> f32 {
        let (pi, po) = (self.frame.to_local(wi), self.frame.to_local(wo));
        if wo.z * po.z <= 0.0 {
            return 0.0;
        }
        inner.pdf_at(wl, self.inner_point(at), pi, po)
    }

    #[allow(clippy::too_many_arguments)]
    pub fn sample<const K: usize>(
        &self,
        inner: &Bsdf,
        wl: &SampledWavelengths<K>,
        at: ShadingPoint,
        wi: Vec3,
        u_lobe: f32,
        u: [f32; 2],
        mode: Transport,
    ) -> Option<BsdfSample<K>> {
        let pi = self.frame.to_local(wi);
        let mut s = inner.sample(wl, self.inner_point(at), pi, u_lobe, u, mode)?;
        let wo = self.frame.to_world(s.wo);
        if s.wo.z * wo.z <= 0.0 {
            return None;
        }
        s.weight *= self.factor(wi, wo, mode);
        s.wo = wo;
        Some(s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_shadowing_term_is_one_without_perturbation_and_falls_towards_grazing() {
        let up = Vec3::new(0.0, 0.0, 1.0);
        let w = Vec3::new(0.6, 0.0, 0.8);
        assert_eq!(shadow_terminator(up, w), 1.0);
        let tilted = Vec3::new(0.5, 0.0, 0.866).normalize();
        let g_steep = shadow_terminator(tilted, up);
        let g_mid = shadow_terminator(tilted, w);
        let g_grazing = shadow_terminator(tilted, Vec3::new(0.999, 0.0, 0.0447).normalize());
        assert_eq!(g_steep, 1.0);
        assert!(1.0 > g_mid && g_mid > g_grazing && g_grazing > 0.0);
        // Eq. 3–4 by hand: α² = tan²30°/8 = 1/24, tan²θ_w = 0.5625.
        let want = 2.0 / (1.0 + (1.0 + 0.5625 / 24.0f32).sqrt());
        assert!((g_mid - want).abs() < 1e-5, "{g_mid} vs {want}");
    }

    #[test]
    fn flipping_mirrors_the_tangential_part_only() {
        let n = Vec3::new(0.6, 0.0, 0.8);
        let wi = Vec3::new(-0.95, 0.0, 0.312).normalize();
        assert_eq!(flip_towards(n, wi), Vec3::new(-0.6, 0.0, 0.8));
        assert_eq!(flip_towards(n, Vec3::new(0.0, 0.0, 1.0)), n);
    }
}

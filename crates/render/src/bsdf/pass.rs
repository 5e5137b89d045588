//! What a surface lets through unchanged in direction: the null lobes
//! that Mitsuba's volume path tracers treat as no scattering at all
//! (`eval_null_transmission`). Shadow rays through participating media
//! cross such surfaces, weighted by this, instead of stopping there.

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::Bsdf;
use crate::texture::TexPoint;

impl Bsdf {
    /// Whether any light can pass straight through (a cheap test before
    /// the surface point is worked out).
    pub fn may_pass(&self) -> bool {
        match self {
            Bsdf::Null(_) | Bsdf::ThinDielectric(_) | Bsdf::Mask(_) => true,
            Bsdf::Blend(b) => b.first.may_pass() || b.second.may_pass(),
            Bsdf::TwoSided(inner) => inner.may_pass(),
            Bsdf::NormalMap(b) => b.inner.may_pass(),
            Bsdf::BumpMap(b) => b.inner.may_pass(),
            _ => false,
        }
    }

    /// The fraction passing straight through at `uv`, for a direction at
    /// |cos θ| = `cos` to the surface.
    pub fn null_transmission<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: TexPoint,
        cos: f32,
    ) -> SampledSpectrum<K> {
        match self {
            Bsdf::Null(b) => b.transmittance.eval(wl, uv) * b.scale,
            Bsdf::ThinDielectric(b) => b.transmission(wl, uv, cos),
            Bsdf::Mask(b) => {
                let o = b.opacity(uv);
                b.inner.null_transmission(wl, uv, cos) * o + SampledSpectrum::splat(1.0 - o)
            }
            Bsdf::Blend(b) => {
                let w = b.weight(uv);
                b.first.null_transmission(wl, uv, cos) * (1.0 - w)
                    + b.second.null_transmission(wl, uv, cos) * w
            }
            Bsdf::TwoSided(inner) => inner.null_transmission(wl, uv, cos),
            Bsdf::NormalMap(b) => b.inner.null_transmission(wl, uv, cos),
            Bsdf::BumpMap(b) => b.inner.null_transmission(wl, uv, cos),
            _ => SampledSpectrum::splat(0.0),
        }
    }
}

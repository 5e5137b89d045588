//! Mitsuba 3's `mask`: the nested BSDF where the surface is there (with
//! probability `opacity`), the null lobe elsewhere — light passes
//! straight through with probability 1 − opacity (src/bsdfs/mask.cpp).
//! eval and pdf are the nested ones times the opacity; a sample is the
//! nested one (its weight unchanged, its pdf times the opacity) or the
//! pass-through, a delta event of pdf 1 − opacity.

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::null::pass_through;
use super::{Bsdf, BsdfSample, ShadingPoint, Transport};
use crate::math::Vec3;
use crate::texture::{FloatTexture, TexPoint};

#[derive(Debug, Clone, PartialEq)]
pub struct Mask {
    /// Clamped to [0, 1] where it is looked up.
    pub opacity: FloatTexture,
    pub inner: Bsdf,
}

impl Mask {
    #[inline]
    pub(super) fn opacity(&self, uv: TexPoint) -> f32 {
        self.opacity.eval_fraction(uv)
    }

    pub fn eval<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        at: ShadingPoint,
        wi: Vec3,
        wo: Vec3,
        mode: Transport,
    ) -> SampledSpectrum<K> {
        self.inner.eval(wl, at, wi, wo, mode) * self.opacity(at.tex())
    }

    pub fn pdf<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        at: ShadingPoint,
        wi: Vec3,
        wo: Vec3,
    ) -> f32 {
        self.inner.pdf_at(wl, at, wi, wo) * self.opacity(at.tex())
    }

    pub fn sample<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        at: ShadingPoint,
        wi: Vec3,
        u_lobe: f32,
        u: [f32; 2],
        mode: Transport,
    ) -> Option<BsdfSample<K>> {
        let opacity = self.opacity(at.tex());
        if u_lobe < opacity {
            // The surface: the lobe number is reused, rescaled to [0, 1).
            let mut s = self.inner.sample(wl, at, wi, u_lobe / opacity, u, mode)?;
            s.pdf *= opacity;
            Some(s)
        } else {
            Some(pass_through(wi, 1.0 - opacity))
        }
    }
}

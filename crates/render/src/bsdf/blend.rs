//! Mitsuba 3's `blendbsdf`: (1 − w)·first + w·second with `weight` w in
//! [0, 1] (src/bsdfs/blendbsdf.cpp). Sampling picks one BSDF by its
//! weight; a direction from a non-delta lobe is then weighted by the
//! mixture of both densities (one-sample MIS), so eval/pdf holds for the
//! blend as a whole. A delta sample keeps the weight of the BSDF that
//! drew it: the other cannot produce its direction.

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::{Bsdf, BsdfSample, ShadingPoint, Transport};
use crate::math::Vec3;
use crate::texture::{FloatTexture, TexPoint};

#[derive(Debug, Clone, PartialEq)]
pub struct Blend {
    /// The share of `second`, clamped to [0, 1] where it is looked up.
    pub weight: FloatTexture,
    pub first: Bsdf,
    pub second: Bsdf,
}

impl Blend {
    #[inline]
    pub(super) fn weight(&self, uv: TexPoint) -> f32 {
        self.weight.eval_fraction(uv)
    }

    pub fn eval<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        at: ShadingPoint,
        wi: Vec3,
        wo: Vec3,
        mode: Transport,
    ) -> SampledSpectrum<K> {
        let w = self.weight(at.tex());
        self.first.eval(wl, at, wi, wo, mode) * (1.0 - w)
            + self.second.eval(wl, at, wi, wo, mode) * w
    }

    pub fn pdf<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        at: ShadingPoint,
        wi: Vec3,
        wo: Vec3,
    ) -> f32 {
        let w = self.weight(at.tex());
        self.first.pdf_at(wl, at, wi, wo) * (1.0 - w) + self.second.pdf_at(wl, at, wi, wo) * w
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
        let w = self.weight(at.tex());
        // Mitsuba's rule: u ≤ w picks the second BSDF.
        let (chosen, other, p_chosen, u_lobe) = if u_lobe <= w && w > 0.0 {
            (&self.second, &self.first, w, u_lobe / w)
        } else {
            (&self.first, &self.second, 1.0 - w, (u_lobe - w) / (1.0 - w))
        };
        let mut s = chosen.sample(wl, at, wi, u_lobe.clamp(0.0, 1.0 - f32::EPSILON), u, mode)?;
        if s.delta {
            s.pdf *= p_chosen;
            return Some(s);
        }
        let f_chosen = s.weight * s.pdf;
        let f_other = other.eval(wl, at, wi, s.wo, mode);
        let pdf = p_chosen * s.pdf + (1.0 - p_chosen) * other.pdf_at(wl, at, wi, s.wo);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        s.weight = (f_chosen * p_chosen + f_other * (1.0 - p_chosen)) / pdf;
        s.pdf = pdf;
        Some(s)
    }
}

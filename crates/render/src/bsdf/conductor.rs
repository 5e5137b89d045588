//! Conductors, smooth (a mirror) or rough (Beckmann or GGX microfacets,
//! possibly anisotropic), with the exact Fresnel reflectance of a complex
//! index η + iκ per wavelength.

use scotopia_color::{SampledSpectrum, SampledWavelengths, Spectrum};

use super::{fresnel_conductor, reflect, reflect_about, BsdfSample, Roughness};
use crate::math::Vec3;
use crate::texture::{TexPoint, Texture};

#[derive(Debug, Clone, PartialEq)]
pub struct Conductor {
    /// Real part of the index, relative to the outside medium.
    pub eta: Spectrum,
    /// Imaginary part (absorption).
    pub k: Spectrum,
    /// A scale on the reflectance (Mitsuba's `specular_reflectance`).
    pub specular_reflectance: Texture,
    /// The microfacet roughness; `None` is a perfect mirror.
    pub distribution: Option<Roughness>,
}

impl Conductor {
    fn fresnel<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: TexPoint,
        cos_i: f32,
    ) -> SampledSpectrum<K> {
        let (eta, k) = (self.eta.sample(wl), self.k.sample(wl));
        let f = SampledSpectrum::from_fn(|i| fresnel_conductor(cos_i, eta[i], k[i]));
        f * self.specular_reflectance.eval(wl, uv)
    }

    /// Whether this is a perfect mirror (a delta lobe).
    pub fn is_smooth(&self) -> bool {
        self.distribution.is_none()
    }

    pub fn eval<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: TexPoint,
        wi: Vec3,
        wo: Vec3,
    ) -> SampledSpectrum<K> {
        let Some(roughness) = &self.distribution else {
            return SampledSpectrum::splat(0.0);
        };
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return SampledSpectrum::splat(0.0);
        }
        let dist = roughness.at(uv);
        let m = (wi + wo).normalize();
        // f·cos θ_o = F D G / (4 cos θ_i).
        let v = dist.d(m) * dist.g(wi, wo, m) / (4.0 * wi.z);
        self.fresnel(wl, uv, wi.dot(m)) * v
    }

    pub fn pdf(&self, uv: TexPoint, wi: Vec3, wo: Vec3) -> f32 {
        let Some(roughness) = &self.distribution else {
            return 0.0;
        };
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let dist = roughness.at(uv);
        let m = (wi + wo).normalize();
        if wo.dot(m) <= 0.0 {
            return 0.0;
        }
        // Visible-normal density times the reflection Jacobian 1/(4 wo·m).
        dist.pdf_visible(wi, m) / (4.0 * wo.dot(m))
    }

    pub fn sample<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: TexPoint,
        wi: Vec3,
        u: [f32; 2],
    ) -> Option<BsdfSample<K>> {
        if wi.z <= 0.0 {
            return None;
        }
        let Some(roughness) = &self.distribution else {
            return Some(BsdfSample {
                wo: reflect(wi),
                weight: self.fresnel(wl, uv, wi.z),
                pdf: 1.0,
                delta: true,
                collapse: false,
            });
        };
        let dist = roughness.at(uv);
        let m = dist.sample_visible(wi, u);
        let wo = reflect_about(wi, m);
        if wo.z <= 0.0 {
            return None;
        }
        let pdf = dist.pdf_visible(wi, m) / (4.0 * wo.dot(m));
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        // eval/pdf = F G₁(wo) for visible-normal sampling (Heitz & d'Eon
        // 2014, eq. 19).
        Some(BsdfSample {
            wo,
            weight: self.fresnel(wl, uv, wi.dot(m)) * dist.reflection_weight(wi, wo, m),
            pdf,
            delta: false,
            collapse: false,
        })
    }
}

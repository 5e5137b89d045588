//! Conductors, smooth (a mirror) or rough (GGX microfacets), with the
//! exact Fresnel reflectance of a complex index η + iκ per wavelength.

use scotopia_color::{SampledSpectrum, SampledWavelengths, Spectrum};

use super::{fresnel_conductor, reflect, reflect_about, BsdfSample, Ggx};
use crate::math::Vec3;
use crate::texture::Texture;

#[derive(Debug, Clone, PartialEq)]
pub struct Conductor {
    /// Real part of the index, relative to the outside medium.
    pub eta: Spectrum,
    /// Imaginary part (absorption).
    pub k: Spectrum,
    /// A scale on the reflectance (Mitsuba's `specular_reflectance`).
    pub specular_reflectance: Texture,
    /// GGX roughness; 0 is a perfect mirror.
    pub alpha: f32,
}

impl Conductor {
    fn fresnel<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: [f32; 2],
        cos_i: f32,
    ) -> SampledSpectrum<K> {
        let (eta, k) = (self.eta.sample(wl), self.k.sample(wl));
        let f = SampledSpectrum::from_fn(|i| fresnel_conductor(cos_i, eta[i], k[i]));
        f * self.specular_reflectance.eval(wl, uv)
    }

    fn ggx(&self) -> Ggx {
        Ggx { alpha: self.alpha }
    }

    pub fn eval<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: [f32; 2],
        wi: Vec3,
        wo: Vec3,
    ) -> SampledSpectrum<K> {
        if self.alpha == 0.0 || wi.z <= 0.0 || wo.z <= 0.0 {
            return SampledSpectrum::splat(0.0);
        }
        let m = (wi + wo).normalize();
        let ggx = self.ggx();
        // f·cos θ_o = F D G / (4 cos θ_i).
        let v = ggx.d(m) * ggx.g(wi, wo, m) / (4.0 * wi.z);
        self.fresnel(wl, uv, wi.dot(m)) * v
    }

    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if self.alpha == 0.0 || wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let m = (wi + wo).normalize();
        // Visible-normal density times the reflection Jacobian 1/(4 wo·m).
        self.ggx().pdf_visible(wi, m) / (4.0 * wo.dot(m))
    }

    pub fn sample<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: [f32; 2],
        wi: Vec3,
        u: [f32; 2],
    ) -> Option<BsdfSample<K>> {
        if wi.z <= 0.0 {
            return None;
        }
        if self.alpha == 0.0 {
            return Some(BsdfSample {
                wo: reflect(wi),
                weight: self.fresnel(wl, uv, wi.z),
                pdf: 1.0,
                delta: true,
                collapse: false,
            });
        }
        let ggx = self.ggx();
        let m = ggx.sample_visible(wi, u);
        let wo = reflect_about(wi, m);
        if wo.z <= 0.0 {
            return None;
        }
        let pdf = ggx.pdf_visible(wi, m) / (4.0 * wo.dot(m));
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        // eval/pdf = F G₁(wo) for visible-normal sampling (Heitz 2018, eq. 19).
        Some(BsdfSample {
            wo,
            weight: self.fresnel(wl, uv, wi.dot(m)) * ggx.g1(wo, m),
            pdf,
            delta: false,
            collapse: false,
        })
    }
}

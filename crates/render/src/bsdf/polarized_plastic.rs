//! Mitsuba 3's `pplastic` (src/bsdfs/pplastic.cpp) as its unpolarised
//! variants render it: a glossy microfacet reflection
//! ρ_s F(wi·h) D G / (4 cos θ_i) plus a diffuse term
//! ρ_d (1 − F(cos θ_i)) (1 − F(cos θ_o)) cos θ_o / π — two refractions
//! through the interface, without the internal reflections that
//! `roughplastic` sums. Lobes are chosen by the mean reflectances, as
//! Mitsuba does (its `specular_sampling_weight`).

use std::f32::consts::FRAC_1_PI;

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::plastic::{glossy_or_diffuse_pdf, sample_glossy_or_diffuse};
use super::{fresnel_dielectric, BsdfSample, Roughness};
use crate::math::Vec3;
use crate::texture::{TexPoint, Texture};

#[derive(Debug, Clone, PartialEq)]
pub struct PolarizedPlastic {
    pub diffuse_reflectance: Texture,
    pub specular_reflectance: Texture,
    /// η_interior / η_exterior.
    pub eta: f32,
    /// The coating's microfacets (Mitsuba's `distribution`, `alpha`,
    /// which may be textures).
    pub distribution: Roughness,
    /// Probability of sampling the glossy lobe.
    specular_weight: f32,
}

impl PolarizedPlastic {
    pub fn new(
        diffuse_reflectance: Texture,
        specular_reflectance: Texture,
        eta: f32,
        distribution: Roughness,
    ) -> Self {
        let (d, s) = (diffuse_reflectance.mean(), specular_reflectance.mean());
        let specular_weight = if d + s > 0.0 { s / (d + s) } else { 0.5 };
        Self {
            diffuse_reflectance,
            specular_reflectance,
            eta,
            distribution,
            specular_weight,
        }
    }

    pub fn eval<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: TexPoint,
        wi: Vec3,
        wo: Vec3,
    ) -> SampledSpectrum<K> {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return SampledSpectrum::splat(0.0);
        }
        let d = &self.distribution.at(uv);
        let h = (wi + wo).normalize();
        let glossy =
            fresnel_dielectric(wi.dot(h), self.eta).0 * d.d(h) * d.g(wi, wo, h) / (4.0 * wi.z);
        let through = (1.0 - fresnel_dielectric(wi.z, self.eta).0)
            * (1.0 - fresnel_dielectric(wo.z, self.eta).0);
        self.specular_reflectance.eval(wl, uv) * glossy
            + self.diffuse_reflectance.eval(wl, uv) * (through * FRAC_1_PI * wo.z)
    }

    pub fn pdf(&self, uv: TexPoint, wi: Vec3, wo: Vec3) -> f32 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        glossy_or_diffuse_pdf(&self.distribution.at(uv), self.specular_weight, wi, wo)
    }

    pub fn sample<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: TexPoint,
        wi: Vec3,
        u_lobe: f32,
        u: [f32; 2],
    ) -> Option<BsdfSample<K>> {
        if wi.z <= 0.0 {
            return None;
        }
        let d = self.distribution.at(uv);
        let wo = sample_glossy_or_diffuse(&d, self.specular_weight, wi, u_lobe, u);
        let pdf = self.pdf(uv, wi, wo);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wo,
            weight: self.eval(wl, uv, wi, wo) / pdf,
            pdf,
            delta: false,
            collapse: false,
        })
    }
}

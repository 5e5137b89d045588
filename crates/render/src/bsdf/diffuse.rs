//! Lambertian reflection.

use std::f32::consts::FRAC_1_PI;

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::BsdfSample;
use crate::math::Vec3;
use crate::sampling::warp::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};
use crate::texture::{TexPoint, Texture};

/// The density of cosine sampling on the side the normal points to, where
/// both directions are (diffuse surfaces, and the road's tables).
pub(super) fn upper_cosine_pdf(wi: Vec3, wo: Vec3) -> f32 {
    if wi.z <= 0.0 || wo.z <= 0.0 {
        return 0.0;
    }
    cosine_hemisphere_pdf(wo.z)
}

/// f = ρ/π on the side the normal points to.
#[derive(Debug, Clone, PartialEq)]
pub struct Diffuse {
    pub reflectance: Texture,
}

impl Diffuse {
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
        self.reflectance.eval(wl, uv) * (FRAC_1_PI * wo.z)
    }

    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        upper_cosine_pdf(wi, wo)
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
        let wo = square_to_cosine_hemisphere(u);
        let pdf = cosine_hemisphere_pdf(wo.z);
        if pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wo,
            // (ρ/π)·cos θ / (cos θ/π) = ρ.
            weight: self.reflectance.eval(wl, uv),
            pdf,
            delta: false,
            collapse: false,
        })
    }
}

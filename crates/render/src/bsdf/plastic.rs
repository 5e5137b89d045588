//! Smooth plastic (Mitsuba's `plastic`): a diffuse substrate under a smooth
//! dielectric coating. Light reflects specularly off the coating with
//! Fresnel reflectance F, or enters, scatters diffusely and leaves, losing
//! (1 − F) twice; internal reflections at the coating are summed with the
//! diffuse Fresnel reflectance F_dr of the inside (Mitsuba 3's model: Weidlich
//! & Wilkie 2007's layered approximation, linear or `nonlinear` in ρ).

use std::f32::consts::FRAC_1_PI;

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::{fresnel_dielectric, reflect, BsdfSample};
use crate::math::Vec3;
use crate::sampling::warp::square_to_cosine_hemisphere;
use crate::texture::Texture;

#[derive(Debug, Clone, PartialEq)]
pub struct Plastic {
    pub diffuse_reflectance: Texture,
    pub specular_reflectance: Texture,
    /// η_interior / η_exterior of the coating.
    pub eta: f32,
    /// Mitsuba's `nonlinear`: internal scattering darkens and saturates ρ.
    pub nonlinear: bool,
    /// F_dr of the inside of the coating (hemispherical average of F at 1/η).
    fdr_internal: f32,
    /// Share of lobe choice given to the specular lobe (by mean reflectances).
    specular_weight: f32,
}

/// The diffuse (cosine-weighted hemispherical) Fresnel reflectance
/// F_dr(η) = ∫₀¹ 2μ F(μ; η) dμ, by the midpoint rule: exact to the model, so
/// no fitted polynomial is needed.
pub fn diffuse_fresnel_reflectance(eta: f32) -> f32 {
    let n = 2048;
    let sum: f64 = (0..n)
        .map(|i| {
            let mu = (i as f64 + 0.5) / n as f64;
            2.0 * mu * fresnel_dielectric(mu as f32, eta).0 as f64
        })
        .sum();
    (sum / n as f64) as f32
}

impl Plastic {
    pub fn new(
        diffuse_reflectance: Texture,
        specular_reflectance: Texture,
        eta: f32,
        nonlinear: bool,
    ) -> Self {
        // Mean reflectances set the lobe choice.
        let (d, s) = (diffuse_reflectance.mean(), specular_reflectance.mean());
        Self {
            fdr_internal: diffuse_fresnel_reflectance(1.0 / eta),
            specular_weight: if d + s > 0.0 { s / (d + s) } else { 0.5 },
            diffuse_reflectance,
            specular_reflectance,
            eta,
            nonlinear,
        }
    }

    /// Probability of choosing the specular lobe at incidence cosine `ci`.
    fn specular_probability(&self, f_i: f32) -> f32 {
        let s = f_i * self.specular_weight;
        let d = (1.0 - f_i) * (1.0 - self.specular_weight);
        if s + d > 0.0 {
            s / (s + d)
        } else {
            0.0
        }
    }

    pub fn eval<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: [f32; 2],
        wi: Vec3,
        wo: Vec3,
    ) -> SampledSpectrum<K> {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return SampledSpectrum::splat(0.0);
        }
        let f_i = fresnel_dielectric(wi.z, self.eta).0;
        let f_o = fresnel_dielectric(wo.z, self.eta).0;
        let rho = self.diffuse_reflectance.eval(wl, uv);
        let denominator = if self.nonlinear {
            SampledSpectrum::splat(1.0) - rho * self.fdr_internal
        } else {
            SampledSpectrum::splat(1.0 - self.fdr_internal)
        };
        let scale = (1.0 - f_i) * (1.0 - f_o) * FRAC_1_PI * wo.z / (self.eta * self.eta);
        rho.safe_div(&denominator) * scale
    }

    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let p_spec = self.specular_probability(fresnel_dielectric(wi.z, self.eta).0);
        (1.0 - p_spec) * wo.z * FRAC_1_PI
    }

    pub fn sample<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: [f32; 2],
        wi: Vec3,
        u_lobe: f32,
        u: [f32; 2],
    ) -> Option<BsdfSample<K>> {
        if wi.z <= 0.0 {
            return None;
        }
        let f_i = fresnel_dielectric(wi.z, self.eta).0;
        let p_spec = self.specular_probability(f_i);
        if u_lobe < p_spec {
            return Some(BsdfSample {
                wo: reflect(wi),
                weight: self.specular_reflectance.eval(wl, uv) * (f_i / p_spec),
                pdf: p_spec,
                delta: true,
                collapse: false,
            });
        }
        let wo = square_to_cosine_hemisphere(u);
        let pdf = self.pdf(wi, wo);
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

//! Rough plastic (Mitsuba's `roughplastic`): a diffuse substrate under a
//! rough dielectric coating with GGX microfacets. The coating reflects
//! glossily, F D G / (4 cos θ_i); what it lets through, T(μ) = 1 − R(μ)
//! with R the coating's directional albedo, scatters diffusely in the
//! substrate and leaves through the coating again, losing T on the way out.
//! Internal reflections at the rough coating are summed with its
//! hemispherical internal albedo, as in Mitsuba 3's model (Weidlich &
//! Wilkie 2007's layering with a rough interface). R is tabulated once per
//! material over μ, as Mitsuba does.

use std::f32::consts::FRAC_1_PI;

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::plastic::{specular_probability, specular_weight, substrate};
use super::{fresnel_dielectric, reflect_about, BsdfSample, Ggx};
use crate::math::Vec3;
use crate::sampling::warp::square_to_cosine_hemisphere;
use crate::texture::Texture;

/// Table nodes over μ ∈ [0, 1] (Mitsuba uses 64 too).
const TABLE: usize = 64;
/// Stratified grid side for each albedo in the table.
const GRID: usize = 32;

#[derive(Debug, Clone, PartialEq)]
pub struct RoughPlastic {
    pub diffuse_reflectance: Texture,
    pub specular_reflectance: Texture,
    /// η_interior / η_exterior of the coating.
    pub eta: f32,
    /// GGX roughness of the coating.
    pub alpha: f32,
    /// Mitsuba's `nonlinear`: internal scattering darkens and saturates ρ.
    pub nonlinear: bool,
    /// T(μ) = 1 − R(μ) at μ = i / (TABLE − 1).
    external_transmittance: Box<[f32; TABLE]>,
    /// 2 ∫ R_int(μ) μ dμ with R_int the albedo from inside (index 1/η).
    internal_reflectance: f32,
    /// Share of lobe choice given to the glossy lobe (by mean reflectances).
    specular_weight: f32,
}

impl RoughPlastic {
    pub fn new(
        diffuse_reflectance: Texture,
        specular_reflectance: Texture,
        eta: f32,
        alpha: f32,
        nonlinear: bool,
    ) -> Self {
        let ggx = Ggx { alpha };
        let external_transmittance = Box::new(std::array::from_fn(|i| {
            1.0 - ggx.dielectric_albedo(i as f32 / (TABLE - 1) as f32, eta, GRID)
        }));
        // Midpoint rule in μ for the cosine-weighted hemispherical mean.
        let internal_reflectance = (0..TABLE)
            .map(|i| {
                let mu = (i as f32 + 0.5) / TABLE as f32;
                2.0 * mu * ggx.dielectric_albedo(mu, 1.0 / eta, GRID)
            })
            .sum::<f32>()
            / TABLE as f32;
        Self {
            specular_weight: specular_weight(&diffuse_reflectance, &specular_reflectance),
            diffuse_reflectance,
            specular_reflectance,
            eta,
            alpha,
            nonlinear,
            external_transmittance,
            internal_reflectance,
        }
    }

    fn ggx(&self) -> Ggx {
        Ggx { alpha: self.alpha }
    }

    /// T(μ), linearly interpolated in the table.
    fn transmittance(&self, mu: f32) -> f32 {
        let x = mu.clamp(0.0, 1.0) * (TABLE - 1) as f32;
        let i = (x as usize).min(TABLE - 2);
        let f = x - i as f32;
        let t = &self.external_transmittance;
        t[i] * (1.0 - f) + t[i + 1] * f
    }

    /// The hemispherical internal albedo of the coating.
    pub fn internal_reflectance(&self) -> f32 {
        self.internal_reflectance
    }

    /// Probability of choosing the glossy lobe at incidence cosine `ci`.
    fn specular_probability(&self, ci: f32) -> f32 {
        specular_probability(1.0 - self.transmittance(ci), self.specular_weight)
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
        let ggx = self.ggx();
        let h = (wi + wo).normalize();
        let glossy =
            fresnel_dielectric(wi.dot(h), self.eta).0 * ggx.d(h) * ggx.g(wi, wo, h) / (4.0 * wi.z);
        let rho = self.diffuse_reflectance.eval(wl, uv);
        let scale = self.transmittance(wi.z) * self.transmittance(wo.z) * FRAC_1_PI * wo.z
            / (self.eta * self.eta);
        self.specular_reflectance.eval(wl, uv) * glossy
            + substrate(rho, self.internal_reflectance, self.nonlinear) * scale
    }

    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let p_spec = self.specular_probability(wi.z);
        let h = (wi + wo).normalize();
        // Visible-normal density times the reflection Jacobian 1/(4 wo·h).
        let glossy = self.ggx().pdf_visible(wi, h) / (4.0 * wo.dot(h));
        p_spec * glossy + (1.0 - p_spec) * wo.z * FRAC_1_PI
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
        let wo = if u_lobe < self.specular_probability(wi.z) {
            reflect_about(wi, self.ggx().sample_visible(wi, u))
        } else {
            square_to_cosine_hemisphere(u)
        };
        // Both lobes can produce any direction: weight by the mixture.
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

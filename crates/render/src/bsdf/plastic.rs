//! Smooth plastic (Mitsuba's `plastic`): a diffuse substrate under a smooth
//! dielectric coating. Light reflects specularly off the coating with
//! Fresnel reflectance F, or enters, scatters diffusely and leaves, losing
//! (1 − F) twice; internal reflections at the coating are summed with the
//! diffuse Fresnel reflectance F_dr of the inside (Mitsuba 3's model: Weidlich
//! & Wilkie 2007's layered approximation, linear or `nonlinear` in ρ).

use std::f32::consts::FRAC_1_PI;

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::{fresnel_dielectric, reflect, reflect_about, BsdfSample, MicrofacetDistribution};
use crate::math::Vec3;
use crate::sampling::warp::square_to_cosine_hemisphere;
use crate::texture::{TexPoint, Texture};

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

/// The specular lobe's share of lobe choice, by the mean reflectances.
pub(super) fn specular_weight(diffuse: &Texture, specular: &Texture) -> f32 {
    let (d, s) = (diffuse.mean(), specular.mean());
    if d + s > 0.0 {
        s / (d + s)
    } else {
        0.5
    }
}

/// Probability of choosing the specular lobe when the coating reflects a
/// share `r` of the incident light.
pub(super) fn specular_probability(r: f32, weight: f32) -> f32 {
    let s = r * weight;
    let d = (1.0 - r) * (1.0 - weight);
    if s + d > 0.0 {
        s / (s + d)
    } else {
        0.0
    }
}

/// The substrate's albedo ρ after the coating's internal reflections
/// (albedo `internal`): ρ / (1 − F_int), or ρ / (1 − ρ F_int) when
/// `nonlinear`.
pub(super) fn substrate<const K: usize>(
    rho: SampledSpectrum<K>,
    internal: f32,
    nonlinear: bool,
) -> SampledSpectrum<K> {
    let denominator = if nonlinear {
        SampledSpectrum::splat(1.0) - rho * internal
    } else {
        SampledSpectrum::splat(1.0 - internal)
    };
    rho.safe_div(&denominator)
}

impl Plastic {
    pub fn new(
        diffuse_reflectance: Texture,
        specular_reflectance: Texture,
        eta: f32,
        nonlinear: bool,
    ) -> Self {
        Self {
            fdr_internal: diffuse_fresnel_reflectance(1.0 / eta),
            specular_weight: specular_weight(&diffuse_reflectance, &specular_reflectance),
            diffuse_reflectance,
            specular_reflectance,
            eta,
            nonlinear,
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
        let f_i = fresnel_dielectric(wi.z, self.eta).0;
        let f_o = fresnel_dielectric(wo.z, self.eta).0;
        let rho = self.diffuse_reflectance.eval(wl, uv);
        let scale = (1.0 - f_i) * (1.0 - f_o) * FRAC_1_PI * wo.z / (self.eta * self.eta);
        substrate(rho, self.fdr_internal, self.nonlinear) * scale
    }

    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        let p_spec =
            specular_probability(fresnel_dielectric(wi.z, self.eta).0, self.specular_weight);
        (1.0 - p_spec) * wo.z * FRAC_1_PI
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
        let f_i = fresnel_dielectric(wi.z, self.eta).0;
        let p_spec = specular_probability(f_i, self.specular_weight);
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

/// A rough coating's sampling: with probability `p_spec` a mirror direction
/// about a visible normal of `d`, else a cosine-weighted one from the
/// substrate.
pub(super) fn sample_glossy_or_diffuse(
    d: &MicrofacetDistribution,
    p_spec: f32,
    wi: Vec3,
    u_lobe: f32,
    u: [f32; 2],
) -> Vec3 {
    if u_lobe < p_spec {
        reflect_about(wi, d.sample_visible(wi, u))
    } else {
        square_to_cosine_hemisphere(u)
    }
}

/// The density of `sample_glossy_or_diffuse` (both lobes reach every
/// direction above the surface).
pub(super) fn glossy_or_diffuse_pdf(
    d: &MicrofacetDistribution,
    p_spec: f32,
    wi: Vec3,
    wo: Vec3,
) -> f32 {
    let h = (wi + wo).normalize();
    // Visible-normal density times the reflection Jacobian 1/(4 wo·h).
    let glossy = d.pdf_visible(wi, h) / (4.0 * wo.dot(h));
    p_spec * glossy + (1.0 - p_spec) * wo.z * FRAC_1_PI
}

//! Rough dielectric interfaces: microfacets (Beckmann or GGX, possibly
//! anisotropic) that reflect and refract
//! (Walter, Marschner, Li & Torrance 2007, "Microfacet Models for
//! Refraction through Rough Surfaces"), sampled by visible normals. A
//! dispersive index makes the refracted direction wavelength-dependent:
//! sampling refracts the first wavelength and collapses the cluster, and
//! `eval` uses each wavelength's own half-vector.

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::dielectric::Ior;
use super::{
    fresnel_dielectric, reflect_about, BsdfSample, MicrofacetDistribution, Roughness, Transport,
};
use crate::math::Vec3;
use crate::texture::{TexPoint, Texture};

#[derive(Debug, Clone, PartialEq)]
pub struct RoughDielectric {
    pub ior: Ior,
    pub distribution: Roughness,
    pub specular_reflectance: Texture,
    pub specular_transmittance: Texture,
}

/// The lobe value f·|cos θ_o| and its sampling density for one wavelength
/// of relative index `eta` (interior over exterior), Walter et al. 2007
/// eq. 20–21 and 38–41. Sampling picks reflection with probability F at
/// the half-vector, so the density carries F or 1 − F.
struct Lobe {
    value: f32,
    pdf: f32,
}

fn lobe(dist: &MicrofacetDistribution, wi: Vec3, wo: Vec3, eta: f32, mode: Transport) -> Lobe {
    let zero = Lobe {
        value: 0.0,
        pdf: 0.0,
    };
    let (ci, co) = (wi.z, wo.z);
    if ci == 0.0 || co == 0.0 {
        return zero;
    }
    let reflection = ci * co > 0.0;
    // η of the side wo lies on over that of wi's side.
    let eta_oi = if reflection {
        1.0
    } else if ci > 0.0 {
        eta
    } else {
        1.0 / eta
    };
    // Generalised half-vector, turned to the outside (+z).
    let mut m = (wi + wo * eta_oi).normalize();
    if !m.is_finite() {
        return zero;
    }
    if m.z < 0.0 {
        m = -m;
    }
    let (im, om) = (wi.dot(m), wo.dot(m));
    // Both directions must be on the sides m and the macro normal agree on.
    if im * ci <= 0.0 || om * co <= 0.0 {
        return zero;
    }
    let d = dist.d(m);
    let g = dist.g(wi, wo, m);
    let f = fresnel_dielectric(im, eta).0;
    let wi_up = if ci > 0.0 { wi } else { -wi };
    let visible = dist.pdf_visible(wi_up, m);
    if reflection {
        Lobe {
            value: f * d * g / (4.0 * ci.abs()),
            pdf: visible * f / (4.0 * om.abs()),
        }
    } else {
        let denom = im + eta_oi * om;
        let jacobian = eta_oi * eta_oi * om.abs() / (denom * denom);
        // Radiance carried from the camera scales by 1/η_oi² (cf. dielectric).
        let scale = match mode {
            Transport::Radiance => 1.0 / (eta_oi * eta_oi),
            Transport::Importance => 1.0,
        };
        Lobe {
            value: (1.0 - f) * d * g * im.abs() * jacobian / ci.abs() * scale,
            pdf: visible * (1.0 - f) * jacobian,
        }
    }
}

impl RoughDielectric {
    fn tint<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: TexPoint,
        reflection: bool,
    ) -> SampledSpectrum<K> {
        if reflection {
            self.specular_reflectance.eval(wl, uv)
        } else {
            self.specular_transmittance.eval(wl, uv)
        }
    }

    pub fn eval<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: TexPoint,
        wi: Vec3,
        wo: Vec3,
        mode: Transport,
    ) -> SampledSpectrum<K> {
        let eta = self.ior.eta(wl);
        let dist = &self.distribution.at(uv);
        // One lobe evaluation serves the cluster unless the index varies.
        let v = if self.ior.dispersive() {
            SampledSpectrum::from_fn(|k| lobe(dist, wi, wo, eta[k], mode).value)
        } else {
            SampledSpectrum::splat(lobe(dist, wi, wo, eta[0], mode).value)
        };
        v * self.tint(wl, uv, wi.z * wo.z > 0.0)
    }

    /// Density for the first wavelength (the one sampling uses).
    pub fn pdf<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: TexPoint,
        wi: Vec3,
        wo: Vec3,
    ) -> f32 {
        let eta = self.ior.eta(wl);
        lobe(
            &self.distribution.at(uv),
            wi,
            wo,
            eta[0],
            Transport::Importance,
        )
        .pdf
    }

    pub fn sample<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: TexPoint,
        wi: Vec3,
        u_lobe: f32,
        u: [f32; 2],
        mode: Transport,
    ) -> Option<BsdfSample<K>> {
        if wi.z == 0.0 {
            return None;
        }
        let eta = self.ior.eta(wl);
        let dist = &self.distribution.at(uv);
        let wi_up = if wi.z > 0.0 { wi } else { -wi };
        let m = dist.sample_visible(wi_up, u);
        let im = wi.dot(m);
        let (f, cos_t, eta_it) = fresnel_dielectric(im, eta[0]);
        let reflection = u_lobe < f;
        let wo = if reflection {
            reflect_about(wi, m)
        } else {
            // Refract about m (Walter et al. 2007, eq. 40).
            let eta_ti = 1.0 / eta_it;
            m * (im * eta_ti + cos_t) - wi * eta_ti
        };
        if (wo.z * wi.z > 0.0) != reflection || wo.z == 0.0 {
            return None;
        }
        let first = lobe(dist, wi, wo, eta[0], mode);
        if first.pdf <= 0.0 || first.pdf.is_nan() {
            return None;
        }
        let dispersive = self.ior.dispersive() && !reflection;
        let value = if !self.ior.dispersive() {
            SampledSpectrum::splat(first.value)
        } else if reflection {
            // Same direction for all; each wavelength has its own Fresnel term.
            SampledSpectrum::from_fn(|k| lobe(dist, wi, wo, eta[k], mode).value)
        } else {
            // Refraction collapses the cluster to its first wavelength.
            SampledSpectrum::from_fn(|k| if k == 0 { first.value } else { 0.0 })
        };
        Some(BsdfSample {
            wo,
            weight: value * self.tint(wl, uv, reflection) / first.pdf,
            pdf: first.pdf,
            delta: false,
            collapse: dispersive,
        })
    }
}

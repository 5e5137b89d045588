//! Mitsuba 3's `principledthin` (`src/bsdfs/principledthin.cpp`): the
//! principled model on a thin sheet (Burley 2015, §4), the same from both
//! sides: a GGX reflection whose Fresnel term mixes the dielectric one
//! with a tinted Schlick term, a transmission lobe that is the reflection
//! mirrored through the sheet with roughness scaled by (0.65·η − 0.35),
//! the diffuse lobe with sheen, and a Lambertian diffuse transmission.
//! Lobe probabilities do not depend on the direction, so the density is
//! exact. Tints use the luminance on the path's wavelengths, as Mitsuba's
//! spectral variants do, reweighted to Mitsuba's wavelength density (see
//! `principled`).

use std::f32::consts::FRAC_1_PI;

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::helpers::{
    alphas, cluster_luminance, compatible, schlick, schlick_r0, schlick_weight, tint,
};
use super::opt;
use crate::bsdf::{fresnel_dielectric, reflect_about, BsdfSample};
use crate::bsdf::{MicrofacetDistribution, MicrofacetKind};
use crate::math::Vec3;
use crate::sampling::warp::square_to_cosine_hemisphere;
use crate::texture::{FloatTexture, TexPoint, Texture};

/// How often each lobe is sampled, relative to its weight (Mitsuba's
/// `*_sampling_rate`, all 1 by default).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ThinSamplingRates {
    pub specular_reflectance: f32,
    pub specular_transmittance: f32,
    pub diffuse_reflectance: f32,
    pub diffuse_transmittance: f32,
}

impl Default for ThinSamplingRates {
    fn default() -> Self {
        Self {
            specular_reflectance: 1.0,
            specular_transmittance: 1.0,
            diffuse_reflectance: 1.0,
            diffuse_transmittance: 1.0,
        }
    }
}

/// The parameters as Mitsuba holds them; `None` where Mitsuba's flag is
/// off (absent, or the number 0), which skips the lobe.
#[derive(Debug, Clone, PartialEq)]
pub struct PrincipledThin {
    pub base_color: Texture,
    pub roughness: FloatTexture,
    pub anisotropic: Option<FloatTexture>,
    pub spec_trans: Option<FloatTexture>,
    pub spec_tint: Option<FloatTexture>,
    pub sheen: Option<FloatTexture>,
    pub sheen_tint: Option<FloatTexture>,
    pub flatness: Option<FloatTexture>,
    /// Diffuse transmission, 0–2 (halved where used, as Mitsuba does).
    pub diff_trans: Option<FloatTexture>,
    /// The sheet's index of refraction.
    pub eta: FloatTexture,
    pub rates: ThinSamplingRates,
}

impl Default for PrincipledThin {
    fn default() -> Self {
        Self {
            base_color: Texture::constant(0.5),
            roughness: FloatTexture::Constant(0.5),
            anisotropic: None,
            spec_trans: None,
            spec_tint: None,
            sheen: None,
            sheen_tint: None,
            flatness: None,
            diff_trans: None,
            eta: FloatTexture::Constant(1.5),
            rates: ThinSamplingRates::default(),
        }
    }
}

struct Params {
    roughness: f32,
    anisotropic: Option<f32>,
    spec_trans: f32,
    diff_trans: f32,
    eta: f32,
}

/// Normalised lobe probabilities.
struct Probs {
    spec_reflect: f32,
    spec_trans: f32,
    diff_reflect: f32,
    diff_trans: f32,
}

impl PrincipledThin {
    fn params(&self, uv: TexPoint) -> Params {
        Params {
            roughness: self.roughness.eval(uv),
            anisotropic: self.anisotropic.as_ref().map(|t| t.eval(uv)),
            spec_trans: opt(&self.spec_trans, uv),
            diff_trans: opt(&self.diff_trans, uv) / 2.0,
            eta: self.eta.eval(uv),
        }
    }

    fn reflection_distribution(p: &Params) -> MicrofacetDistribution {
        let (au, av) = alphas(p.roughness, p.anisotropic);
        MicrofacetDistribution::new(MicrofacetKind::Ggx, au, av)
    }

    /// The transmission lobe's roughness, scaled by the sheet's index
    /// (Burley 2015, eq. 3's thin-surface approximation).
    fn transmission_distribution(p: &Params) -> MicrofacetDistribution {
        let (au, av) = alphas((0.65 * p.eta - 0.35) * p.roughness, p.anisotropic);
        MicrofacetDistribution::new(MicrofacetKind::Ggx, au, av)
    }

    fn probs(&self, p: &Params) -> Probs {
        let r = &self.rates;
        let (st, dt) = (p.spec_trans, p.diff_trans);
        let has_st = self.spec_trans.is_some();
        let mut pr = Probs {
            spec_reflect: if has_st {
                st * r.specular_reflectance / 2.0
            } else {
                0.0
            },
            spec_trans: if has_st {
                st * r.specular_transmittance / 2.0
            } else {
                0.0
            },
            diff_reflect: r.diffuse_reflectance * (1.0 - st) * (1.0 - dt),
            diff_trans: if self.diff_trans.is_some() {
                r.diffuse_transmittance * (1.0 - st) * dt
            } else {
                0.0
            },
        };
        let total = pr.spec_reflect + pr.spec_trans + pr.diff_reflect + pr.diff_trans;
        if total > 0.0 {
            pr.spec_reflect /= total;
            pr.spec_trans /= total;
            pr.diff_reflect /= total;
            pr.diff_trans /= total;
        }
        pr
    }

    /// wi turned to +z, wo turned with it, and the half-vector of wi and
    /// wo mirrored to wi's side.
    fn frame(wi: Vec3, wo: Vec3) -> (Vec3, Vec3, Vec3) {
        let (wi, wo) = if wi.z < 0.0 { (-wi, -wo) } else { (wi, wo) };
        let wo_r = Vec3::new(wo.x, wo.y, wo.z.abs());
        (wi, wo, (wi + wo_r).normalize())
    }

    pub fn eval<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: TexPoint,
        wi: Vec3,
        wo: Vec3,
    ) -> SampledSpectrum<K> {
        let zero = SampledSpectrum::splat(0.0);
        if wi.z == 0.0 {
            return zero;
        }
        let p = self.params(uv);
        let base = self.base_color.eval(wl, uv);
        let (wi, wo, wh) = Self::frame(wi, wo);
        if !wh.is_finite() {
            return zero;
        }
        let (ci, co) = (wi.z, wo.z);
        let (reflect, refract) = (co > 0.0, co < 0.0);
        let st = p.spec_trans;
        let mut value = zero;
        if self.spec_trans.is_some() {
            let wi_h = wi.dot(wh);
            let f = fresnel_dielectric(wi_h, p.eta).0;
            if st > 0.0 && reflect && compatible(wh, wi, wo, ci, true) {
                let dist = Self::reflection_distribution(&p);
                let spec_tint = opt(&self.spec_tint, uv);
                let f_thin = match &self.spec_tint {
                    Some(_) => {
                        let c_tint = tint(&base, cluster_luminance(wl, &base));
                        let r0 = schlick_r0(p.eta);
                        SampledSpectrum::from_fn(|k| {
                            let fs = schlick(c_tint[k] * r0, wi_h, p.eta);
                            f + (fs - f) * spec_tint
                        })
                    }
                    None => SampledSpectrum::splat(f * (1.0 - spec_tint)),
                };
                value += f_thin * (st * dist.d(wh) * dist.g(wi, wo, wh) / (4.0 * ci));
            }
            if st > 0.0 && refract && compatible(wh, wi, wo, ci, false) {
                let dist = Self::transmission_distribution(&p);
                value += base * (st * (1.0 - f) * dist.d(wh) * dist.g(wi, wo, wh) / (4.0 * ci));
            }
        }
        let dt = p.diff_trans;
        if reflect && st < 1.0 && dt < 1.0 {
            let (fo, fi) = (schlick_weight(co.abs()), schlick_weight(ci));
            let f_diff = (1.0 - 0.5 * fi) * (1.0 - 0.5 * fo);
            let cos_d = wh.dot(wo);
            let rr = 2.0 * p.roughness * cos_d * cos_d;
            let f_retro = rr * (fo + fi + fo * fi * (rr - 1.0));
            let lambert = f_diff + f_retro;
            let shape = match &self.flatness {
                Some(flat) => {
                    let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
                    let fss90 = rr / 2.0;
                    let fss = lerp(1.0, fss90, fo) * lerp(1.0, fss90, fi);
                    let f_ss = 1.25 * (fss * (1.0 / (co.abs() + ci) - 0.5) + 0.5);
                    lerp(lambert, f_ss, flat.eval(uv))
                }
                None => lambert,
            };
            value += base * ((1.0 - st) * co * FRAC_1_PI * (1.0 - dt) * shape);
            if let Some(sh) = &self.sheen {
                let sheen = sh.eval(uv);
                if sheen > 0.0 {
                    let w = sheen * (1.0 - st) * schlick_weight(cos_d.abs()) * (1.0 - dt) * co;
                    match &self.sheen_tint {
                        Some(t) => {
                            let sheen_tint = t.eval(uv);
                            let c_tint = tint(&base, cluster_luminance(wl, &base));
                            let c_sheen =
                                SampledSpectrum::splat(1.0 - sheen_tint) + c_tint * sheen_tint;
                            value += c_sheen * w;
                        }
                        None => value += SampledSpectrum::splat(w),
                    }
                }
            }
        }
        if self.diff_trans.is_some() && refract && st < 1.0 && dt > 0.0 {
            value += base * ((1.0 - st) * dt * FRAC_1_PI * co.abs());
        }
        value
    }

    pub fn pdf(&self, uv: TexPoint, wi: Vec3, wo: Vec3) -> f32 {
        if wi.z == 0.0 {
            return 0.0;
        }
        let p = self.params(uv);
        let pr = self.probs(&p);
        let (wi, wo, wh) = Self::frame(wi, wo);
        let (reflect, refract) = (wo.z > 0.0, wo.z < 0.0);
        let mut pdf = 0.0;
        if self.spec_trans.is_some() && wh.is_finite() {
            let wo_r = Vec3::new(wo.x, wo.y, wo.z.abs());
            let dwh_dwo = (1.0 / (4.0 * wo_r.dot(wh))).abs();
            if reflect && compatible(wh, wi, wo, wi.z, true) {
                let dist = Self::reflection_distribution(&p);
                pdf += pr.spec_reflect * dist.pdf_visible(wi, wh) * dwh_dwo;
            }
            if refract && compatible(wh, wi, wo, wi.z, false) {
                let dist = Self::transmission_distribution(&p);
                pdf += pr.spec_trans * dist.pdf_visible(wi, wh) * dwh_dwo;
            }
        }
        if reflect {
            pdf += pr.diff_reflect * wo.z * FRAC_1_PI;
        }
        if self.diff_trans.is_some() && refract {
            pdf += pr.diff_trans * -wo.z * FRAC_1_PI;
        }
        pdf
    }

    pub fn sample<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: TexPoint,
        wi_in: Vec3,
        u_lobe: f32,
        u: [f32; 2],
    ) -> Option<BsdfSample<K>> {
        if wi_in.z == 0.0 {
            return None;
        }
        let p = self.params(uv);
        let pr = self.probs(&p);
        let wi = if wi_in.z < 0.0 { -wi_in } else { wi_in };
        let c1 = pr.spec_reflect;
        let c2 = c1 + pr.spec_trans;
        let c3 = c2 + pr.diff_reflect;
        let has_st = self.spec_trans.is_some();
        let wo = if has_st && u_lobe < c1 {
            let m = Self::reflection_distribution(&p).sample_visible(wi, u);
            let wo = reflect_about(wi, m);
            if !(compatible(m, wi, wo, wi.z, true) && wo.z > 0.0) {
                return None;
            }
            wo
        } else if has_st && u_lobe >= c1 && u_lobe < c2 {
            let m = Self::transmission_distribution(&p).sample_visible(wi, u);
            let r = reflect_about(wi, m);
            let wo = Vec3::new(r.x, r.y, -r.z);
            if !(compatible(m, wi, wo, wi.z, false) && wo.z < 0.0) {
                return None;
            }
            wo
        } else if u_lobe >= c2 && u_lobe < c3 {
            square_to_cosine_hemisphere(u)
        } else if self.diff_trans.is_some() && u_lobe >= c3 {
            -square_to_cosine_hemisphere(u)
        } else {
            return None;
        };
        let wo = if wi_in.z < 0.0 { -wo } else { wo };
        let pdf = self.pdf(uv, wi_in, wo);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        Some(BsdfSample {
            wo,
            weight: self.eval(wl, uv, wi_in, wo) / pdf,
            pdf,
            delta: false,
            collapse: false,
        })
    }
}

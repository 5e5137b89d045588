//! Mitsuba 3's `principled` BSDF (Burley 2012, 2015): a Disney-style
//! material of a diffuse lobe with retro-reflection (or Hanrahan–Krueger
//! flattening), sheen, a GGX specular lobe whose Fresnel term mixes the
//! dielectric one with Schlick's metallic and tinted terms, a GGX
//! transmission lobe and a GTR1 clearcoat, with Mitsuba's lobe weights,
//! lobe-selection probabilities and sampling (`src/bsdfs/principled.cpp`).
//!
//! As in Mitsuba's spectral variants, the tint of `spec_tint` and
//! `sheen_tint` divides the base colour by its luminance on the path's
//! wavelengths ([`helpers::cluster_luminance`]), not on the whole
//! spectrum; since that depends on how wavelengths are drawn, each is
//! weighted by Mitsuba's wavelength density over the path's, which makes
//! the tint Mitsuba's on its wavelengths and in expectation (without it a
//! tinted sphere rendered 2 % brighter than in Mitsuba). Mitsuba picks a lobe with probabilities that depend on the
//! Fresnel term at the sampled microfacet, while its density uses the one
//! at the half-vector of the direction returned; both agree except when
//! 0 < spec_trans < 1, or spec_trans > 0 with clearcoat, where Mitsuba's
//! density (and weight) is an approximation. Scotopia follows it.

mod helpers;
mod thin;

pub use helpers::mitsuba_wavelength_pdf;
pub use thin::{PrincipledThin, ThinSamplingRates};

use std::f32::consts::FRAC_1_PI;

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::{fresnel_dielectric, reflect_about, BsdfSample, Transport};
use super::{MicrofacetDistribution, MicrofacetKind};
use crate::math::Vec3;
use crate::sampling::warp::square_to_cosine_hemisphere;
use crate::texture::{FloatTexture, TexPoint, Texture};
use helpers::{
    alphas, clearcoat_g, cluster_luminance, compatible, schlick, schlick_r0, schlick_weight, tint,
    Gtr1,
};

/// How often each lobe is sampled, relative to its weight (Mitsuba's
/// `*_sampling_rate`, all 1 by default).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SamplingRates {
    pub diffuse: f32,
    pub specular: f32,
    pub clearcoat: f32,
}

impl Default for SamplingRates {
    fn default() -> Self {
        Self {
            diffuse: 1.0,
            specular: 1.0,
            clearcoat: 1.0,
        }
    }
}

/// The parameters as Mitsuba holds them. An optional parameter is `None`
/// where Mitsuba's flag is off (absent, or the number 0): its lobe is
/// then skipped entirely, which for `spec_trans` and `anisotropic` also
/// changes the sampling and the roughness mapping.
#[derive(Debug, Clone, PartialEq)]
pub struct Principled {
    pub base_color: Texture,
    pub roughness: FloatTexture,
    pub anisotropic: Option<FloatTexture>,
    pub metallic: Option<FloatTexture>,
    pub spec_trans: Option<FloatTexture>,
    pub spec_tint: Option<FloatTexture>,
    pub sheen: Option<FloatTexture>,
    pub sheen_tint: Option<FloatTexture>,
    pub flatness: Option<FloatTexture>,
    pub clearcoat: Option<FloatTexture>,
    pub clearcoat_gloss: FloatTexture,
    /// Interior over exterior index (from `eta` or `specular`).
    pub eta: f32,
    pub rates: SamplingRates,
}

/// `principled`'s default: Mitsuba's `specular` 0.5 ⇒ η = 1.5.
impl Default for Principled {
    fn default() -> Self {
        Self {
            base_color: Texture::constant(0.5),
            roughness: FloatTexture::Constant(0.5),
            anisotropic: None,
            metallic: None,
            spec_trans: None,
            spec_tint: None,
            sheen: None,
            sheen_tint: None,
            flatness: None,
            clearcoat: None,
            clearcoat_gloss: FloatTexture::Constant(0.0),
            eta: specular_to_eta(0.5),
            rates: SamplingRates::default(),
        }
    }
}

/// Mitsuba's `specular` → η: the index whose normal-incidence
/// reflectance is 0.08·specular (Burley 2015, §5.2).
pub fn specular_to_eta(specular: f32) -> f32 {
    2.0 / (1.0 - (0.08 * specular).sqrt()) - 1.0
}

/// The scalar parameters at one point.
struct Params {
    roughness: f32,
    anisotropic: Option<f32>,
    metallic: f32,
    spec_trans: f32,
    clearcoat: f32,
}

/// Normalised probabilities of picking each lobe.
struct LobeProbs {
    diffuse: f32,
    clearcoat: f32,
    trans: f32,
    reflect: f32,
}

fn opt(t: &Option<FloatTexture>, uv: TexPoint) -> f32 {
    t.as_ref().map_or(0.0, |t| t.eval(uv))
}

impl Principled {
    fn params(&self, uv: TexPoint) -> Params {
        Params {
            roughness: self.roughness.eval(uv),
            anisotropic: self.anisotropic.as_ref().map(|t| t.eval(uv)),
            metallic: opt(&self.metallic, uv),
            spec_trans: opt(&self.spec_trans, uv),
            clearcoat: opt(&self.clearcoat, uv),
        }
    }

    fn distribution(p: &Params) -> MicrofacetDistribution {
        let (au, av) = alphas(p.roughness, p.anisotropic);
        MicrofacetDistribution::new(MicrofacetKind::Ggx, au, av)
    }

    /// Mitsuba's lobe-selection probabilities for dielectric reflectance
    /// `f`; from inside only the specular reflection and transmission.
    fn probs(&self, p: &Params, front: bool, f: f32) -> LobeProbs {
        let bsdf = (1.0 - p.metallic) * p.spec_trans;
        let brdf = (1.0 - p.metallic) * (1.0 - p.spec_trans);
        let has_trans = self.spec_trans.is_some();
        let (mut reflect, mut trans, mut clearcoat, mut diffuse) = if front {
            (
                self.rates.specular * (1.0 - bsdf * (1.0 - f)),
                self.rates.specular * bsdf * (1.0 - f),
                0.25 * p.clearcoat * self.rates.clearcoat,
                brdf * self.rates.diffuse,
            )
        } else {
            (f, 1.0 - f, 0.0, 0.0)
        };
        if !has_trans {
            trans = 0.0;
        }
        if self.clearcoat.is_none() {
            clearcoat = 0.0;
        }
        let total = reflect + trans + clearcoat + diffuse;
        if total > 0.0 {
            reflect /= total;
            trans /= total;
            clearcoat /= total;
            diffuse /= total;
        }
        LobeProbs {
            diffuse,
            clearcoat,
            trans,
            reflect,
        }
    }

    /// The half-vector of (wi, wo), generalised for refraction and turned
    /// to +z, and the index ratio of the path's far side to its near side.
    fn half_vector(&self, wi: Vec3, wo: Vec3) -> (Vec3, f32) {
        let eta_path = if wi.z > 0.0 { self.eta } else { 1.0 / self.eta };
        let reflect = wi.z * wo.z > 0.0;
        let wh = (wi + wo * if reflect { 1.0 } else { eta_path }).normalize();
        (if wh.z < 0.0 { -wh } else { wh }, eta_path)
    }

    pub fn eval<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: TexPoint,
        wi: Vec3,
        wo: Vec3,
        mode: Transport,
    ) -> SampledSpectrum<K> {
        let zero = SampledSpectrum::splat(0.0);
        let (ci, co) = (wi.z, wo.z);
        if ci == 0.0 {
            return zero;
        }
        let p = self.params(uv);
        let base = self.base_color.eval(wl, uv);
        let bsdf = (1.0 - p.metallic) * p.spec_trans;
        let brdf = (1.0 - p.metallic) * (1.0 - p.spec_trans);
        let (reflect, refract, front) = (ci * co > 0.0, ci * co < 0.0, ci > 0.0);
        let (wh, eta_path) = self.half_vector(wi, wo);
        if !wh.is_finite() {
            return zero;
        }
        let dist = Self::distribution(&p);
        let (wi_h, wo_h) = (wi.dot(wh), wo.dot(wh));
        let f_diel = fresnel_dielectric(wi_h, self.eta).0;
        let refl_ok = compatible(wh, wi, wo, ci, true);
        let d = dist.d(wh);
        let g = dist.g(wi, wo, wh);
        let mut value = zero;

        if reflect && refl_ok && f_diel > 0.0 {
            let spec_tint = opt(&self.spec_tint, uv);
            let f = if front {
                self.principled_fresnel(wl, &base, f_diel, p.metallic, spec_tint, wi_h)
            } else {
                SampledSpectrum::splat(bsdf * f_diel)
            };
            value += f * (d * g / (4.0 * ci.abs()));
        }
        if self.spec_trans.is_some()
            && bsdf > 0.0
            && refract
            && compatible(wh, wi, wo, ci, false)
            && f_diel < 1.0
        {
            let scale = match mode {
                Transport::Radiance => 1.0 / (eta_path * eta_path),
                Transport::Importance => 1.0,
            };
            let denom = wi_h + eta_path * wo_h;
            let t = (scale * (1.0 - f_diel) * d * g * eta_path * eta_path * wi_h * wo_h
                / (ci * denom * denom))
                .abs();
            value += base.map(f32::sqrt) * (bsdf * t);
        }
        if let Some(cc) = &self.clearcoat {
            let clearcoat = cc.eval(uv);
            if clearcoat > 0.0 && reflect && refl_ok && front {
                let gtr = Gtr1::from_gloss(self.clearcoat_gloss.eval(uv));
                let fcc = schlick(0.04, wi_h, self.eta);
                value += SampledSpectrum::splat(
                    clearcoat * 0.25 * fcc * gtr.d(wh) * clearcoat_g(wi, wo, wh) * co.abs(),
                );
            }
        }
        if brdf > 0.0 && reflect && front {
            value += self.diffuse(wl, uv, &p, &base, brdf, ci, co, wh.dot(wo));
        }
        value
    }

    /// The diffuse lobe (Burley 2012, B.1; Burley 2015, §5.3 for the
    /// flattening) and the sheen, which Mitsuba adds only where the
    /// diffuse lobe is active.
    #[allow(clippy::too_many_arguments)]
    fn diffuse<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: TexPoint,
        p: &Params,
        base: &SampledSpectrum<K>,
        brdf: f32,
        ci: f32,
        co: f32,
        cos_d: f32,
    ) -> SampledSpectrum<K> {
        let (fo, fi) = (schlick_weight(co.abs()), schlick_weight(ci.abs()));
        let f_diff = (1.0 - 0.5 * fi) * (1.0 - 0.5 * fo);
        let rr = 2.0 * p.roughness * cos_d * cos_d;
        let f_retro = rr * (fo + fi + fo * fi * (rr - 1.0));
        let lambert = f_diff + f_retro;
        let shape = match &self.flatness {
            Some(flat) => {
                let flatness = flat.eval(uv);
                let fss90 = rr / 2.0;
                let lerp = |a: f32, b: f32, t: f32| a + (b - a) * t;
                let fss = lerp(1.0, fss90, fo) * lerp(1.0, fss90, fi);
                let f_ss = 1.25 * (fss * (1.0 / (co.abs() + ci.abs()) - 0.5) + 0.5);
                lerp(lambert, f_ss, flatness)
            }
            None => lambert,
        };
        let mut value = *base * (brdf * co.abs() * FRAC_1_PI * shape);
        if let Some(sh) = &self.sheen {
            let sheen = sh.eval(uv);
            if sheen > 0.0 && 1.0 - p.metallic > 0.0 {
                let fd = schlick_weight(cos_d.abs());
                let w = sheen * (1.0 - p.metallic) * fd * co.abs();
                match &self.sheen_tint {
                    Some(st) => {
                        let sheen_tint = st.eval(uv);
                        let c_tint = tint(base, cluster_luminance(wl, base));
                        let c_sheen =
                            SampledSpectrum::splat(1.0 - sheen_tint) + c_tint * sheen_tint;
                        value += c_sheen * w;
                    }
                    None => value += SampledSpectrum::splat(w),
                }
            }
        }
        value
    }

    /// The front side's Fresnel term: the dielectric reflectance, with the
    /// metallic part and the tinted dielectric part by Schlick's
    /// approximation (Mitsuba's `principled_fresnel`).
    fn principled_fresnel<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        base: &SampledSpectrum<K>,
        f_diel: f32,
        metallic: f32,
        spec_tint: f32,
        cos_i: f32,
    ) -> SampledSpectrum<K> {
        let eta = self.eta;
        let eta_it = if cos_i >= 0.0 { eta } else { 1.0 / eta };
        let mut f = SampledSpectrum::splat((1.0 - metallic) * (1.0 - spec_tint) * f_diel);
        if self.metallic.is_some() {
            f += SampledSpectrum::from_fn(|k| metallic * schlick(base[k], cos_i, eta));
        }
        if self.spec_tint.is_some() {
            let c_tint = tint(base, cluster_luminance(wl, base));
            let r0 = schlick_r0(eta_it);
            f += SampledSpectrum::from_fn(|k| {
                (1.0 - metallic) * spec_tint * schlick(c_tint[k] * r0, cos_i, eta)
            });
        }
        f
    }

    /// Mitsuba's `pdf`: the lobe mixture with the selection probabilities
    /// evaluated at the half-vector of (wi, wo).
    pub fn pdf(&self, uv: TexPoint, wi: Vec3, wo: Vec3) -> f32 {
        let (ci, co) = (wi.z, wo.z);
        if ci == 0.0 {
            return 0.0;
        }
        let p = self.params(uv);
        let (reflect, refract, front) = (ci * co > 0.0, ci * co < 0.0, ci > 0.0);
        let (wh, eta_path) = self.half_vector(wi, wo);
        if !wh.is_finite() {
            return 0.0;
        }
        let dist = Self::distribution(&p);
        let (wi_h, wo_h) = (wi.dot(wh), wo.dot(wh));
        let f = fresnel_dielectric(wi_h, self.eta).0;
        let pr = self.probs(&p, front, f);
        let dwh_dwo = if self.spec_trans.is_some() && !reflect {
            let denom = wi_h + eta_path * wo_h;
            (eta_path * eta_path * wo_h / (denom * denom)).abs()
        } else {
            (1.0 / (4.0 * wo_h)).abs()
        };
        let wi_up = if ci > 0.0 { wi } else { -wi };
        let mut pdf = 0.0;
        let refl_ok = reflect && compatible(wh, wi, wo, ci, true);
        if refl_ok {
            pdf += pr.reflect * dist.pdf_visible(wi_up, wh) * dwh_dwo;
        }
        if reflect {
            pdf += pr.diffuse * co * FRAC_1_PI;
        }
        if self.spec_trans.is_some() && refract && compatible(wh, wi, wo, ci, false) {
            pdf += pr.trans * dist.pdf_visible(wi_up, wh) * dwh_dwo;
        }
        if self.clearcoat.is_some() && refl_ok {
            let gtr = Gtr1::from_gloss(self.clearcoat_gloss.eval(uv));
            pdf += pr.clearcoat * gtr.pdf(wh) * dwh_dwo;
        }
        pdf
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
        let ci = wi.z;
        if ci == 0.0 {
            return None;
        }
        let p = self.params(uv);
        let front = ci > 0.0;
        let bsdf = if self.spec_trans.is_some() {
            (1.0 - p.metallic) * p.spec_trans
        } else {
            0.0
        };
        if !(front || bsdf > 0.0) {
            return None;
        }
        let dist = Self::distribution(&p);
        let wi_up = if front { wi } else { -wi };
        let m = dist.sample_visible(wi_up, u);
        let wi_m = wi.dot(m);
        let (f, cos_t, eta_it) = fresnel_dielectric(wi_m, self.eta);
        let pr = self.probs(&p, front, f);
        let (c1, c2, c3) = (
            pr.diffuse,
            pr.diffuse + pr.clearcoat,
            pr.diffuse + pr.clearcoat + pr.trans,
        );
        let wo = if u_lobe < c1 {
            square_to_cosine_hemisphere(u)
        } else if u_lobe < c2 {
            let m_cc = Gtr1::from_gloss(self.clearcoat_gloss.eval(uv)).sample(u);
            let wo = reflect_about(wi, m_cc);
            if !compatible(m_cc, wi, wo, ci, true) {
                return None;
            }
            wo
        } else if u_lobe < c3 {
            let eta_ti = 1.0 / eta_it;
            let wo = m * (wi_m * eta_ti + cos_t) - wi * eta_ti;
            if !(compatible(m, wi, wo, ci, false) && ci * wo.z < 0.0) {
                return None;
            }
            wo
        } else {
            let wo = reflect_about(wi, m);
            if !compatible(m, wi, wo, ci, true) {
                return None;
            }
            wo
        };
        let transmitted = u_lobe >= c2 && u_lobe < c3;
        if !transmitted && ci * wo.z <= 0.0 {
            return None;
        }
        let pdf = self.pdf(uv, wi, wo);
        if pdf.is_nan() || pdf <= 0.0 {
            return None;
        }
        let value = self.eval(wl, uv, wi, wo, mode);
        Some(BsdfSample {
            wo,
            weight: value / pdf,
            pdf,
            delta: false,
            collapse: false,
        })
    }
}

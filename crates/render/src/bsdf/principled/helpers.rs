//! The pieces Mitsuba 3's `principled` and `principledthin` share
//! (`src/bsdfs/principledhelpers.h`): Schlick's Fresnel approximation,
//! the GTR1 clearcoat distribution, its separable GGX shadowing, the
//! macro/micro-surface side test and the roughness mapping. The models
//! are Burley's (2012, "Physically Based Shading at Disney"; 2015,
//! "Extending the Disney BRDF to a BSDF with Integrated Subsurface
//! Scattering").

use std::f32::consts::PI;

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use crate::math::Vec3;

/// Schlick's weight (1 − cos)⁵, the cosine clamped to [0, 1].
#[inline]
pub fn schlick_weight(cos: f32) -> f32 {
    let m = (1.0 - cos).clamp(0.0, 1.0);
    let m2 = m * m;
    m2 * m2 * m
}

/// Schlick's reflectance R₀ + (1 − R₀)(1 − cos)⁵ at a microfacet of
/// relative index `eta` (inside over outside). Where light leaves the
/// denser side (η_it < 1) the refracted angle's cosine is used, as Mitsuba
/// does (zero beyond the critical angle, so F = 1).
#[inline]
pub fn schlick(r0: f32, cos_i: f32, eta: f32) -> f32 {
    let outside = cos_i >= 0.0;
    let (eta_it, eta_ti) = if outside {
        (eta, 1.0 / eta)
    } else {
        (1.0 / eta, eta)
    };
    let w = if eta_it > 1.0 {
        schlick_weight(cos_i.abs())
    } else {
        let cos_t2 = 1.0 - (1.0 - cos_i * cos_i) * eta_ti * eta_ti;
        schlick_weight(cos_t2.max(0.0).sqrt())
    };
    w * (1.0 - r0) + r0
}

/// Normal-incidence reflectance ((η − 1)/(η + 1))².
#[inline]
pub fn schlick_r0(eta: f32) -> f32 {
    let r = (eta - 1.0) / (eta + 1.0);
    r * r
}

/// The density with which Mitsuba 3's spectral variants draw wavelengths
/// (`pdf_rgb_spectrum`, after Radziszewski et al. 2009, "An Improved
/// Technique for Full Spectral Rendering"), per nm over 360–830 nm.
#[inline]
pub fn mitsuba_wavelength_pdf(lambda: f32) -> f32 {
    if !(360.0..=830.0).contains(&lambda) {
        return 0.0;
    }
    let c = (0.0072 * (lambda - 538.0)).cosh();
    0.003_939_804 / (c * c)
}

/// The luminance Mitsuba's spectral variants give a spectrum sampled on
/// a path's wavelengths: the mean over the cluster of ȳ(λ)·value
/// (`mitsuba::luminance(value, wavelengths)`), which depends on the
/// wavelengths the path carries. Mitsuba draws them from
/// [`mitsuba_wavelength_pdf`]; scotopia's clusters have other densities,
/// so each wavelength is weighted by Mitsuba's density over the path's
/// and the mean self-normalised: Mitsuba's own mean where the densities
/// are Mitsuba's, and the same luminance in expectation otherwise.
#[inline]
pub fn cluster_luminance<const K: usize>(
    wl: &SampledWavelengths<K>,
    value: &SampledSpectrum<K>,
) -> f32 {
    let (mut sum, mut weights) = (0.0f32, 0.0f32);
    for k in 0..K {
        let (lambda, pdf) = (wl.lambda(k), wl.pdf(k));
        if pdf > 0.0 {
            let w = mitsuba_wavelength_pdf(lambda) / pdf;
            sum += w * scotopia_color::cie::xyz_bar(lambda)[1] * value[k];
            weights += w;
        }
    }
    if weights > 0.0 {
        sum / weights
    } else {
        0.0
    }
}

/// `base / lum` where the luminance is positive, else 1: the hue of the
/// base colour at unit luminance (Burley 2012's C_tint).
#[inline]
pub fn tint<const K: usize>(base: &SampledSpectrum<K>, lum: f32) -> SampledSpectrum<K> {
    if lum > 0.0 {
        *base / lum
    } else {
        SampledSpectrum::splat(1.0)
    }
}

/// Whether `wi` and `wo` lie on the sides of microfacet `m` that a
/// reflection (or a refraction) needs, seen from the side of `wi`
/// (`cos_i` = wi.z).
#[inline]
pub fn compatible(m: Vec3, wi: Vec3, wo: Vec3, cos_i: f32, reflection: bool) -> bool {
    let m = if cos_i < 0.0 { -m } else { m };
    let wo_side = if reflection { wo.dot(m) } else { -wo.dot(m) };
    wi.dot(m) > 0.0 && wo_side > 0.0
}

/// GGX roughness (α_u, α_v) from Disney's `roughness` and `anisotropic`
/// (Burley 2012, addendum B.2: α = roughness², aspect √(1 − 0.9·aniso)),
/// each at least 0.001 as Mitsuba clamps it.
#[inline]
pub fn alphas(roughness: f32, anisotropic: Option<f32>) -> (f32, f32) {
    let r2 = roughness * roughness;
    match anisotropic {
        None => (r2.max(0.001), r2.max(0.001)),
        Some(a) => {
            let aspect = (1.0 - 0.9 * a).sqrt();
            ((r2 / aspect).max(0.001), (r2 * aspect).max(0.001))
        }
    }
}

/// Burley's "generalised Trowbridge–Reitz" with γ = 1, the clearcoat's
/// distribution (Burley 2012, eq. 4 and B.2), isotropic and sampled by
/// D(m) cos θ_m (not by visible normals, as in Mitsuba).
#[derive(Debug, Clone, Copy)]
pub struct Gtr1 {
    pub alpha: f32,
}

impl Gtr1 {
    /// Mitsuba's mapping of `clearcoat_gloss` to α: 0.1 (matte) → 0.001.
    pub fn from_gloss(gloss: f32) -> Self {
        Self {
            alpha: 0.1 + (0.001 - 0.1) * gloss,
        }
    }

    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        let c2 = m.z * m.z;
        let a2 = self.alpha * self.alpha;
        let d = (a2 - 1.0) / (PI * a2.ln() * (1.0 + (a2 - 1.0) * c2));
        if d * m.z > 1e-20 {
            d
        } else {
            0.0
        }
    }

    #[inline]
    pub fn pdf(&self, m: Vec3) -> f32 {
        if m.z < 0.0 {
            0.0
        } else {
            m.z * self.d(m)
        }
    }

    #[inline]
    pub fn sample(&self, u: [f32; 2]) -> Vec3 {
        let (sin_phi, cos_phi) = (2.0 * PI * u[0]).sin_cos();
        let a2 = self.alpha * self.alpha;
        let c2 = (1.0 - a2.powf(1.0 - u[1])) / (1.0 - a2);
        let s = (1.0 - c2).max(0.0).sqrt();
        let c = c2.max(0.0).sqrt();
        Vec3::new(cos_phi * s, sin_phi * s, c)
    }
}

/// Smith's G₁ for an isotropic GGX of roughness `alpha`, zero where `v`
/// sees the back of `m` (Mitsuba's `smith_ggx1`).
#[inline]
pub fn smith_ggx1(v: Vec3, m: Vec3, alpha: f32) -> f32 {
    if v.dot(m) * v.z <= 0.0 {
        return 0.0;
    }
    if v.z == 1.0 {
        return 1.0;
    }
    let c2 = v.z * v.z;
    let t2 = (1.0 - c2) / c2;
    2.0 / (1.0 + (1.0 + alpha * alpha * t2).sqrt())
}

/// The clearcoat's separable shadowing–masking (GGX of α 0.25, as Burley
/// 2012 fixes it).
#[inline]
pub fn clearcoat_g(wi: Vec3, wo: Vec3, m: Vec3) -> f32 {
    smith_ggx1(wi, m, 0.25) * smith_ggx1(wo, m, 0.25)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn gtr1_projects_to_one() {
        for gloss in [0.0, 0.5, 0.9] {
            let d = Gtr1::from_gloss(gloss);
            let n = 200_000;
            // ∫ D cos θ dω by a midpoint rule in cos²θ… in u of the sampler:
            // the inverse CDF maps u uniformly, so check it numerically.
            let mut sum = 0.0f64;
            for i in 0..n {
                let x = (i as f64 + 0.5) / n as f64;
                let c = 1.0 - x * x;
                let m = Vec3::new((1.0 - c * c).sqrt() as f32, 0.0, c as f32);
                sum += d.pdf(m) as f64 * 2.0 * x / n as f64;
            }
            sum *= 2.0 * std::f64::consts::PI;
            assert!((sum - 1.0).abs() < 2e-3, "gloss {gloss}: {sum}");
        }
    }

    #[test]
    fn luminance_is_mitsubas_mean_on_its_wavelength_density() {
        // Mitsuba's density integrates to 1 over 360–830 nm.
        let total: f32 = (0..4700)
            .map(|i| mitsuba_wavelength_pdf(360.05 + i as f32 * 0.1) * 0.1)
            .sum();
        assert!((total - 1.0).abs() < 1e-3, "{total}");
        let lambda = [450.0, 520.0, 580.0, 650.0];
        let v = SampledSpectrum([0.2, 0.5, 0.7, 0.1]);
        let y = lambda.map(|l| scotopia_color::cie::xyz_bar(l)[1]);
        let plain = (0..4).map(|k| y[k] * v[k]).sum::<f32>() / 4.0;
        let wl = SampledWavelengths::new(lambda, lambda.map(mitsuba_wavelength_pdf));
        assert!((cluster_luminance(&wl, &v) - plain).abs() < 1e-6);
        // Drawn uniformly: weighted by Mitsuba's density.
        let wl = SampledWavelengths::new(lambda, [1.0 / 470.0; 4]);
        let w = lambda.map(mitsuba_wavelength_pdf);
        let want = (0..4).map(|k| w[k] * y[k] * v[k]).sum::<f32>() / w.iter().sum::<f32>();
        assert!((cluster_luminance(&wl, &v) - want).abs() < 1e-6);
        assert!((want - plain).abs() > 1e-3, "the test must tell them apart");
    }

    #[test]
    fn schlick_limits() {
        assert!((schlick(0.04, 1.0, 1.5) - 0.04).abs() < 1e-6);
        assert!((schlick(0.04, 0.0, 1.5) - 1.0).abs() < 1e-6);
        // Inside beyond the critical angle: total reflection.
        assert!((schlick(0.04, -0.2, 1.5) - 1.0).abs() < 1e-6);
    }
}

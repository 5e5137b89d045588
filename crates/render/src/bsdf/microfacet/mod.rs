//! Microfacet normal distributions, Beckmann or GGX (Trowbridge–Reitz),
//! isotropic or anisotropic (α_u along the shading frame's x, α_v along y),
//! with the separable Smith shadowing term and visible-normal sampling
//! (Heitz & d'Eon 2014, "Importance Sampling Microfacet-Based BSDFs using
//! the Distribution of Visible Normals"), as Mitsuba 3's `microfacet.h`
//! uses by default. Both distributions are written for roughness 1 and
//! stretched (Heitz 2014, "Understanding the Masking-Shadowing Function",
//! §5.3): a surface of roughness (α_u, α_v) is the unit one scaled by α_u
//! in x and α_v in y.

mod albedo;
mod beckmann;
mod erf;
mod ggx;
mod roughness;

use std::f32::consts::PI;

use crate::math::Vec3;

pub use roughness::{Roughness, TexturedRoughness};

/// The shape of the slope distribution.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum MicrofacetKind {
    /// Gaussian slopes (Mitsuba's default).
    Beckmann,
    /// Trowbridge–Reitz: long-tailed, for very rough surfaces.
    Ggx,
}

/// Below this roughness the distributions are clamped, as Mitsuba does
/// (smaller values overflow D); a smooth surface is its own BSDF.
pub const MIN_ALPHA: f32 = 1e-4;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MicrofacetDistribution {
    pub kind: MicrofacetKind,
    /// Roughness along the shading frame's tangent (x).
    pub alpha_u: f32,
    /// Roughness along the bitangent (y).
    pub alpha_v: f32,
}

impl MicrofacetDistribution {
    /// A distribution with roughness (α_u, α_v), each at least [`MIN_ALPHA`].
    pub fn new(kind: MicrofacetKind, alpha_u: f32, alpha_v: f32) -> Self {
        Self {
            kind,
            alpha_u: alpha_u.max(MIN_ALPHA),
            alpha_v: alpha_v.max(MIN_ALPHA),
        }
    }

    pub fn isotropic(kind: MicrofacetKind, alpha: f32) -> Self {
        Self::new(kind, alpha, alpha)
    }

    pub fn is_isotropic(&self) -> bool {
        self.alpha_u == self.alpha_v
    }

    /// D(m), normalised so that ∫ D(m) cos θ_m dω = 1; zero below the
    /// surface.
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let (x, y) = (m.x / self.alpha_u, m.y / self.alpha_v);
        let (s, c2) = (x * x + y * y, m.z * m.z);
        let unit = match self.kind {
            MicrofacetKind::Beckmann => beckmann::d_unnormalised(s, c2),
            MicrofacetKind::Ggx => ggx::d_unnormalised(s, c2),
        };
        let d = unit / (PI * self.alpha_u * self.alpha_v);
        // As Mitsuba: negligible densities are zero (no denormal noise).
        if d * m.z > 1e-20 {
            d
        } else {
            0.0
        }
    }

    /// Smith's G₁(w, m), zero when w and m lie on different sides of the
    /// microfacet (Walter et al. 2007, eq. 7's χ⁺).
    #[inline]
    pub fn g1(&self, w: Vec3, m: Vec3) -> f32 {
        if w.dot(m) * w.z <= 0.0 {
            return 0.0;
        }
        let (x, y) = (self.alpha_u * w.x, self.alpha_v * w.y);
        let xy2 = x * x + y * y;
        if xy2 == 0.0 {
            return 1.0;
        }
        // α² tan²θ with α projected on w's azimuth.
        let t2 = xy2 / (w.z * w.z);
        match self.kind {
            MicrofacetKind::Beckmann => beckmann::g1(t2),
            MicrofacetKind::Ggx => ggx::g1(t2),
        }
    }

    /// The G₁(w, m) that normalises the visible-normal density, exactly
    /// Smith's: the same as [`Self::g1`] for GGX; for Beckmann the exact
    /// erf form, where `g1` is Walter's approximation (as in Mitsuba's
    /// `eval`). Sampling draws normals with this exact density, so `pdf`
    /// uses it and the estimator stays unbiased; Mitsuba's `pdf` uses the
    /// approximation, 0.35 % off at most.
    #[inline]
    pub fn g1_visible(&self, w: Vec3, m: Vec3) -> f32 {
        match self.kind {
            MicrofacetKind::Ggx => self.g1(w, m),
            MicrofacetKind::Beckmann => {
                if w.dot(m) * w.z <= 0.0 {
                    return 0.0;
                }
                let (x, y) = (self.alpha_u * w.x, self.alpha_v * w.y);
                let xy2 = x * x + y * y;
                if xy2 == 0.0 {
                    return 1.0;
                }
                beckmann::g1_exact(xy2 / (w.z * w.z))
            }
        }
    }

    /// eval/pdf of a reflection sampled by visible normals, without the
    /// Fresnel factor: G₁(wi) G₁(wo) / G₁_visible(wi) (Heitz & d'Eon 2014,
    /// eq. 19: G₁(wo) when the two G₁ are the same function).
    #[inline]
    pub fn reflection_weight(&self, wi: Vec3, wo: Vec3, m: Vec3) -> f32 {
        let v = self.g1_visible(wi, m);
        if v > 0.0 {
            self.g1(wi, m) * self.g1(wo, m) / v
        } else {
            0.0
        }
    }

    /// Separable shadowing–masking G₁(wi) G₁(wo).
    #[inline]
    pub fn g(&self, wi: Vec3, wo: Vec3, m: Vec3) -> f32 {
        self.g1(wi, m) * self.g1(wo, m)
    }

    /// Density of `sample_visible` for `wi` (wi.z > 0):
    /// G₁(wi, m) max(0, wi·m) D(m) / wi.z (Heitz & d'Eon 2014, eq. 2), with
    /// the exact G₁ ([`Self::g1_visible`]).
    #[inline]
    pub fn pdf_visible(&self, wi: Vec3, m: Vec3) -> f32 {
        if wi.z <= 0.0 {
            return 0.0;
        }
        self.g1_visible(wi, m) * wi.dot(m).max(0.0) * self.d(m) / wi.z
    }

    /// A normal m drawn from the normals visible from `wi` (wi.z > 0), with
    /// density [`Self::pdf_visible`]: stretch wi to roughness 1, sample
    /// there, unstretch (Heitz & d'Eon 2014, §4).
    #[inline]
    pub fn sample_visible(&self, wi: Vec3, u: [f32; 2]) -> Vec3 {
        let (au, av) = (self.alpha_u, self.alpha_v);
        let vh = Vec3::new(au * wi.x, av * wi.y, wi.z).normalize();
        let nh = match self.kind {
            MicrofacetKind::Ggx => ggx::sample_visible_11(vh, u),
            MicrofacetKind::Beckmann => {
                // Slopes for vh turned into the x–z plane, turned back by φ.
                let (sx, sy) = beckmann::sample_visible_slopes_11(vh.z, u);
                let r = (vh.x * vh.x + vh.y * vh.y).sqrt();
                let (cos_phi, sin_phi) = if r > 0.0 {
                    (vh.x / r, vh.y / r)
                } else {
                    (1.0, 0.0)
                };
                let (x, y) = (cos_phi * sx - sin_phi * sy, sin_phi * sx + cos_phi * sy);
                // Slopes are −m_x/m_z, −m_y/m_z.
                Vec3::new(-x, -y, 1.0)
            }
        };
        Vec3::new(au * nh.x, av * nh.y, nh.z.max(1e-6)).normalize()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn all() -> Vec<MicrofacetDistribution> {
        let mut v = vec![];
        for kind in [MicrofacetKind::Beckmann, MicrofacetKind::Ggx] {
            for (au, av) in [(0.05, 0.05), (0.3, 0.3), (0.9, 0.9), (0.1, 0.5), (0.7, 0.2)] {
                v.push(MicrofacetDistribution::new(kind, au, av));
            }
        }
        v
    }

    #[test]
    fn ndf_projects_to_one() {
        // ∫ D(m) cos θ_m dω = 1, by a midpoint rule in (cos θ, φ);
        // cos θ = 1 − x² resolves the peak of small α.
        for dist in all() {
            let (nt, np) = (4000, 64);
            let mut sum = 0.0f64;
            for i in 0..nt {
                let x = (i as f64 + 0.5) / nt as f64;
                let c = 1.0 - x * x;
                let s = (1.0 - c * c).max(0.0).sqrt();
                for j in 0..np {
                    let phi = 2.0 * std::f64::consts::PI * (j as f64 + 0.5) / np as f64;
                    let m = Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, c as f32);
                    sum += dist.d(m) as f64 * c * 2.0 * x / nt as f64;
                }
            }
            sum *= 2.0 * std::f64::consts::PI / np as f64;
            assert!((sum - 1.0).abs() < 2e-3, "{dist:?}: {sum}");
        }
    }

    #[test]
    fn projected_visible_area_is_the_macrosurface_s() {
        // ∫ G₁(wi, m) max(0, wi·m) D(m) dω = wi.z (Heitz 2014, eq. 2): the
        // visible-normal density integrates to 1, so sampling loses nothing.
        for dist in all() {
            if dist.alpha_u.min(dist.alpha_v) < 0.1 {
                continue; // too narrow for this grid
            }
            for (theta, phi) in [(0.0f32, 0.0f32), (1.0, 0.3), (1.4, 2.0)] {
                let wi = Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                );
                let (nt, np) = (1500, 128);
                let mut sum = 0.0f64;
                for i in 0..nt {
                    let x = (i as f64 + 0.5) / nt as f64;
                    let c = 1.0 - x * x;
                    let s = (1.0 - c * c).max(0.0).sqrt();
                    for j in 0..np {
                        let p = 2.0 * std::f64::consts::PI * (j as f64 + 0.5) / np as f64;
                        let m = Vec3::new((s * p.cos()) as f32, (s * p.sin()) as f32, c as f32);
                        sum += dist.pdf_visible(wi, m) as f64 * 2.0 * x / nt as f64;
                    }
                }
                sum *= 2.0 * std::f64::consts::PI / np as f64;
                assert!((sum - 1.0).abs() < 2e-3, "{dist:?} θ {theta}: {sum}");
            }
        }
    }
}

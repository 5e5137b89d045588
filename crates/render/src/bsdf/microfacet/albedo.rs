//! Directional albedos of a rough dielectric interface: how much of the
//! light arriving from `wi` it reflects, and how much it lets through,
//! shadowing included. Rough plastic tabulates them for its coating.
//! Each is an expectation over the visible normals m (Heitz & d'Eon 2014,
//! eq. 19: the sampling weight of a visible-normal sample is F G₁(wo, m)),
//! integrated by Gauss–Legendre quadrature over the sampler's unit square,
//! as Mitsuba 3 does (`eval_reflectance`, `eval_transmittance`).

use super::MicrofacetDistribution;
use crate::bsdf::{fresnel_dielectric, reflect_about};
use crate::math::Vec3;

/// Gauss–Legendre nodes and weights on [−1, 1]: the roots of Pₙ by Newton's
/// method from Tricomi's initial guesses (Abramowitz & Stegun 25.4.29).
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    use std::f64::consts::PI;
    (0..n)
        .map(|i| {
            let mut x = -(PI * (i as f64 + 0.75) / (n as f64 + 0.5)).cos();
            let mut dp = 1.0;
            for _ in 0..100 {
                // P_n(x) and P_n'(x) by the three-term recurrence.
                let (mut p0, mut p1) = (1.0, x);
                for k in 2..=n {
                    let p2 = ((2 * k - 1) as f64 * x * p1 - (k - 1) as f64 * p0) / k as f64;
                    p0 = p1;
                    p1 = p2;
                }
                let p = if n == 0 { 1.0 } else { p1 };
                dp = n as f64 * (x * p - p0) / (x * x - 1.0);
                let step = p / dp;
                x -= step;
                if step.abs() < 1e-15 {
                    break;
                }
            }
            (x, 2.0 / ((1.0 - x * x) * dp * dp))
        })
        .collect()
}

impl MicrofacetDistribution {
    /// The mean of `f(m)` over the normals visible from `wi` at cosine
    /// `cos_i`, by an n×n Gauss–Legendre rule on the sampler's unit square.
    fn visible_mean(&self, cos_i: f32, n: usize, f: impl Fn(Vec3, Vec3) -> f32) -> f32 {
        let c = cos_i.clamp(1e-6, 1.0);
        let wi = Vec3::new((1.0 - c * c).max(0.0).sqrt(), 0.0, c);
        let rule = gauss_legendre(n);
        let mut sum = 0.0f64;
        for &(x, wx) in &rule {
            for &(y, wy) in &rule {
                let u = [(0.5 * (x + 1.0)) as f32, (0.5 * (y + 1.0)) as f32];
                let m = self.sample_visible(wi, u);
                sum += f(wi, m) as f64 * wx * wy * 0.25;
            }
        }
        sum as f32
    }

    /// ∫ F D G / (4 cos θ_i) dω_o, the share reflected off a dielectric of
    /// relative index `eta` at incidence cosine `cos_i`: the mean of
    /// F(wi·m) G₁(wo, m) over visible normals, wo the reflection of wi.
    pub fn dielectric_reflectance(&self, cos_i: f32, eta: f32, n: usize) -> f32 {
        self.visible_mean(cos_i, n, |wi, m| {
            let wo = reflect_about(wi, m);
            if wo.z <= 0.0 {
                return 0.0;
            }
            fresnel_dielectric(wi.dot(m), eta).0 * self.g1(wo, m)
        })
    }

    /// The share transmitted into a dielectric of relative index `eta` at
    /// incidence cosine `cos_i`: the mean of (1 − F(wi·m)) G₁(wt, m) over
    /// visible normals, wt the refraction of wi through m. Less than one
    /// minus the reflectance: shadowing on either path loses light.
    pub fn dielectric_transmittance(&self, cos_i: f32, eta: f32, n: usize) -> f32 {
        self.visible_mean(cos_i, n, |wi, m| {
            let im = wi.dot(m);
            let (f, cos_t, eta_it) = fresnel_dielectric(im, eta);
            if f >= 1.0 {
                return 0.0;
            }
            // Refract about m (Walter et al. 2007, eq. 40).
            let eta_ti = 1.0 / eta_it;
            let wt = m * (im * eta_ti + cos_t) - wi * eta_ti;
            if wt.z * wi.z >= 0.0 {
                return 0.0;
            }
            (1.0 - f) * self.g1(wt, m)
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::bsdf::MicrofacetKind;

    #[test]
    fn gauss_legendre_integrates_polynomials_exactly() {
        for n in [1, 4, 32, 128] {
            let rule = gauss_legendre(n);
            let w: f64 = rule.iter().map(|r| r.1).sum();
            assert!((w - 2.0).abs() < 1e-12, "n {n}: Σw {w}");
            // ∫ x^(2n−2) dx over [−1, 1] = 2/(2n − 1).
            let k = 2 * n - 2;
            let s: f64 = rule.iter().map(|&(x, w)| w * x.powi(k as i32)).sum();
            assert!((s - 2.0 / (k as f64 + 1.0)).abs() < 1e-10, "n {n}: {s}");
        }
    }

    #[test]
    fn a_smooth_interface_reflects_and_transmits_by_fresnel() {
        // Nearly smooth, both distributions: R = F, T = 1 − F.
        for kind in [MicrofacetKind::Beckmann, MicrofacetKind::Ggx] {
            let d = MicrofacetDistribution::isotropic(kind, 1e-3);
            for cos_i in [1.0f32, 0.7, 0.3] {
                let f = fresnel_dielectric(cos_i, 1.5).0;
                let r = d.dielectric_reflectance(cos_i, 1.5, 16);
                let t = d.dielectric_transmittance(cos_i, 1.5, 16);
                assert!((r - f).abs() < 1e-3, "{kind:?} {cos_i}: R {r} vs {f}");
                assert!((t - (1.0 - f)).abs() < 1e-3, "{kind:?} {cos_i}: T {t}");
            }
        }
    }
}

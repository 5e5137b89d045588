//! The GGX (Trowbridge–Reitz) microfacet distribution, isotropic, with the
//! separable Smith shadowing term and visible-normal sampling (Heitz 2018,
//! "Sampling the GGX Distribution of Visible Normals", JCGT 7(4)), as
//! Mitsuba 3's `microfacet.h` uses by default.

use std::f32::consts::PI;

use super::{fresnel_dielectric, reflect_about};
use crate::math::Vec3;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ggx {
    pub alpha: f32,
}

impl Ggx {
    /// D(m) = 1 / (π α² cos⁴θ (1 + tan²θ / α²)²); zero below the surface.
    #[inline]
    pub fn d(&self, m: Vec3) -> f32 {
        if m.z <= 0.0 {
            return 0.0;
        }
        let a2 = self.alpha * self.alpha;
        let cos2 = m.z * m.z;
        let t = (m.x * m.x + m.y * m.y) / a2 + cos2;
        1.0 / (PI * a2 * t * t)
    }

    /// Smith's G₁(w, m) = 2 / (1 + √(1 + α² tan²θ)), zero when w and m lie
    /// on different sides (Walter et al. 2007, eq. 34).
    #[inline]
    pub fn g1(&self, w: Vec3, m: Vec3) -> f32 {
        if w.dot(m) * w.z <= 0.0 {
            return 0.0;
        }
        let cos2 = w.z * w.z;
        if cos2 >= 1.0 {
            return 1.0;
        }
        let tan2 = (1.0 - cos2) / cos2;
        2.0 / (1.0 + (1.0 + self.alpha * self.alpha * tan2).sqrt())
    }

    /// Separable shadowing–masking G₁(wi) G₁(wo).
    #[inline]
    pub fn g(&self, wi: Vec3, wo: Vec3, m: Vec3) -> f32 {
        self.g1(wi, m) * self.g1(wo, m)
    }

    /// Density of `sample_visible` for `wi` (wi.z > 0): G₁(wi, m) max(0, wi·m) D(m) / wi.z.
    #[inline]
    pub fn pdf_visible(&self, wi: Vec3, m: Vec3) -> f32 {
        if wi.z <= 0.0 {
            return 0.0;
        }
        self.g1(wi, m) * wi.dot(m).max(0.0) * self.d(m) / wi.z
    }

    /// A normal m drawn from the normals visible from `wi` (wi.z > 0),
    /// Heitz 2018, listing 1.
    #[inline]
    pub fn sample_visible(&self, wi: Vec3, u: [f32; 2]) -> Vec3 {
        let a = self.alpha;
        // Stretch to the hemisphere configuration.
        let vh = Vec3::new(a * wi.x, a * wi.y, wi.z).normalize();
        let lensq = vh.x * vh.x + vh.y * vh.y;
        let t1 = if lensq > 0.0 {
            Vec3::new(-vh.y, vh.x, 0.0) / lensq.sqrt()
        } else {
            Vec3::new(1.0, 0.0, 0.0)
        };
        let t2 = vh.cross(t1);
        // A point on the projected area, warped towards the visible half disk.
        let r = u[0].sqrt();
        let phi = 2.0 * PI * u[1];
        let p1 = r * phi.cos();
        let mut p2 = r * phi.sin();
        let s = 0.5 * (1.0 + vh.z);
        p2 = (1.0 - s) * (1.0 - p1 * p1).max(0.0).sqrt() + s * p2;
        let nh = t1 * p1 + t2 * p2 + vh * (1.0 - p1 * p1 - p2 * p2).max(0.0).sqrt();
        // Unstretch.
        Vec3::new(a * nh.x, a * nh.y, nh.z.max(1e-6)).normalize()
    }
}

impl Ggx {
    /// Directional albedo of microfacet reflection off a dielectric of
    /// relative index `eta`, ∫ F D G / (4 cos θ_i) dω_o at incidence
    /// cosine `cos_i`: the mean of F(wi·m) G₁(wo, m) over visible normals m
    /// (the sampling weight of Heitz 2018, eq. 19), on an n×n grid of
    /// stratified midpoints.
    pub fn dielectric_albedo(&self, cos_i: f32, eta: f32, n: usize) -> f32 {
        let c = cos_i.clamp(1e-6, 1.0);
        let wi = Vec3::new((1.0 - c * c).max(0.0).sqrt(), 0.0, c);
        let mut sum = 0.0f64;
        for i in 0..n {
            for j in 0..n {
                let u = [(i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32];
                let m = self.sample_visible(wi, u);
                let wo = reflect_about(wi, m);
                if wo.z > 0.0 {
                    sum += (fresnel_dielectric(wi.dot(m), eta).0 * self.g1(wo, m)) as f64;
                }
            }
        }
        (sum / (n * n) as f64) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ndf_projects_to_one() {
        // ∫ D(m) cos θ_m dω = 1, by a midpoint rule in (cos θ, φ).
        for alpha in [0.05f32, 0.3, 0.9] {
            let g = Ggx { alpha };
            let n = 4000;
            let mut sum = 0.0f64;
            for i in 0..n {
                // Substitute cos θ = 1 − x² to resolve the peak of small α.
                let x = (i as f64 + 0.5) / n as f64;
                let c = 1.0 - x * x;
                let m = Vec3::new((1.0 - c * c).max(0.0).sqrt() as f32, 0.0, c as f32);
                sum += g.d(m) as f64 * c * 2.0 * x * (1.0 / n as f64) * 2.0 * std::f64::consts::PI;
            }
            assert!((sum - 1.0).abs() < 2e-3, "α {alpha}: {sum}");
        }
    }
}

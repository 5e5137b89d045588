//! The Beckmann distribution's pieces, written for the stretched
//! configuration where the roughness is 1: the caller stretches and
//! unstretches (Heitz & d'Eon 2014, "Importance Sampling Microfacet-Based
//! BSDFs using the Distribution of Visible Normals", EGSR, §4).

use std::f64::consts::PI;

use super::erf::{erf, erfinv};

/// D(m)·(π α_u α_v) as a function of s = (m_x/α_u)² + (m_y/α_v)² and
/// c² = m_z², for a unit m: exp(−s/c²) / c⁴ (Walter et al. 2007, eq. 25).
#[inline]
pub fn d_unnormalised(s: f32, c2: f32) -> f32 {
    (-s / c2).exp() / (c2 * c2)
}

/// Smith's G₁ for t² = α² tan²θ, by the rational approximation in
/// a = 1/(α tan θ) that Walter et al. 2007 give after eq. 27 (relative
/// error below 0.35 %): the one Mitsuba 3 evaluates, so the two renderers'
/// BSDF values agree.
#[inline]
pub fn g1(t2: f32) -> f32 {
    let a = 1.0 / t2.sqrt();
    if a >= 1.6 {
        return 1.0;
    }
    let a2 = a * a;
    (3.535 * a + 2.181 * a2) / (1.0 + 2.276 * a + 2.577 * a2)
}

/// Smith's exact G₁ = 1 / (1 + Λ) with Λ(a) = (erf(a) − 1)/2 +
/// e^{−a²}/(2a√π), a = 1/(α tan θ) (Walter et al. 2007, eq. 27): the
/// normalisation of the visible-normal density that the sampler below
/// draws from.
#[inline]
pub fn g1_exact(t2: f32) -> f32 {
    let a = 1.0 / (t2 as f64).sqrt();
    let lambda = 0.5 * (erf(a) - 1.0) + (-a * a).exp() / (2.0 * a * PI.sqrt());
    (1.0 / (1.0 + lambda)) as f32
}

/// Slopes (x̃, ỹ) of a normal visible from a direction of polar cosine
/// `cos_i` in the x–z plane (x > 0), on the surface of roughness 1. ỹ is a
/// normal variate of variance ½; x̃ has the density ∝ (cot θ − x̃) e^{−x̃²}
/// on x̃ < cot θ (Heitz & d'Eon 2014, eq. 12), inverted by Newton's method
/// in the variable z = erf(x̃), where its CDF
/// C(z) = 1 + z + tan θ/√π · e^{−erf⁻¹(z)²} is nearly linear, starting from
/// the exact inverse at grazing incidence (W. Jakob 2014, "An Improved
/// Visible Normal Sampling Routine for the Beckmann Distribution"). The
/// bracket [−1, erf(cot θ)] keeps each step safe where C is flat.
pub fn sample_visible_slopes_11(cos_i: f32, u: [f32; 2]) -> (f32, f32) {
    let c = (cos_i as f64).clamp(1e-7, 1.0);
    let tan = (1.0 - c * c).max(0.0).sqrt() / c;
    let cot = 1.0 / tan;
    // Sample numbers away from 0 and 1, where erf⁻¹ is infinite.
    let (u0, u1) = (
        (u[0] as f64).clamp(1e-7, 1.0 - 1e-7),
        (u[1] as f64).clamp(1e-7, 1.0 - 1e-7),
    );
    let k = tan / PI.sqrt();
    let cdf = |z: f64| {
        let x = erfinv(z);
        (1.0 + z + k * (-x * x).exp(), x)
    };
    let (mut lo, mut hi) = (-1.0, erf(cot));
    let target = u0 * cdf(hi).0;
    // Jakob 2014: the exact solution for θ = π/2, C = e^{−x̃²}.
    let mut z = hi - (hi + 1.0) * erf((-u0.ln()).sqrt());
    for _ in 0..20 {
        let (value, x) = cdf(z);
        let residual = value - target;
        // Converged well past single precision.
        if residual.abs() < 1e-9 * target.max(1e-3) {
            break;
        }
        if residual > 0.0 {
            hi = z;
        } else {
            lo = z;
        }
        let slope = 1.0 - x * tan;
        let mut next = z - residual / slope;
        if !(next > lo && next < hi) {
            next = 0.5 * (lo + hi);
        }
        z = next;
    }
    let x = erfinv(z);
    let y = erfinv(2.0 * u1 - 1.0);
    (x as f32, y as f32)
}

/// C(cot θ) in x̃: the slope density's normalisation, ∫ (cot θ − x̃)⁺
/// e^{−x̃²} dx̃, times 2 tan θ/√π (for tests).
#[cfg(test)]
pub fn slope_cdf_total(cos_i: f64) -> f64 {
    let tan = (1.0 - cos_i * cos_i).sqrt() / cos_i;
    let cot = 1.0 / tan;
    1.0 + erf(cot) + tan / PI.sqrt() * (-cot * cot).exp()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn walters_g1_is_within_its_bound_of_the_exact_one() {
        for i in 1..400 {
            let t2 = (i as f32 / 40.0).powi(2);
            let (a, e) = (g1(t2), g1_exact(t2));
            assert!(
                (a - e).abs() <= 3.6e-3 * e,
                "α tan θ {}: {a} vs {e}",
                t2.sqrt()
            );
        }
    }

    #[test]
    fn slope_sampler_inverts_its_cdf() {
        // The sampled x̃ has C(x̃) = u·C(cot θ) for each u: checked by
        // evaluating the CDF in x̃ directly.
        for cos_i in [1.0f64, 0.9, 0.5, 0.1, 0.01] {
            let tan = (1.0 - cos_i * cos_i).sqrt() / cos_i;
            let total = slope_cdf_total(cos_i);
            for i in 1..50 {
                let u = i as f32 / 50.0;
                let (x, _) = sample_visible_slopes_11(cos_i as f32, [u, 0.5]);
                let x = x as f64;
                let c = 1.0 + erf(x) + tan / PI.sqrt() * (-x * x).exp();
                assert!(
                    (c / total - u as f64).abs() < 1e-5,
                    "cos {cos_i}, u {u}: x {x}, C {}",
                    c / total
                );
            }
        }
    }
}

//! Fresnel equations for unpolarised light.

/// Reflectance at a dielectric interface, and the refracted direction's
/// cosine. `cos_i` is the cosine of the incident direction with the normal
/// (positive on the outside), `eta` = η_inside / η_outside. Returns
/// (F, cos θ_t signed opposite to cos_i, η_ratio of the side entered over the
/// side left). Total internal reflection gives F = 1 and cos θ_t = 0.
#[inline]
pub fn fresnel_dielectric(cos_i: f32, eta: f32) -> (f32, f32, f32) {
    let outside = cos_i >= 0.0;
    let eta_it = if outside { eta } else { 1.0 / eta };
    let ci = cos_i.abs();
    // Snell: sin²θ_t = sin²θ_i / η².
    let sin2_t = (1.0 - ci * ci).max(0.0) / (eta_it * eta_it);
    if sin2_t >= 1.0 {
        return (1.0, 0.0, eta_it);
    }
    let ct = (1.0 - sin2_t).sqrt();
    let r_s = (ci - eta_it * ct) / (ci + eta_it * ct);
    let r_p = (eta_it * ci - ct) / (eta_it * ci + ct);
    let f = 0.5 * (r_s * r_s + r_p * r_p);
    (f, if outside { -ct } else { ct }, eta_it)
}

/// Reflectance of a conductor with complex index η + iκ (relative to the
/// outside medium) at incidence cosine `cos_i` ≥ 0: the exact unpolarised
/// formula (e.g. pbrt-v4 §9.3.6, evaluated with complex arithmetic).
#[inline]
pub fn fresnel_conductor(cos_i: f32, eta: f32, k: f32) -> f32 {
    let ci = cos_i.clamp(0.0, 1.0) as f64;
    let (eta, k) = (eta as f64, k as f64);
    // Complex sqrt of (η + iκ)² − sin²θ_i gives η cos θ_t.
    let sin2 = 1.0 - ci * ci;
    let (re, im) = (eta * eta - k * k - sin2, 2.0 * eta * k);
    let modulus = (re * re + im * im).sqrt();
    let a = ((modulus + re) * 0.5).max(0.0).sqrt();
    let b = ((modulus - re) * 0.5).max(0.0).sqrt() * if im < 0.0 { -1.0 } else { 1.0 };
    // r_s = (cos_i − (a + ib)) / (cos_i + (a + ib)).
    let rs = ((ci - a).powi(2) + b * b) / ((ci + a).powi(2) + b * b);
    // r_p = ((η+iκ)² cos_i − (a + ib)) / ((η+iκ)² cos_i + (a + ib)).
    let (e2r, e2i) = (eta * eta - k * k, 2.0 * eta * k);
    let (nr, ni) = (e2r * ci - a, e2i * ci - b);
    let (dr, di) = (e2r * ci + a, e2i * ci + b);
    let rp = (nr * nr + ni * ni) / (dr * dr + di * di);
    (0.5 * (rs + rp)) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dielectric_limits() {
        // Normal incidence: ((η − 1)/(η + 1))².
        let (f, ct, _) = fresnel_dielectric(1.0, 1.5);
        assert!((f - 0.04).abs() < 1e-6 && (ct + 1.0).abs() < 1e-6);
        // Grazing: 1. Inside beyond the critical angle: total reflection.
        assert!((fresnel_dielectric(0.0, 1.5).0 - 1.0).abs() < 1e-6);
        assert_eq!(fresnel_dielectric(-0.5, 1.5).0, 1.0);
        // Brewster's angle: r_p = 0, F = r_s²/2.
        let cb = (1.5f32).atan().cos();
        let (fb, _, _) = fresnel_dielectric(cb, 1.5);
        assert!(fb < 0.08 && fb > 0.07, "{fb}");
    }

    #[test]
    fn conductor_reduces_to_dielectric_without_absorption() {
        for c in [1.0, 0.8, 0.3, 0.05] {
            let d = fresnel_dielectric(c, 1.7).0;
            let m = fresnel_conductor(c, 1.7, 0.0);
            assert!((d - m).abs() < 1e-5, "{c}: {d} vs {m}");
        }
        // Normal incidence: ((η−1)² + κ²)/((η+1)² + κ²).
        let (eta, k) = (0.27, 2.78);
        let r0 = ((eta - 1.0f32).powi(2) + k * k) / ((eta + 1.0f32).powi(2) + k * k);
        assert!((fresnel_conductor(1.0, eta, k) - r0).abs() < 1e-6);
    }
}

//! pbrt-v4's visible-wavelength density (Pharr, Jakob & Humphreys,
//! *Physically Based Rendering*, 4th ed., §4.6.5): a sech² bump centred at
//! 538 nm that follows the CIE observers' combined sensitivity, with an
//! analytic inverse CDF. Constants as pbrt-v4's `SampleVisibleWavelengths`
//! and `VisibleWavelengthsPDF` (../shared/vision-equations.md §8).

use scotopia_color::{LAMBDA_MAX, LAMBDA_MIN};

/// p(λ) = 0.0039398042 / cosh²(0.0072 (λ − 538)) on [360, 830] nm.
#[inline]
pub fn visible_pdf(lambda: f32) -> f32 {
    if !(LAMBDA_MIN..=LAMBDA_MAX).contains(&lambda) {
        return 0.0;
    }
    // 1/cosh²x = 4y/(1 + y)² with y = e^(−2|x|): one `expf`, where
    // `coshf` is two and a reciprocal.
    let y = (-2.0 * 0.0072 * (lambda - 538.0).abs()).exp();
    0.003_939_804 * 4.0 * y / ((1.0 + y) * (1.0 + y))
}

/// λ = 538 − 138.888889 · atanh(0.85691062 − 1.82750197 u), u ∈ [0, 1).
#[inline]
pub fn sample_visible(u: f32) -> f32 {
    (538.0 - 138.888_89 * (0.856_910_6 - 1.827_502 * u).atanh()).clamp(LAMBDA_MIN, LAMBDA_MAX)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn density_integrates_to_one_and_inverts_its_cdf() {
        let n = 47_000;
        let h = (LAMBDA_MAX - LAMBDA_MIN) as f64 / n as f64;
        let mut cdf = 0.0f64;
        for i in 0..n {
            let l = LAMBDA_MIN as f64 + (i as f64 + 0.5) * h;
            cdf += visible_pdf(l as f32) as f64 * h;
            // The sampler maps u = CDF(λ) back to λ.
            if i % 4700 == 4699 {
                let back = sample_visible(cdf as f32) as f64;
                assert!((back - (l + 0.5 * h)).abs() < 0.05, "{l}: {back}");
            }
        }
        assert!((cdf - 1.0).abs() < 1e-4, "{cdf}");
        assert_eq!(sample_visible(0.0), LAMBDA_MIN);
        assert!(sample_visible(0.999_999) <= LAMBDA_MAX);
        assert_eq!(visible_pdf(900.0), 0.0);
        // The same function as pbrt-v4's form with cosh.
        for l in [360.0f32, 400.0, 538.0, 600.0, 700.0, 830.0] {
            let c = (0.0072 * (l - 538.0)).cosh();
            let sech2 = 0.003_939_804 / (c * c);
            assert!((visible_pdf(l) / sech2 - 1.0).abs() < 1e-6, "{l}");
        }
    }
}

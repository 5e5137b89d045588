//! The spectrum of Jakob & Hanika 2019, "A Low-Dimensional Function Space for
//! Efficient Spectral Upsampling": a sigmoid of a quadratic polynomial in λ,
//! optionally scaled and multiplied by an illuminant.

use std::sync::Arc;

use super::Tabulated;
use crate::{LAMBDA_MAX, LAMBDA_MIN};

/// S(x) = ½ + x / (2√(1 + x²)), Jakob & Hanika 2019, eq. 3: maps ℝ onto (0, 1)
/// with algebraic (not exponential) tails, cheap and smooth.
#[inline]
pub fn sigmoid(x: f32) -> f32 {
    if x.is_infinite() {
        return if x > 0.0 { 1.0 } else { 0.0 };
    }
    0.5 + x / (2.0 * (1.0 + x * x).sqrt())
}

/// Normalised wavelength t ∈ [0, 1] over 360–830 nm, the polynomial's variable.
/// Fitting in t rather than nm keeps the three coefficients of similar size.
#[inline]
pub fn normalised_lambda(lambda: f32) -> f32 {
    (lambda - LAMBDA_MIN) / (LAMBDA_MAX - LAMBDA_MIN)
}

/// scale · S(c₀t² + c₁t + c₂) · illuminant(λ).
#[derive(Debug, Clone, PartialEq)]
pub struct RgbSigmoid {
    pub coeffs: [f32; 3],
    pub scale: f32,
    /// For emission: the colour space's white illuminant, normalised to unit
    /// luminance-weighted mean (see `upsample`).
    pub illuminant: Option<Arc<Tabulated>>,
}

impl RgbSigmoid {
    /// The bare sigmoid-polynomial reflectance at `lambda`, in [0, 1].
    #[inline]
    pub fn reflectance(coeffs: &[f32; 3], lambda: f32) -> f32 {
        let t = normalised_lambda(lambda);
        sigmoid((coeffs[0] * t + coeffs[1]) * t + coeffs[2])
    }

    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        let v = self.scale * Self::reflectance(&self.coeffs, lambda);
        match &self.illuminant {
            Some(illuminant) => v * illuminant.eval(lambda),
            None => v,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sigmoid_limits_and_symmetry() {
        assert_eq!(sigmoid(0.0), 0.5);
        assert_eq!(sigmoid(f32::INFINITY), 1.0);
        assert_eq!(sigmoid(f32::NEG_INFINITY), 0.0);
        for x in [-1e3f32, -3.0, -0.1, 0.2, 7.0] {
            assert!((sigmoid(x) + sigmoid(-x) - 1.0).abs() < 1e-6);
            assert!(sigmoid(x) > 0.0 && sigmoid(x) < 1.0);
        }
    }
}

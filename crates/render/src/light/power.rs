//! Radiant and luminous power of emission spectra.

use scotopia_color::photometry::{integrate_observers, K_M};
use scotopia_color::{Spectrum, LAMBDA_MAX, LAMBDA_MIN};

/// Total power of a light, over 360–830 nm.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Power {
    /// Radiant power, W.
    pub watts: f64,
    /// Luminous flux, lm (K_m = 683 lm/W).
    pub lumens: f64,
}

impl Power {
    pub fn scaled(self, s: f64) -> Self {
        Self {
            watts: self.watts * s,
            lumens: self.lumens * s,
        }
    }
}

/// ∫ S dλ (W per unit of the geometric factor) and 683 ∫ S ȳ dλ (lm per
/// unit), by the trapezoid rule on the 1 nm grid merged with S's samples.
pub fn spectral_power(s: &Spectrum) -> Power {
    let mut nodes: Vec<f32> = (LAMBDA_MIN as u32..=LAMBDA_MAX as u32)
        .map(|l| l as f32)
        .collect();
    nodes.extend(
        s.breakpoints()
            .iter()
            .filter(|&&l| (LAMBDA_MIN..=LAMBDA_MAX).contains(&l)),
    );
    nodes.sort_by(f32::total_cmp);
    nodes.dedup();
    let watts = nodes
        .windows(2)
        .map(|w| 0.5 * (w[1] - w[0]) as f64 * (s.eval(w[0]) + s.eval(w[1])) as f64)
        .sum();
    Power {
        watts,
        lumens: K_M * integrate_observers(s)[1],
    }
}

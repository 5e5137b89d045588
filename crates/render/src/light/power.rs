//! Radiant and luminous power of emission spectra.

use scotopia_color::cie;
use scotopia_color::photometry::{integration_nodes, K_M};
use scotopia_color::Spectrum;

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
    // One trapezoid pass over the same nodes photometry integrates on.
    let nodes = integration_nodes(s);
    let at = |l: f32| {
        let v = s.eval(l) as f64;
        (v, v * cie::xyz_bar(l)[1] as f64)
    };
    let (mut watts, mut y) = (0.0, 0.0);
    let mut prev = (nodes[0], at(nodes[0]));
    for &l in &nodes[1..] {
        let f = at(l);
        let h = 0.5 * (l - prev.0) as f64;
        watts += h * (prev.1 .0 + f.0);
        y += h * (prev.1 .1 + f.1);
        prev = (l, f);
    }
    Power {
        watts,
        lumens: K_M * y,
    }
}

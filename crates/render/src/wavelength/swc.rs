//! Stratified wavelength clusters (Evans & McCool 1999, Graphics Interface,
//! pp. 42–49): K numbers stratified in [0, 1) pushed through one inverse
//! CDF, that of the mixture of the lights' spectra weighted by radiant
//! power, with a defensive share of the visible density. Each member's
//! marginal density is that mixture, so the cluster average is unbiased.
//!
//! Each light's spectrum enters as the eye sees it: times the visible
//! density (pbrt-v4's sech² bump over the observers' sensitivity), its
//! power weighed the same way (scotopia's refinement of Evans & McCool,
//! who sample the emitted spectrum). A warm lamp puts much of its power
//! between 700 and 830 nm, where X, Y, Z and V′ are all near zero; drawn
//! from the emitted spectrum, those members carry nothing to the image.
//! On the Cornell box at K = 4 this lowered the variance of X, Y, Z and
//! V′ by 27, 13, 46 and 32 % at the same cost (docs/performance.md).
//!
//! Fluorescence (scotopia's extension): light can reach the eye at
//! wavelengths no lamp emits, so each fluorescent material's emission
//! shape joins the mixture as a source of its own, weighted by the share
//! of the lights' power it would re-emit were all of it to fall on it,
//! r = ∫ p_lights(λi)·∫ F(λi → λo) dλo dλi (for the separable model
//! Q·∫ p_lights·e·λi·∫_{λo ≥ λi} η/λo dλo dλi, the Stokes loss included).
//! With R = Σ r the lights keep 1/(1 + R) of the (non-defensive) mixture
//! and each material r/(1 + R): a white paper with a little brightener
//! barely changes it, a black-light poster lit only in the UV (r near Q
//! times the Stokes factor) draws about 40 % of its wavelengths from the
//! paints' emission, where the eye sees.
//!
//! Every source is stratified within each cluster rather than chosen per
//! cluster: the strata run over the whole mixture's CDF, so a cluster of 4
//! under a black light carries about 2 UV and 2 emission wavelengths
//! instead of being all-UV or all-emission (that halves the variance of
//! what the eye sees on such scenes), and a street under sodium and LED
//! lamps gets members on the sodium lines and on the LED's band in the
//! same cluster. The mixture's inverse CDF is tabulated ([`InverseCdf`]):
//! a member costs one lookup and its density comes with it, where
//! choosing a light and inverting its piecewise-linear density took a
//! search, a square root and two divisions per member and the mixture's
//! density another search.

use scotopia_color::SampledWavelengths;

use super::inverse_cdf::{InverseCdf, CELLS};
use super::SpectralPdf;
use crate::bsdf::Fluorescent;
use crate::light::Light;

/// Share of the mixture given to the visible density, so p(λ) > 0
/// wherever the image can have energy (reflected RGB emitters,
/// environment maps, fluorescence); scotopia's choice.
pub const DEFENSIVE_SHARE: f32 = 0.1;

/// The mixture of densities weighted by their powers; `None` when there
/// are none or no power.
fn mixture_by_power(parts: &[(SpectralPdf, f32)]) -> Option<SpectralPdf> {
    let total: f32 = parts.iter().map(|(_, w)| w).sum();
    if !(total > 0.0 && total.is_finite()) {
        return None;
    }
    let weighted: Vec<(f32, &SpectralPdf)> = parts.iter().map(|(p, w)| (w / total, p)).collect();
    SpectralPdf::mixture(&weighted)
}

#[derive(Debug, Clone, PartialEq)]
pub struct Swc {
    /// The tabulated inverse CDF of the whole mixture.
    table: InverseCdf,
}

impl Swc {
    /// `power[i]`: light i's radiant power, W.
    pub fn new(lights: &[Light], power: &[f32], fluorescent: &[&Fluorescent]) -> Self {
        // Each light's spectrum as emitted (for the fluorescent materials'
        // shares) and as seen (for sampling), with their powers.
        let mut emitted = Vec::new();
        let mut seen = Vec::new();
        for (l, &watts) in lights.iter().zip(power) {
            if !(watts > 0.0 && watts.is_finite()) {
                continue;
            }
            let (Some(all), Some(visible)) = (
                SpectralPdf::new(l.spectrum()),
                SpectralPdf::seen(l.spectrum()),
            ) else {
                continue;
            };
            let seen_watts = watts as f64 * visible.integral() / all.integral();
            emitted.push((all, watts));
            seen.push((visible, seen_watts as f32));
        }
        let lights_mix = mixture_by_power(&emitted);
        let seen_mix = mixture_by_power(&seen);
        let (mut emitters, mut ratios) = (Vec::new(), Vec::new());
        if let Some(m) = &lights_mix {
            for f in fluorescent {
                // r = ∫ p_lights(λ)·∫F(λ → λo) dλo dλ, at 1 nm.
                let r: f32 = (360..830)
                    .map(|l| {
                        let l = l as f32 + 0.5;
                        m.pdf(l) * f.reemitted(l)
                    })
                    .sum();
                if r > 0.0 {
                    emitters.push(f.emission_density().clone());
                    ratios.push(r);
                }
            }
        }
        let light_share = 1.0 / (1.0 + ratios.iter().sum::<f32>());
        let mut parts: Vec<(f32, &SpectralPdf)> = Vec::new();
        if let Some(m) = &seen_mix {
            parts.push((light_share, m));
        }
        for (e, r) in emitters.iter().zip(&ratios) {
            parts.push((r * light_share, e));
        }
        let sources = SpectralPdf::mixture(&parts);
        // The visible density, linear between whole nanometres: only the
        // table's edges come from it, and the table is its own density.
        let visible = SpectralPdf::visible();
        let total = match &sources {
            Some(m) => {
                SpectralPdf::mixture(&[(1.0 - DEFENSIVE_SHARE, m), (DEFENSIVE_SHARE, &visible)])
            }
            None => None,
        }
        .unwrap_or(visible);
        Self {
            table: InverseCdf::new(&total, CELLS),
        }
    }

    /// The density the estimator divides by (per nm): the table's.
    pub fn pdf(&self, lambda: f32) -> f32 {
        self.table.pdf(lambda)
    }

    /// A cluster: member k at (k + u)/K through the mixture's inverse CDF
    /// (`_u_choice` is not needed: no source is chosen per cluster).
    #[inline]
    pub fn sample<const K: usize>(&self, _u_choice: f32, u: f32) -> SampledWavelengths<K> {
        let (lambda, pdf) = self.table.sample_strata::<K>(u);
        SampledWavelengths::new(lambda, pdf)
    }

    /// The table's probability mass in [a, b] (tests).
    #[cfg(test)]
    pub(super) fn mass_between(&self, a: f32, b: f32) -> f64 {
        self.table.mass_between(a, b)
    }
}

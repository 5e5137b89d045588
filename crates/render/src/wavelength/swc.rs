//! Stratified wavelength clusters (Evans & McCool 1999, Graphics Interface,
//! pp. 42–49): the cluster is drawn from one light's spectrum, chosen by
//! radiant power, and weighed by the mixture density of all lights.

use scotopia_color::SampledWavelengths;

use super::{sample_visible, visible_pdf, SpectralPdf};
use crate::light::Light;
use crate::sampling::distribution::Distribution1D;

/// Share of clusters drawn from the visible density instead of a light,
/// so p(λ) > 0 wherever the image can have energy (reflected RGB
/// emitters, environment maps, fluorescence); scotopia's choice.
pub const DEFENSIVE_SHARE: f32 = 0.1;

#[derive(Debug, Clone, PartialEq)]
pub struct Swc {
    /// Spectral densities of the lights with power.
    pdfs: Vec<SpectralPdf>,
    /// Choice among `pdfs`, by radiant power.
    choice: Distribution1D,
    /// Σ P(l)·p_l(λ), tabulated once on the union of the lights' nodes.
    lights: Option<SpectralPdf>,
    /// Probability of drawing from the visible density instead.
    defensive: f32,
}

impl Swc {
    /// `power[i]`: light i's radiant power, W.
    pub fn new(lights: &[Light], power: &[f32]) -> Self {
        let (pdfs, power): (Vec<SpectralPdf>, Vec<f32>) = lights
            .iter()
            .zip(power)
            .filter_map(|(l, &watts)| {
                (watts > 0.0 && watts.is_finite())
                    .then(|| SpectralPdf::new(l.spectrum()).map(|p| (p, watts)))
                    .flatten()
            })
            .unzip();
        let choice = Distribution1D::new(power);
        let parts: Vec<(f32, &SpectralPdf)> = pdfs
            .iter()
            .enumerate()
            .map(|(i, p)| (choice.probability(i), p))
            .collect();
        let lights = SpectralPdf::mixture(&parts);
        Self {
            lights,
            defensive: if pdfs.is_empty() {
                1.0
            } else {
                DEFENSIVE_SHARE
            },
            choice,
            pdfs,
        }
    }

    /// The mixture density the estimator divides by.
    #[inline]
    pub fn pdf(&self, lambda: f32) -> f32 {
        let lights = self.lights.as_ref().map_or(0.0, |m| m.pdf(lambda));
        (1.0 - self.defensive) * lights + self.defensive * visible_pdf(lambda)
    }

    pub fn sample<const K: usize>(&self, u_choice: f32, u: f32) -> SampledWavelengths<K> {
        let strata = |k: usize| (k as f32 + u) / K as f32;
        let lambda: [f32; K] = if u_choice < self.defensive {
            std::array::from_fn(|k| sample_visible(strata(k)))
        } else {
            let v = (u_choice - self.defensive) / (1.0 - self.defensive);
            match self.choice.sample_discrete(v) {
                Some((i, _, _)) => std::array::from_fn(|k| self.pdfs[i].sample(strata(k))),
                None => std::array::from_fn(|k| sample_visible(strata(k))),
            }
        };
        SampledWavelengths::new(lambda, lambda.map(|l| self.pdf(l)))
    }
}

//! Stratified wavelength clusters (Evans & McCool 1999, Graphics Interface,
//! pp. 42–49): the cluster is drawn from one light's spectrum, chosen by
//! radiant power, and weighed by the mixture density of all lights.
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
//! times the Stokes factor) draws about 40 % of its clusters from the
//! paints' emission, where the eye sees.

use scotopia_color::SampledWavelengths;

use super::{sample_visible, visible_pdf, SpectralPdf};
use crate::bsdf::Fluorescent;
use crate::light::Light;
use crate::sampling::distribution::Distribution1D;

/// Share of clusters drawn from the visible density instead of a light,
/// so p(λ) > 0 wherever the image can have energy (reflected RGB
/// emitters, environment maps, fluorescence); scotopia's choice.
pub const DEFENSIVE_SHARE: f32 = 0.1;

#[derive(Debug, Clone, PartialEq)]
pub struct Swc {
    /// Spectral densities of the lights with power, then of the
    /// fluorescent materials' emission.
    pdfs: Vec<SpectralPdf>,
    /// Choice among `pdfs`: lights by radiant power, materials by the
    /// power they would re-emit.
    choice: Distribution1D,
    /// Σ P(source)·p_source(λ), tabulated once on the union of the nodes.
    lights: Option<SpectralPdf>,
    /// Probability of drawing from the visible density instead.
    defensive: f32,
}

impl Swc {
    /// `power[i]`: light i's radiant power, W.
    pub fn new(lights: &[Light], power: &[f32], fluorescent: &[&Fluorescent]) -> Self {
        let (mut pdfs, mut weights): (Vec<SpectralPdf>, Vec<f32>) = lights
            .iter()
            .zip(power)
            .filter_map(|(l, &watts)| {
                (watts > 0.0 && watts.is_finite())
                    .then(|| SpectralPdf::new(l.spectrum()).map(|p| (p, watts)))
                    .flatten()
            })
            .unzip();
        let total: f32 = weights.iter().sum();
        if total > 0.0 {
            let lights_only = Distribution1D::new(weights.clone());
            let parts: Vec<(f32, &SpectralPdf)> = pdfs
                .iter()
                .enumerate()
                .map(|(i, p)| (lights_only.probability(i), p))
                .collect();
            let mix = SpectralPdf::mixture(&parts);
            for f in fluorescent {
                // r = ∫ p_lights(λ)·∫F(λ → λo) dλo dλ, at 1 nm.
                let r: f32 = mix.as_ref().map_or(0.0, |m| {
                    (360..830)
                        .map(|l| {
                            let l = l as f32 + 0.5;
                            m.pdf(l) * f.reemitted(l)
                        })
                        .sum::<f32>()
                });
                if r > 0.0 {
                    pdfs.push(f.emission_density().clone());
                    weights.push(r * total);
                }
            }
        }
        let choice = Distribution1D::new(weights);
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

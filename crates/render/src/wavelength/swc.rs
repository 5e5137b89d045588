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
//! times the Stokes factor) draws about 40 % of its wavelengths from the
//! paints' emission, where the eye sees.
//!
//! The two shares are stratified within each cluster rather than chosen
//! per cluster: member k's stratum (k + u)/K falls in the lights' share
//! or the materials', so a cluster of 4 under a black light carries about
//! 2 UV and 2 emission wavelengths instead of being all-UV or
//! all-emission; that halves the variance of what the eye sees on such
//! scenes. The light is still chosen once per cluster by power and the
//! lights' members are stratified over its spectrum (Evans & McCool);
//! without fluorescence nothing changes. Each member's marginal density
//! is the same mixture, so the estimator's p(λ) is unchanged.

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
    /// Spectral densities of the lights with power.
    lights: Vec<SpectralPdf>,
    /// Choice of the light, by radiant power.
    light_choice: Option<Distribution1D>,
    /// Spectral densities of the fluorescent materials' emission.
    emitters: Vec<SpectralPdf>,
    /// Choice among `emitters`, by the power each would re-emit.
    emitter_choice: Option<Distribution1D>,
    /// The lights' share of the non-defensive mixture, 1/(1 + R).
    light_share: f32,
    /// Σ P(source)·p_source(λ) over lights and emitters, tabulated once.
    mixture: Option<SpectralPdf>,
    /// Probability of drawing from the visible density instead.
    defensive: f32,
}

impl Swc {
    /// `power[i]`: light i's radiant power, W.
    pub fn new(lights: &[Light], power: &[f32], fluorescent: &[&Fluorescent]) -> Self {
        let (light_pdfs, watts): (Vec<SpectralPdf>, Vec<f32>) = lights
            .iter()
            .zip(power)
            .filter_map(|(l, &watts)| {
                (watts > 0.0 && watts.is_finite())
                    .then(|| SpectralPdf::new(l.spectrum()).map(|p| (p, watts)))
                    .flatten()
            })
            .unzip();
        let light_choice = (!light_pdfs.is_empty()).then(|| Distribution1D::new(watts));
        let lights_mix = light_choice.as_ref().and_then(|c| {
            let parts: Vec<(f32, &SpectralPdf)> = light_pdfs
                .iter()
                .enumerate()
                .map(|(i, p)| (c.probability(i), p))
                .collect();
            SpectralPdf::mixture(&parts)
        });
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
        let big_r: f32 = ratios.iter().sum();
        let light_share = 1.0 / (1.0 + big_r);
        let emitter_choice = (!emitters.is_empty()).then(|| Distribution1D::new(ratios.clone()));
        let mut parts: Vec<(f32, &SpectralPdf)> = Vec::new();
        if let Some(m) = &lights_mix {
            parts.push((light_share, m));
        }
        for (e, r) in emitters.iter().zip(&ratios) {
            parts.push((r * light_share, e));
        }
        let mixture = SpectralPdf::mixture(&parts);
        Self {
            defensive: if light_pdfs.is_empty() {
                1.0
            } else {
                DEFENSIVE_SHARE
            },
            lights: light_pdfs,
            light_choice,
            emitters,
            emitter_choice,
            light_share,
            mixture,
        }
    }

    /// The mixture density the estimator divides by.
    #[inline]
    pub fn pdf(&self, lambda: f32) -> f32 {
        let sources = self.mixture.as_ref().map_or(0.0, |m| m.pdf(lambda));
        (1.0 - self.defensive) * sources + self.defensive * visible_pdf(lambda)
    }

    pub fn sample<const K: usize>(&self, u_choice: f32, u: f32) -> SampledWavelengths<K> {
        let strata = |k: usize| (k as f32 + u) / K as f32;
        let light = (u_choice >= self.defensive)
            .then(|| {
                let v = (u_choice - self.defensive) / (1.0 - self.defensive);
                self.light_choice.as_ref()?.sample_discrete(v)
            })
            .flatten();
        let lambda: [f32; K] = match light {
            None => std::array::from_fn(|k| sample_visible(strata(k))),
            Some((i, _, _)) => std::array::from_fn(|k| {
                let s = strata(k);
                match &self.emitter_choice {
                    Some(c) if s >= self.light_share => {
                        let v = (s - self.light_share) / (1.0 - self.light_share);
                        match c.sample_discrete(v.min(1.0 - f32::EPSILON)) {
                            Some((m, _, rest)) => self.emitters[m].sample(rest),
                            None => self.lights[i].sample(s),
                        }
                    }
                    _ => self.lights[i].sample(s / self.light_share),
                }
            }),
        };
        SampledWavelengths::new(lambda, lambda.map(|l| self.pdf(l)))
    }
}

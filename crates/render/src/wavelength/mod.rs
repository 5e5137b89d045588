//! Choosing the wavelengths a path carries (`--wavelengths`):
//!
//! - `swc`, stratified wavelength clusters (Evans & McCool 1999): K
//!   numbers stratified in [0, 1) pushed through the tabulated inverse CDF
//!   of the mixture of all lights' spectra (by power, with a defensive
//!   share of the visible density); each wavelength's density in the
//!   estimator is that table's, returned with it, which keeps the cluster
//!   average unbiased.
//! - `hero`, hero wavelengths (Wilkie et al. 2014): one wavelength from the
//!   visible density, the others rotated by equal offsets over 360–830 nm;
//!   each weighed by the mean of the visible density over the K rotations
//!   that could have produced it (the balance heuristic), which is exact.
//! - `single`: one wavelength per path, from the visible density.

mod inverse_cdf;
mod swc;

pub use inverse_cdf::InverseCdf;
pub use swc::Swc;
// The densities live in `sampling`, below the fluorescent BSDFs that
// sample with them; named here too, where the strategies use them.
pub use crate::sampling::spectral_pdf::SpectralPdf;
pub use crate::sampling::visible::{sample_visible, visible_pdf};

use scotopia_color::{SampledWavelengths, LAMBDA_MAX, LAMBDA_MIN};

use crate::bsdf::Fluorescent;
use crate::light::Light;

/// The strategy names the CLI and Python accept.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum WavelengthStrategy {
    Swc,
    Hero,
    Single,
}

impl WavelengthStrategy {
    pub const ALL: [WavelengthStrategy; 3] = [Self::Swc, Self::Hero, Self::Single];

    pub fn name(self) -> &'static str {
        match self {
            Self::Swc => "swc",
            Self::Hero => "hero",
            Self::Single => "single",
        }
    }

    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|s| s.name() == name.trim())
    }
}

/// A strategy ready to draw clusters for one scene.
#[derive(Debug, Clone, PartialEq)]
pub enum WavelengthSampler {
    Swc(Box<Swc>),
    Hero,
    Single,
}

impl WavelengthSampler {
    /// `power[i]` is light i's radiant power (W), as the renderer's light
    /// choice has it; `fluorescent` the scene's fluorescent materials.
    pub fn new(
        strategy: WavelengthStrategy,
        lights: &[Light],
        power: &[f32],
        fluorescent: &[&Fluorescent],
    ) -> Self {
        match strategy {
            WavelengthStrategy::Swc => Self::Swc(Box::new(Swc::new(lights, power, fluorescent))),
            WavelengthStrategy::Hero => Self::Hero,
            WavelengthStrategy::Single => Self::Single,
        }
    }

    /// A cluster from `u_choice` (which light, for `swc`) and `u` (the
    /// stratification offset), both in [0, 1).
    pub fn sample<const K: usize>(&self, u_choice: f32, u: f32) -> SampledWavelengths<K> {
        match self {
            Self::Swc(s) => s.sample(u_choice, u),
            Self::Hero => hero(u),
            Self::Single => {
                let l = sample_visible(u);
                let mut wl = SampledWavelengths::new([l; K], [visible_pdf(l); K]);
                wl.terminate_secondary();
                wl
            }
        }
    }
}

/// Wavelength `lambda` moved by `offset` nm, wrapped into [360, 830).
#[inline]
fn rotate(lambda: f32, offset: f32) -> f32 {
    let range = LAMBDA_MAX - LAMBDA_MIN;
    LAMBDA_MIN + (lambda - LAMBDA_MIN + offset).rem_euclid(range)
}

fn hero<const K: usize>(u: f32) -> SampledWavelengths<K> {
    let step = (LAMBDA_MAX - LAMBDA_MIN) / K as f32;
    let hero = sample_visible(u);
    let lambda: [f32; K] = std::array::from_fn(|k| rotate(hero, k as f32 * step));
    // p̄(λ) = (1/K) Σ_j p(λ − j·step): the density of λ over the choice of
    // which member of the cluster was the hero.
    let pdf = lambda.map(|l| {
        (0..K)
            .map(|j| visible_pdf(rotate(l, -(j as f32) * step)))
            .sum::<f32>()
            / K as f32
    });
    SampledWavelengths::new(lambda, pdf)
}

#[cfg(test)]
mod tests;

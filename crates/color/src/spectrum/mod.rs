//! Spectra: the closed set of spectral functions scotopia evaluates, each
//! evaluable at one wavelength or on a cluster of sampled wavelengths.

mod blackbody;
mod lookup;
mod sigmoid;
mod tabulated;

use std::sync::Arc;

pub use blackbody::{planck, Blackbody, BOLTZMANN_K, LIGHT_C, PLANCK_H};
pub use lookup::RESAMPLE_TOLERANCE;
pub use sigmoid::{normalised_lambda, sigmoid, RgbSigmoid};
pub use tabulated::Tabulated;

use crate::error::ColorError;
use crate::sampled::{SampledSpectrum, SampledWavelengths};

/// A spectral function of wavelength (nm). What the value means — spectral
/// radiance in W·sr⁻¹·m⁻²·nm⁻¹, a reflectance, an index — is the user's.
#[derive(Debug, Clone, PartialEq)]
pub enum Spectrum {
    /// The same value at every wavelength.
    Constant(f32),
    /// Piecewise linear through tabulated samples, zero outside them.
    Tabulated(Arc<Tabulated>),
    /// Planck's law in absolute radiance, times a scale.
    Blackbody(Blackbody),
    /// Jakob & Hanika 2019 sigmoid polynomial, from an RGB colour.
    Sigmoid(RgbSigmoid),
}

impl Spectrum {
    /// A tabulated spectrum.
    pub fn tabulated(t: Tabulated) -> Self {
        Spectrum::Tabulated(Arc::new(t))
    }

    /// Black-body spectral radiance (W·sr⁻¹·m⁻²·nm⁻¹) at `kelvin`.
    pub fn blackbody(kelvin: f32) -> Result<Self, ColorError> {
        if !(kelvin.is_finite() && kelvin > 0.0) {
            return Err(ColorError::OutOfRange(format!(
                "black-body temperature must be positive, got {kelvin} K"
            )));
        }
        Ok(Spectrum::Blackbody(Blackbody { kelvin, scale: 1.0 }))
    }

    /// Value at `lambda` nm.
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        match self {
            Spectrum::Constant(v) => *v,
            Spectrum::Tabulated(t) => t.eval(lambda),
            Spectrum::Blackbody(b) => b.eval(lambda),
            Spectrum::Sigmoid(s) => s.eval(lambda),
        }
    }

    /// Values on a wavelength cluster; one dispatch for the whole cluster.
    #[inline]
    pub fn sample<const K: usize>(
        &self,
        wavelengths: &SampledWavelengths<K>,
    ) -> SampledSpectrum<K> {
        let lambda = wavelengths.lambdas();
        match self {
            Spectrum::Constant(v) => SampledSpectrum::splat(*v),
            Spectrum::Tabulated(t) => SampledSpectrum(t.eval_cluster(lambda)),
            Spectrum::Blackbody(b) => SampledSpectrum::from_fn(|i| b.eval(lambda[i])),
            Spectrum::Sigmoid(s) => SampledSpectrum::from_fn(|i| s.eval(lambda[i])),
        }
    }

    /// The spectrum multiplied by `s`.
    pub fn scaled(&self, s: f32) -> Self {
        match self {
            Spectrum::Constant(v) => Spectrum::Constant(v * s),
            Spectrum::Tabulated(t) => Spectrum::tabulated(t.scaled(s)),
            Spectrum::Blackbody(b) => Spectrum::Blackbody(Blackbody {
                scale: b.scale * s,
                ..*b
            }),
            Spectrum::Sigmoid(g) => Spectrum::Sigmoid(RgbSigmoid {
                scale: g.scale * s,
                ..g.clone()
            }),
        }
    }

    /// Wavelengths where the spectrum has kinks (tabulated samples), which
    /// an integration must include to be exact for line spectra.
    pub fn breakpoints(&self) -> &[f32] {
        match self {
            Spectrum::Tabulated(t) => t.wavelengths(),
            _ => &[],
        }
    }

    /// Values at `start, start + step, …, end`.
    pub fn on_grid(&self, start: f32, end: f32, step: f32) -> Vec<f32> {
        let n = ((end - start) / step).round() as usize + 1;
        (0..n).map(|i| self.eval(start + step * i as f32)).collect()
    }
}

impl From<Tabulated> for Spectrum {
    fn from(t: Tabulated) -> Self {
        Spectrum::tabulated(t)
    }
}

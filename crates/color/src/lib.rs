//! Colour science for scotopia: spectra and their evaluation on wavelength
//! clusters, the CIE observers and illuminants, absolute photometry, colour
//! spaces and colour-difference metrics, and RGB → spectrum upsampling.
//!
//! Units: wavelengths in nm; emission in spectral radiance
//! W·sr⁻¹·m⁻²·nm⁻¹; photometric output in cd/m² (Y) and scotopic cd/m² (V′).

pub mod alpha_opic;
pub mod cct;
pub mod cie;
pub mod colorimetry;
pub mod error;
pub mod io;
pub mod photometry;
pub mod sampled;
pub mod space;
pub mod spectrum;
pub mod upsample;

pub use colorimetry::Colorimetry;
pub use error::ColorError;
pub use photometry::Xyzv;
pub use sampled::{SampledSpectrum, SampledWavelengths};
pub use space::{Mat3, RgbColorSpace, RgbSpace};
pub use spectrum::{Spectrum, Tabulated};
pub use upsample::{rgb_to_spectrum, SpectrumKind, UpsampleMethod};

/// Shortest wavelength scotopia renders and integrates, nm.
pub const LAMBDA_MIN: f32 = 360.0;
/// Longest wavelength scotopia renders and integrates, nm.
pub const LAMBDA_MAX: f32 = 830.0;

//! Sample warping, sample sequences, and densities over wavelength.

pub mod distribution;
pub mod sobol;
pub mod sobol_batch;
pub mod sobol_pair;
pub mod sobol_point;
pub mod spectral_pdf;
pub mod splitmix;
pub mod visible;
pub mod warp;

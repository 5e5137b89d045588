//! Participating media (issue 25): what light meets between surfaces.
//!
//! Mitsuba 3's model: a medium has an extinction coefficient σ_t (per
//! scene unit) and a single-scattering albedo α, both spectra, so that
//! σ_s = α σ_t and σ_a = σ_t − σ_s, and a phase function. Spectral
//! coefficients mean that a cluster of wavelengths sees different
//! extinctions: a distance is sampled for the cluster's first wavelength
//! and every outcome carries the densities it would have had for each
//! wavelength (`DistanceSample::pdf`), so that the integrator can weight
//! the path by one-sample MIS over the cluster (Wilkie et al. 2014, "Hero
//! Wavelength Spectral Sampling", §4; pbrt-v4 §14.2.2 tracks the same
//! ratios along a whole path).
//!
//! Built so far: the phase functions and the homogeneous medium, with
//! their sampling, and voxel grids (read from Mitsuba's `.vol` files by
//! `scotopia_scene::volume`); the loader's media, heterogeneous tracking
//! and the integrators are still to come.

mod grid;
mod homogeneous;
mod phase;

pub use grid::Grid;

/// A medium a scene holds (`Scene::media`).
#[derive(Debug, Clone, PartialEq)]
pub enum Medium {
    Homogeneous(Homogeneous),
}

/// The media on either side of a shape's surface (Mitsuba's `interior`
/// and `exterior`), as indices into `Scene::media`; `None` is vacuum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ShapeMedia {
    pub interior: Option<u32>,
    pub exterior: Option<u32>,
}
pub use homogeneous::{DistanceSample, Homogeneous};
pub use phase::Phase;

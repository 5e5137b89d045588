//! Participating media (issue 25): what light meets between surfaces.
//!
//! Mitsuba 3's model: a medium has an extinction coefficient σ_t (per
//! scene unit) and a single-scattering albedo α, both spectra, so that
//! σ_s = α σ_t and σ_a = σ_t − σ_s, and a phase function. Spectral
//! coefficients mean that a cluster of wavelengths sees different
//! extinctions: free flights are drawn for the cluster's first wavelength
//! and every outcome reports the density it would have had for each
//! wavelength (`MediumEvent::density`), so that the integrator weights the
//! path by one-sample MIS over the cluster (Wilkie et al. 2014, "Hero
//! Wavelength Spectral Sampling", §4), with the densities multiplied along
//! the whole path as pbrt-v4's volume path tracer does (§14.2.2, its
//! r_u): `integrator/volume.rs`.

mod grid;
mod heterogeneous;
mod homogeneous;
mod majorant;
mod phase;
mod volume;

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use crate::math::Ray;
use crate::sampling::splitmix::SplitMix;

pub use grid::Grid;
pub use heterogeneous::Heterogeneous;
pub use homogeneous::Homogeneous;
pub use majorant::Majorants;
pub use phase::Phase;
pub use volume::{Field, Filter, GridVolume};

/// A medium a scene holds (`Scene::media`).
#[derive(Debug, Clone, PartialEq)]
pub enum Medium {
    Homogeneous(Homogeneous),
    Heterogeneous(Box<Heterogeneous>),
}

/// The media on either side of a shape's surface (Mitsuba's `interior`
/// and `exterior`), as indices into `Scene::media`; `None` is vacuum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct ShapeMedia {
    pub interior: Option<u32>,
    pub exterior: Option<u32>,
}

impl ShapeMedia {
    /// Whether the surface separates media at all: a shape that names
    /// neither leaves the medium a ray is in unchanged (Mitsuba's
    /// `is_medium_transition`).
    pub fn is_transition(&self) -> bool {
        self.interior.is_some() || self.exterior.is_some()
    }

    /// The medium a ray leaving the surface in direction `d` enters, with
    /// `n` the geometric normal (outwards): the exterior on the normal's
    /// side.
    pub fn target(&self, d: crate::math::Vec3, n: crate::math::Vec3) -> Option<u32> {
        if d.dot(n) > 0.0 {
            self.exterior
        } else {
            self.interior
        }
    }
}

/// What a free flight through a medium met along a segment.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MediumEvent<const K: usize> {
    /// Distance of the scattering event, or the segment's end.
    pub t: f32,
    /// Whether the path scatters in the medium at `t`.
    pub scattered: bool,
    /// Each wavelength's own estimator f/p for this outcome: the albedo
    /// where it scattered, 1 where it passed (absorption is carried in
    /// the weight, never by ending the path).
    pub own: SampledSpectrum<K>,
    /// Each wavelength's density of this outcome up to one common factor
    /// (the first wavelength drew it); the path multiplies these along its
    /// events for the cluster's MIS.
    pub density: SampledSpectrum<K>,
}

impl Medium {
    /// The phase function.
    pub fn phase(&self) -> &Phase {
        match self {
            Medium::Homogeneous(m) => &m.phase,
            Medium::Heterogeneous(m) => &m.phase,
        }
    }

    /// Draws the next event along `ray` up to `t_max` for the wavelengths
    /// `wl` (the first one samples): `u` draws the distance, `rng` any
    /// further numbers a tracking walk needs.
    pub fn sample_event<const K: usize>(
        &self,
        ray: &Ray,
        t_max: f32,
        wl: &SampledWavelengths<K>,
        u: f32,
        rng: &mut SplitMix,
    ) -> MediumEvent<K> {
        match self {
            Medium::Homogeneous(m) => m.sample_event(wl, t_max, u),
            Medium::Heterogeneous(m) => m.sample_event(ray, t_max, wl, u, rng),
        }
    }

    /// The transmittance along `ray` up to `t_max`, per wavelength: exact
    /// for a homogeneous medium, an unbiased estimate otherwise.
    pub fn transmittance<const K: usize>(
        &self,
        ray: &Ray,
        t_max: f32,
        wl: &SampledWavelengths<K>,
        rng: &mut SplitMix,
    ) -> SampledSpectrum<K> {
        match self {
            Medium::Homogeneous(m) => m.transmittance(wl, t_max),
            Medium::Heterogeneous(m) => m.transmittance(ray, t_max, wl, rng),
        }
    }
}

/// Densities given as natural logarithms, scaled so that the largest is 1
/// (they may span more than f32's range: e^{−σt} over a long flight).
pub(crate) fn densities_from_logs<const K: usize>(logs: [f32; K]) -> SampledSpectrum<K> {
    let top = logs.iter().copied().fold(f32::NEG_INFINITY, f32::max);
    if top.is_finite() {
        SampledSpectrum::from_fn(|k| (logs[k] - top).exp())
    } else {
        // None of them is positive (or one is infinite, which no density
        // of a drawn event is).
        SampledSpectrum::splat(0.0)
    }
}

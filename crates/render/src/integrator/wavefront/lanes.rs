//! The batch: the paths in flight, one [`Lane`] each, and what the stages
//! pass between them.

use scotopia_color::SampledSpectrum;

use super::super::path::PathState;
use crate::geometry::Hit;
use crate::math::Ray;
use crate::sampling::sobol::Sampler;

/// Paths in flight per batch: enough that each stage's loop amortises its
/// set-up, few enough that the batch (about 250 bytes a path at K = 4)
/// stays in the L2 cache.
pub const BATCH: usize = 1024;

/// One path in flight.
pub struct Lane<const K: usize> {
    pub path: PathState<K>,
    /// The path's own sampler: its numbers depend on (seed, pixel, sample
    /// index, dimension) only, not on the lane or the batch.
    pub sampler: Sampler,
    /// Where its estimate goes in the row's results.
    pub slot: u32,
    /// The intersect stage's result.
    pub hit: Option<Hit>,
    /// The shade stage's shadow ray and what it carries if unoccluded.
    pub shadow: Option<(Ray, SampledSpectrum<K>)>,
    /// Whether the path goes on after this bounce.
    pub alive: bool,
}

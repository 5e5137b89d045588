//! Mitsuba 3's `null`: a surface light passes through unchanged, in
//! direction and (with `transmittance` 1) in weight. Sampling it is a
//! delta event: it counts as a bounce towards `max_depth` and blocks
//! shadow rays, as in Mitsuba's `path` integrator. The polarisation
//! plugins that scotopia reads without polarisation (`polarizer`,
//! `retarder`, `circular`) are this lobe with a transmittance below 1.

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::BsdfSample;
use crate::math::Vec3;
use crate::texture::{TexPoint, Texture};

#[derive(Debug, Clone, PartialEq)]
pub struct Null {
    /// The fraction of light passing (1 for `null`).
    pub transmittance: Texture,
    /// A factor on it (½ for a polariser seen by unpolarised light).
    pub scale: f32,
}

impl Default for Null {
    fn default() -> Self {
        Self {
            transmittance: Texture::constant(1.0),
            scale: 1.0,
        }
    }
}

impl Null {
    /// Straight on: `wo = −wi`, with pdf 1 as the delta marker.
    pub fn sample<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        uv: TexPoint,
        wi: Vec3,
    ) -> BsdfSample<K> {
        BsdfSample {
            wo: -wi,
            weight: self.transmittance.eval(wl, uv) * self.scale,
            pdf: 1.0,
            delta: true,
            collapse: false,
        }
    }
}

/// The pass-through sample with weight 1 (the null part of `mask`).
pub(super) fn pass_through<const K: usize>(wi: Vec3, pdf: f32) -> BsdfSample<K> {
    BsdfSample {
        wo: -wi,
        weight: SampledSpectrum::splat(1.0),
        pdf,
        delta: true,
        collapse: false,
    }
}

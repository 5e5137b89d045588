//! Mitsuba 3's `normalmap` (src/bsdfs/normalmap.cpp): the nested BSDF in
//! a shading frame whose normal is read from an RGB texture, c ↦ 2c − 1,
//! in the coordinates of the surface's own shading frame (x along
//! ∂p/∂u, z the normal), so (0.5, 0.5, 1) changes nothing.

use std::sync::Arc;

use super::perturbed::{flip_towards, frame_around, Perturbation, Perturbs};
use super::{Bsdf, ShadingPoint};
use crate::math::Vec3;
use crate::texture::RgbBitmap;

#[derive(Debug, Clone, PartialEq)]
pub struct NormalMap {
    /// Linear RGB in [0, 1] (a constant is a 1×1 bitmap).
    pub normals: Arc<RgbBitmap>,
    pub inner: Bsdf,
    /// Mirror a normal that faces away from `wi` (default true).
    pub flip_invalid_normals: bool,
    /// Estevez et al.'s shadowing term (default true).
    pub use_shadowing_function: bool,
}

impl NormalMap {
    /// The perturbed frame at `at` seen from `w` (the original frame when the
    /// map's normal is zero or not finite).
    pub(super) fn perturbation(&self, at: ShadingPoint, w: Vec3) -> Perturbation {
        let [r, g, b] = self.normals.eval(at.uv);
        let mut n = Vec3::new(2.0 * r - 1.0, 2.0 * g - 1.0, 2.0 * b - 1.0);
        if self.flip_invalid_normals {
            n = flip_towards(n, w);
        }
        Perturbation {
            frame: frame_around(n, Vec3::new(1.0, 0.0, 0.0)),
            shadowing: self.use_shadowing_function,
        }
    }
}

impl Perturbs for NormalMap {
    fn perturbation(&self, at: ShadingPoint, w: Vec3) -> Perturbation {
        self.perturbation(at, w)
    }

    fn inner(&self) -> &Bsdf {
        &self.inner
    }
}

//! Mitsuba 3's `bumpmap` (src/bsdfs/bumpmap.cpp): the nested BSDF in a
//! shading frame tilted by a height texture h (times `scale`). The
//! displaced surface p + h·n has ∂p'/∂u = ∂p/∂u + n·(∂h/∂u − n·∂p/∂u)
//! (likewise in v), and its normal ∂p'/∂u × ∂p'/∂v, turned to the side of
//! the geometric normal, is the new shading normal (Blinn 1978,
//! "Simulation of Wrinkled Surfaces", with Mitsuba's simplification of
//! dropping the normal's own derivatives).

use super::perturbed::{flip_towards, frame_around, Perturbation, Perturbs};
use super::{Bsdf, ShadingPoint};
use crate::math::Vec3;
use crate::texture::FloatTexture;

#[derive(Debug, Clone, PartialEq)]
pub struct BumpMap {
    pub height: FloatTexture,
    /// Multiplies the height (default 1).
    pub scale: f32,
    pub inner: Bsdf,
    /// Mirror a normal that faces away from `wi` (default true).
    pub flip_invalid_normals: bool,
    /// Estevez et al.'s shadowing term (default true).
    pub use_shadowing_function: bool,
}

impl BumpMap {
    /// The perturbed frame at `at` seen from `w`, in the original frame's
    /// coordinates (whose normal is z).
    pub(super) fn perturbation(&self, at: ShadingPoint, w: Vec3) -> Perturbation {
        let [hu, hv] = self.height.grad(at.uv);
        let dpdu = Vec3::new(at.dpdu.x, at.dpdu.y, self.scale * hu);
        let dpdv = Vec3::new(at.dpdv.x, at.dpdv.y, self.scale * hv);
        let mut n = dpdu.cross(dpdv);
        if at.ng.dot(n) < 0.0 {
            n = -n;
        }
        if self.flip_invalid_normals {
            n = flip_towards(n, w);
        }
        Perturbation {
            frame: frame_around(n, at.dpdu),
            shadowing: self.use_shadowing_function,
        }
    }
}

impl Perturbs for BumpMap {
    fn perturbation(&self, at: ShadingPoint, w: Vec3) -> Perturbation {
        self.perturbation(at, w)
    }

    fn inner(&self) -> &Bsdf {
        &self.inner
    }
}

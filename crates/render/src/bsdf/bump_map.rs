//! Mitsuba 3's `bumpmap` (src/bsdfs/bumpmap.cpp): the nested BSDF in a
//! shading frame tilted by a height texture h (times `scale`). The
//! displaced surface p + h·n has ∂p'/∂u = ∂p/∂u + n·(∂h/∂u − n·∂p/∂u)
//! (likewise in v), and its normal ∂p'/∂u × ∂p'/∂v, turned to the side of
//! the geometric normal, is the new shading normal (Blinn 1978,
//! "Simulation of Wrinkled Surfaces", with Mitsuba's simplification of
//! dropping the normal's own derivatives).

use scotopia_color::{SampledSpectrum, SampledWavelengths};

use super::perturbed::{self, flip_towards, frame_around, Perturbation};
use super::{Bsdf, BsdfSample, ShadingPoint, Transport};
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

    pub fn eval<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        at: ShadingPoint,
        wi: Vec3,
        wo: Vec3,
        mode: Transport,
    ) -> SampledSpectrum<K> {
        let frame_for = |w| self.perturbation(at, w);
        perturbed::eval(frame_for, &self.inner, wl, at, wi, wo, mode)
    }

    pub fn pdf<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        at: ShadingPoint,
        wi: Vec3,
        wo: Vec3,
    ) -> f32 {
        let frame_for = |w| self.perturbation(at, w);
        perturbed::pdf(frame_for, &self.inner, wl, at, wi, wo)
    }

    pub fn sample<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        at: ShadingPoint,
        wi: Vec3,
        u_lobe: f32,
        u: [f32; 2],
        mode: Transport,
    ) -> Option<BsdfSample<K>> {
        let frame_for = |w| self.perturbation(at, w);
        perturbed::sample(frame_for, &self.inner, wl, at, wi, u_lobe, u, mode)
    }
}

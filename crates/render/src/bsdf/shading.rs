//! Where a BSDF is evaluated: the hit's texture coordinates (and the
//! triangle and barycentrics that mesh attributes are read at) and, for
//! the BSDFs that perturb the shading frame (normal and bump maps), the
//! surface's differential geometry — all in the local shading frame, whose
//! x axis follows ∂p/∂u (what Mitsuba's BSDFs read from `si`).

use crate::math::{Frame, Vec3};
use crate::texture::TexPoint;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ShadingPoint {
    pub uv: [f32; 2],
    /// The triangle hit and the barycentric weights of its second and
    /// third vertices (see [`TexPoint`]).
    pub prim: u32,
    pub bary: [f32; 2],
    /// ∂p/∂u and ∂p/∂v in the shading frame.
    pub dpdu: Vec3,
    pub dpdv: Vec3,
    /// The geometric normal in the shading frame.
    pub ng: Vec3,
}

impl ShadingPoint {
    /// The shading frame of a hit (z = the shading normal `ns`, x along
    /// `dpdu`) and the point seen from it, where textures are looked up
    /// at `tex` (texture coordinates, or a [`TexPoint`]).
    #[inline]
    pub fn at(
        tex: impl Into<TexPoint>,
        ns: Vec3,
        ng: Vec3,
        dpdu: Vec3,
        dpdv: Vec3,
    ) -> (Frame, Self) {
        let tex: TexPoint = tex.into();
        let frame = Frame::from_normal_tangent(ns, dpdu);
        let at = Self {
            uv: tex.uv,
            prim: tex.prim,
            bary: tex.bary,
            dpdu: frame.to_local(dpdu),
            dpdv: frame.to_local(dpdv),
            ng: frame.to_local(ng),
        };
        (frame, at)
    }

    /// Where textures are looked up.
    #[inline]
    pub fn tex(&self) -> TexPoint {
        TexPoint {
            uv: self.uv,
            prim: self.prim,
            bary: self.bary,
        }
    }

    /// The same point seen from below: every z mirrored (`twosided`).
    #[inline]
    pub(crate) fn mirrored(self) -> Self {
        let m = |v: Vec3| Vec3::new(v.x, v.y, -v.z);
        Self {
            dpdu: m(self.dpdu),
            dpdv: m(self.dpdv),
            ng: m(self.ng),
            ..self
        }
    }
}

/// A flat surface parametrised by the frame's own axes: what BSDFs that
/// only read textures need (and what tests pass as bare `uv`).
impl From<[f32; 2]> for ShadingPoint {
    #[inline]
    fn from(uv: [f32; 2]) -> Self {
        TexPoint::from(uv).into()
    }
}

/// A flat surface as above, its textures looked up at `tex`.
impl From<TexPoint> for ShadingPoint {
    #[inline]
    fn from(tex: TexPoint) -> Self {
        Self {
            uv: tex.uv,
            prim: tex.prim,
            bary: tex.bary,
            dpdu: Vec3::new(1.0, 0.0, 0.0),
            dpdv: Vec3::new(0.0, 1.0, 0.0),
            ng: Vec3::new(0.0, 0.0, 1.0),
        }
    }
}

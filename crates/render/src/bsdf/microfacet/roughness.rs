//! A rough BSDF's roughness: constant — the distribution built once, as
//! cheap to use as a bare one — or textured: α_u and α_v looked up where
//! the BSDF is evaluated, as Mitsuba 3's `roughconductor` and
//! `roughdielectric` take them (`alpha`, `alpha_u`, `alpha_v` as
//! textures, read with `eval_1`, then clamped to `MIN_ALPHA` by the
//! distribution).

use std::sync::Arc;

use super::{MicrofacetDistribution, MicrofacetKind};
use crate::texture::{FloatTexture, TexPoint};

#[derive(Debug, Clone, PartialEq)]
pub enum Roughness {
    Constant(MicrofacetDistribution),
    Textured(Arc<TexturedRoughness>),
}

#[derive(Debug, Clone, PartialEq)]
pub struct TexturedRoughness {
    pub kind: MicrofacetKind,
    /// α along the shading frame's tangent (x) and bitangent (y).
    pub alpha_u: FloatTexture,
    pub alpha_v: FloatTexture,
}

impl From<MicrofacetDistribution> for Roughness {
    fn from(d: MicrofacetDistribution) -> Self {
        Roughness::Constant(d)
    }
}

impl Roughness {
    /// Roughness from textures; constant textures give the constant
    /// distribution.
    pub fn new(kind: MicrofacetKind, alpha_u: FloatTexture, alpha_v: FloatTexture) -> Self {
        match (&alpha_u, &alpha_v) {
            (FloatTexture::Constant(u), FloatTexture::Constant(v)) => {
                Roughness::Constant(MicrofacetDistribution::new(kind, *u, *v))
            }
            _ => Roughness::Textured(Arc::new(TexturedRoughness {
                kind,
                alpha_u,
                alpha_v,
            })),
        }
    }

    /// The distribution at `at`.
    #[inline]
    pub fn at(&self, at: TexPoint) -> MicrofacetDistribution {
        match self {
            Roughness::Constant(d) => *d,
            Roughness::Textured(t) => {
                MicrofacetDistribution::new(t.kind, t.alpha_u.eval(at), t.alpha_v.eval(at))
            }
        }
    }

    /// The distribution when it is the same everywhere.
    pub fn constant(&self) -> Option<MicrofacetDistribution> {
        match self {
            Roughness::Constant(d) => Some(*d),
            Roughness::Textured(_) => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::super::MIN_ALPHA;
    use super::*;

    #[test]
    fn constant_textures_build_the_constant_distribution() {
        let r = Roughness::new(
            MicrofacetKind::Ggx,
            FloatTexture::Constant(0.3),
            FloatTexture::Constant(0.0),
        );
        let d = MicrofacetDistribution::new(MicrofacetKind::Ggx, 0.3, MIN_ALPHA);
        assert_eq!(r, Roughness::Constant(d));
        assert_eq!(r.at([0.7, 0.2].into()), d);
    }
}

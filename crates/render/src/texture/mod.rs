//! Textures: spectral values that vary over a surface, looked up by the
//! hit's (u, v) — or, for a mesh's own attributes, its triangle and
//! barycentrics ([`TexPoint`]) — and evaluated on the path's wavelength
//! cluster. A constant spectrum is the common case; `bitmap`,
//! `checkerboard` and `mesh_attribute` follow Mitsuba 3's plugins of the
//! same names.

mod bitmap;
mod checkerboard;
mod mesh_attribute;
mod point;
mod scalar;
mod uv;

use std::sync::Arc;

pub use bitmap::{Bitmap, Filter, Wrap};
pub use checkerboard::Checkerboard;
pub use mesh_attribute::MeshAttribute;
pub use point::TexPoint;
pub use scalar::{luminance, FloatCheckerboard, FloatTexture, RgbBitmap};
pub use uv::UvTransform;

use scotopia_color::{SampledSpectrum, SampledWavelengths, Spectrum};

/// The closed set of textures.
#[derive(Debug, Clone, PartialEq)]
pub enum Texture {
    /// The same spectrum everywhere.
    Constant(Spectrum),
    /// An RGB image, upsampled per texel.
    Bitmap(Arc<Bitmap>),
    /// Two textures alternating on a unit checkerboard in (u, v).
    Checkerboard(Arc<Checkerboard>),
    /// A mesh's named attribute (bound to that mesh).
    MeshAttribute(Arc<MeshAttribute>),
}

impl From<Spectrum> for Texture {
    fn from(s: Spectrum) -> Self {
        Texture::Constant(s)
    }
}

impl Texture {
    /// A constant texture of value `v` at every wavelength.
    pub fn constant(v: f32) -> Self {
        Texture::Constant(Spectrum::Constant(v))
    }

    /// The value at `at` (texture coordinates, or a [`TexPoint`]) on the
    /// cluster `wl`.
    #[inline]
    pub fn eval<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        at: impl Into<TexPoint>,
    ) -> SampledSpectrum<K> {
        let at: TexPoint = at.into();
        match self {
            Texture::Constant(s) => s.sample(wl),
            Texture::Bitmap(b) => b.eval(wl, at.uv),
            Texture::Checkerboard(c) => {
                if c.first_at(at.uv) {
                    c.color0.eval(wl, at)
                } else {
                    c.color1.eval(wl, at)
                }
            }
            Texture::MeshAttribute(m) => m.eval(wl, at),
        }
    }

    /// The mean value over the surface and the visible range: what a BSDF
    /// uses to share its samples between lobes.
    pub fn mean(&self) -> f32 {
        match self {
            Texture::Constant(s) => {
                (0..=47)
                    .map(|i| s.eval(360.0 + 10.0 * i as f32))
                    .sum::<f32>()
                    / 48.0
            }
            Texture::Bitmap(b) => b.mean(),
            Texture::Checkerboard(c) => 0.5 * (c.color0.mean() + c.color1.mean()),
            Texture::MeshAttribute(m) => m.mean(),
        }
    }

    /// The largest value over the surface at each of `lambdas`.
    pub fn max_over_surface(&self, lambdas: &[f32]) -> Vec<f32> {
        match self {
            Texture::Constant(s) => lambdas.iter().map(|&l| s.eval(l)).collect(),
            Texture::Bitmap(b) => b.max_over_texels(lambdas),
            Texture::Checkerboard(c) => {
                let (a, b) = (
                    c.color0.max_over_surface(lambdas),
                    c.color1.max_over_surface(lambdas),
                );
                a.iter().zip(&b).map(|(x, y)| x.max(*y)).collect()
            }
            Texture::MeshAttribute(m) => m.max_over_records(lambdas),
        }
    }

    /// Whether the value varies over the surface.
    pub fn is_varying(&self) -> bool {
        !matches!(self, Texture::Constant(_))
    }
}

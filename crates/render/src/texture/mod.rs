//! Textures: spectral values that vary over a surface, looked up by the
//! hit's (u, v) — or, for a mesh's own attributes, its triangle and
//! barycentrics ([`TexPoint`]) — and evaluated on the path's wavelength
//! cluster. A constant spectrum is the common case; `bitmap`,
//! `checkerboard` and `mesh_attribute` follow Mitsuba 3's plugins of the
//! same names.

mod bitmap;
mod checkerboard;
mod mesh_attribute;
mod scalar;
mod uv;

use std::sync::Arc;

/// Made by the shapes (`geometry`), which know the hit; kept here for the
/// paths that name it `texture::TexPoint`.
pub use crate::geometry::TexPoint;
pub use bitmap::{Bitmap, Filter, Wrap};
pub use checkerboard::Checkerboard;
pub use mesh_attribute::MeshAttribute;
pub use scalar::{luminance, FloatCheckerboard, FloatTexture, RgbBitmap};
pub use uv::UvTransform;

use scotopia_color::{SampledSpectrum, SampledWavelengths, Spectrum, Tabulated};

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

    /// The spectrum averaged over the texture coordinates `uvs` (equal
    /// weights: the caller chooses where, e.g. uniformly over a surface's
    /// area), tabulated every 5 nm; a constant texture's own spectrum.
    /// Emitters draw wavelengths from it and report their power by it.
    pub fn mean_spectrum(&self, uvs: &[[f32; 2]]) -> Spectrum {
        if let Texture::Constant(s) = self {
            return s.clone();
        }
        // Every 5 nm, and at the samples of the spectra the texture holds,
        // so a line emitter's line stays in its mean.
        let mut lambda: Vec<f32> = (360..=830).step_by(5).map(|l| l as f32).collect();
        self.breakpoints(&mut lambda);
        lambda.retain(|l| (360.0..=830.0).contains(l));
        lambda.sort_by(f32::total_cmp);
        lambda.dedup();
        let mut sums = vec![0.0f64; lambda.len()];
        // Eight wavelengths per lookup, so a texel's upsampling is shared.
        for (chunk, out) in lambda.chunks(8).zip(sums.chunks_mut(8)) {
            let mut l = [chunk[chunk.len() - 1]; 8];
            l[..chunk.len()].copy_from_slice(chunk);
            let wl = SampledWavelengths::<8>::new(l, [1.0; 8]);
            for &uv in uvs {
                let v = self.eval(&wl, uv);
                for (k, o) in out.iter_mut().enumerate() {
                    *o += v.0[k] as f64;
                }
            }
        }
        let n = uvs.len().max(1) as f64;
        let values = sums.iter().map(|s| (s / n) as f32).collect();
        Tabulated::new(lambda, values)
            .map(Spectrum::from)
            .unwrap_or(Spectrum::Constant(0.0))
    }

    /// Appends the tabulated wavelengths of the spectra the texture holds.
    pub fn breakpoints(&self, out: &mut Vec<f32>) {
        match self {
            Texture::Constant(s) => out.extend(s.breakpoints()),
            // Upsampled RGB: smooth, no tabulated wavelengths.
            Texture::Bitmap(_) | Texture::MeshAttribute(_) => {}
            Texture::Checkerboard(c) => {
                c.color0.breakpoints(out);
                c.color1.breakpoints(out);
            }
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

//! Textures of plain numbers rather than spectra: what Mitsuba 3 reads
//! with `eval_1` (an opacity, a blend weight, a height) and `eval_3` (a
//! normal map's RGB). A bitmap here keeps its linear RGB values as they
//! are, without spectral upsampling.

use std::sync::Arc;

use super::checkerboard::same_halves;
use super::{Filter, MeshAttribute, TexPoint, UvTransform, Wrap};

/// Rec. 709 / sRGB luminance weights (ITU-R BT.709, the Y row of the
/// linear-sRGB-to-XYZ matrix): the single value of an RGB texel, as
/// Mitsuba's `luminance()`.
const LUMINANCE: [f32; 3] = [0.212_671, 0.715_160, 0.072_169];

/// An image of linear RGB numbers, looked up like Mitsuba's `bitmap`
/// (texel centres at half-integers, v = 0 the top row).
#[derive(Debug, Clone, PartialEq)]
pub struct RgbBitmap {
    width: usize,
    height: usize,
    /// Row-major, top row first.
    pixels: Vec<[f32; 3]>,
    pub filter: Filter,
    pub wrap: Wrap,
    pub to_uv: UvTransform,
}

/// The four texels around a bilinear lookup and the weights along x, y.
struct Footprint {
    c: [[f32; 3]; 4],
    a: [f32; 2],
}

impl RgbBitmap {
    /// `None` when `pixels` does not hold `width × height` texels.
    pub fn new(width: usize, height: usize, pixels: Vec<[f32; 3]>) -> Option<Self> {
        (width > 0 && height > 0 && pixels.len() == width * height).then_some(Self {
            width,
            height,
            pixels,
            filter: Filter::Bilinear,
            wrap: Wrap::Repeat,
            to_uv: UvTransform::default(),
        })
    }

    fn texel(&self, x: i64, y: i64) -> [f32; 3] {
        let x = self.wrap.index(x, self.width);
        let y = self.wrap.index(y, self.height);
        self.pixels[y * self.width + x]
    }

    /// Texels 00, 10, 01, 11 around the transformed `uv` and the weights.
    fn footprint(&self, [u, v]: [f32; 2]) -> Footprint {
        let (px, py) = (u * self.width as f32 - 0.5, v * self.height as f32 - 0.5);
        let (fx, fy) = (px.floor(), py.floor());
        let (x, y) = (fx as i64, fy as i64);
        Footprint {
            c: [
                self.texel(x, y),
                self.texel(x + 1, y),
                self.texel(x, y + 1),
                self.texel(x + 1, y + 1),
            ],
            a: [px - fx, py - fy],
        }
    }

    /// The filtered RGB at texture coordinates `uv` (Mitsuba's `eval_3`).
    pub fn eval(&self, uv: [f32; 2]) -> [f32; 3] {
        let [u, v] = self.to_uv.apply(uv);
        match self.filter {
            Filter::Nearest => self.texel(
                (u * self.width as f32).floor() as i64,
                (v * self.height as f32).floor() as i64,
            ),
            Filter::Bilinear => {
                let Footprint { c, a: [ax, ay] } = self.footprint([u, v]);
                std::array::from_fn(|k| {
                    let top = c[0][k] * (1.0 - ax) + c[1][k] * ax;
                    let bottom = c[2][k] * (1.0 - ax) + c[3][k] * ax;
                    top * (1.0 - ay) + bottom * ay
                })
            }
        }
    }

    /// The luminance at `uv` (Mitsuba's `eval_1`).
    pub fn eval_1(&self, uv: [f32; 2]) -> f32 {
        luminance(self.eval(uv))
    }

    /// ∂/∂u and ∂/∂v of the luminance at `uv` (Mitsuba's `eval_1_grad`):
    /// zero for nearest filtering; otherwise the bilinear patch's slope
    /// per texel, times the resolution, through the `to_uv` map by the
    /// chain rule.
    pub fn grad_1(&self, uv: [f32; 2]) -> [f32; 2] {
        if self.filter == Filter::Nearest {
            return [0.0, 0.0];
        }
        let Footprint { c, a: [ax, ay] } = self.footprint(self.to_uv.apply(uv));
        let f = c.map(luminance);
        // Per unit of the transformed (u', v'): texel slopes times resolution.
        let du = ((1.0 - ay) * (f[1] - f[0]) + ay * (f[3] - f[2])) * self.width as f32;
        let dv = ((1.0 - ax) * (f[2] - f[0]) + ax * (f[3] - f[1])) * self.height as f32;
        let m = &self.to_uv.0;
        [m[0] * du + m[3] * dv, m[1] * du + m[4] * dv]
    }
}

/// The luminance of linear sRGB `c`.
#[inline]
pub fn luminance(c: [f32; 3]) -> f32 {
    LUMINANCE[0] * c[0] + LUMINANCE[1] * c[1] + LUMINANCE[2] * c[2]
}

/// A texture of one number per point.
#[derive(Debug, Clone, PartialEq)]
pub enum FloatTexture {
    Constant(f32),
    /// The luminance of a linear RGB bitmap.
    Bitmap(Arc<RgbBitmap>),
    /// `first` where the fractional parts of u and v lie in the same half
    /// of [0, 1), `second` elsewhere (Mitsuba's `checkerboard`).
    Checkerboard(Arc<FloatCheckerboard>),
    /// A mesh's one-number attribute (bound to that mesh).
    MeshAttribute(Arc<MeshAttribute>),
}

/// Mitsuba 3's `checkerboard` read as one number (its `eval_1`): `first`
/// (`color0`) where the fractional parts of u and v lie in *different*
/// halves of [0, 1) — the opposite of its spectral `eval`
/// (checkerboard.cpp, 3.9.1). Followed so that a textured roughness,
/// weight or opacity falls where Mitsuba puts it.
#[derive(Debug, Clone, PartialEq)]
pub struct FloatCheckerboard {
    pub first: FloatTexture,
    pub second: FloatTexture,
    pub to_uv: UvTransform,
}

impl FloatTexture {
    /// The value at `at` as a fraction in [0, 1] (a blend weight, an
    /// opacity): clamped, and 0 where the texture holds NaN.
    #[inline]
    pub fn eval_fraction(&self, at: impl Into<TexPoint>) -> f32 {
        let v = self.eval(at);
        if v.is_nan() {
            0.0
        } else {
            v.clamp(0.0, 1.0)
        }
    }

    /// The value at `at` (texture coordinates, or a [`TexPoint`]).
    #[inline]
    pub fn eval(&self, at: impl Into<TexPoint>) -> f32 {
        let at: TexPoint = at.into();
        match self {
            FloatTexture::Constant(v) => *v,
            FloatTexture::Bitmap(b) => b.eval_1(at.uv),
            FloatTexture::Checkerboard(c) => {
                if !same_halves(&c.to_uv, at.uv) {
                    c.first.eval(at)
                } else {
                    c.second.eval(at)
                }
            }
            FloatTexture::MeshAttribute(m) => m.eval_1(at),
        }
    }

    /// ∂/∂u and ∂/∂v of the value at `uv` (zero where it is piecewise
    /// constant, as Mitsuba's checkerboard and nearest lookups are, and
    /// for mesh attributes, which do not vary with (u, v)).
    pub fn grad(&self, uv: [f32; 2]) -> [f32; 2] {
        match self {
            FloatTexture::Bitmap(b) => b.grad_1(uv),
            FloatTexture::Constant(_)
            | FloatTexture::Checkerboard(_)
            | FloatTexture::MeshAttribute(_) => [0.0, 0.0],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// 2×1: luminance 0 on the left texel, 1 on the right.
    fn ramp() -> RgbBitmap {
        RgbBitmap::new(2, 1, vec![[0.0; 3], [1.0; 3]]).unwrap()
    }

    #[test]
    fn lookups_follow_the_texel_centres() {
        let b = ramp();
        assert!((b.eval_1([0.25, 0.5]) - 0.0).abs() < 1e-6);
        assert!((b.eval_1([0.75, 0.5]) - 1.0).abs() < 1e-6);
        assert!((b.eval_1([0.5, 0.5]) - 0.5).abs() < 1e-6);
        assert!(RgbBitmap::new(2, 2, vec![[0.0; 3]; 3]).is_none());
        assert!((luminance([1.0, 1.0, 1.0]) - 1.0).abs() < 1e-5);
    }

    #[test]
    fn the_gradient_is_the_slope_of_the_lookup() {
        let mut b = ramp();
        // Between the centres the value rises by 1 over half a unit of u.
        let [du, dv] = b.grad_1([0.4, 0.5]);
        assert!((du - 2.0).abs() < 1e-5 && dv.abs() < 1e-6, "{du} {dv}");
        // A finite difference agrees, with a u scale of 3 in to_uv.
        b.to_uv = UvTransform([3.0, 0.0, 0.0, 0.0, 1.0, 0.0]);
        let h = 1e-3;
        let fd = (b.eval_1([0.1 + h, 0.5]) - b.eval_1([0.1 - h, 0.5])) / (2.0 * h);
        let [du, _] = b.grad_1([0.1, 0.5]);
        assert!((du - fd).abs() < 1e-2 * fd.abs(), "{du} vs {fd}");
        b.filter = Filter::Nearest;
        assert_eq!(b.grad_1([0.1, 0.5]), [0.0, 0.0]);
    }

    /// Mitsuba 3.9.1's `eval_1` puts `color0` where u and v fall in
    /// different halves, its spectral `eval` where they fall in the same:
    /// a float checkerboard is the colour checkerboard's negative.
    #[test]
    fn a_float_checkerboard_is_the_colour_checkerboards_negative() {
        let c = FloatTexture::Checkerboard(Arc::new(FloatCheckerboard {
            first: FloatTexture::Constant(0.7),
            second: FloatTexture::Constant(0.1),
            to_uv: UvTransform::default(),
        }));
        assert_eq!(c.eval([0.25, 0.25]), 0.1);
        assert_eq!(c.eval([0.75, 0.75]), 0.1);
        assert_eq!(c.eval([0.75, 0.25]), 0.7);
        assert_eq!(c.eval([0.25, 0.75]), 0.7);
        let colour = crate::texture::Checkerboard {
            color0: crate::texture::Texture::constant(0.7),
            color1: crate::texture::Texture::constant(0.1),
            to_uv: UvTransform::default(),
        };
        assert!(colour.first_at([0.25, 0.25]) && !colour.first_at([0.75, 0.25]));
    }
}

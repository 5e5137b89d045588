//! Oklab for one display space, and the line of constant lightness and
//! hue that the gamut-mapping searches move along.
//!
//! Oklab (Ottosson 2020) is XYZ → LMS (M₁) → cube root → Lab (M₂). Along
//! a line of lightness L and hue (cos h, sin h), the cube-rooted LMS are
//! affine in chroma C: lms′ = L·w + C·v with w = M₂⁻¹(1, 0, 0) and
//! v = M₂⁻¹(0, cos h, sin h); so each linear RGB channel,
//! RGB = (RGB←XYZ · M₁⁻¹) lms′³, is a cubic in C, with derivatives in
//! closed form.

use super::clip;
use crate::wide_math::cbrt;
use scotopia_color::space::{Mat3, RgbColorSpace, RgbSpace};
use std::sync::OnceLock;

/// Ottosson 2020, M₁: XYZ (D65) → LMS (as `scotopia_color`'s Oklab;
/// the tests check that the two agree).
const M1: Mat3 = Mat3([
    [0.8189330101, 0.3618667424, -0.1288597137],
    [0.0329845436, 0.9293118715, 0.0361456387],
    [0.0482003018, 0.2643662691, 0.6338517070],
]);
/// Ottosson 2020, M₂: cube-rooted LMS → Lab.
const M2: Mat3 = Mat3([
    [0.2104542553, 0.7936177850, -0.0040720468],
    [1.9779984951, -2.4285922050, 0.4505937099],
    [0.0259040371, 0.7827717662, -0.8086757660],
]);

#[inline(always)]
fn apply(m: &[[f64; 3]; 3], v: [f64; 3]) -> [f64; 3] {
    let row = |r: usize| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2];
    [row(0), row(1), row(2)]
}

#[inline(always)]
fn cbrt3(v: [f64; 3]) -> [f64; 3] {
    [cbrt(v[0]), cbrt(v[1]), cbrt(v[2])]
}

/// The chroma of an Oklab colour (√(a² + b²): no overflow at these sizes).
#[inline(always)]
pub(super) fn chroma(lab: [f64; 3]) -> f64 {
    (lab[1] * lab[1] + lab[2] * lab[2]).sqrt()
}

/// ΔEOK: the Euclidean distance in Oklab.
#[inline(always)]
pub(super) fn distance(a: [f64; 3], b: [f64; 3]) -> f64 {
    let d = [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt()
}

/// A display space's matrices, combined with Oklab's.
#[derive(Debug, Clone, Copy)]
pub(super) struct Frame {
    lms_from_rgb: [[f64; 3]; 3],
    rgb_from_lms: [[f64; 3]; 3],
    lms_from_lab: [[f64; 3]; 3],
}

impl Frame {
    fn new(space: &RgbColorSpace) -> Self {
        let m1_inv = M1.inverse().expect("M1 is invertible");
        Self {
            lms_from_rgb: (M1 * space.xyz_from_rgb).0,
            rgb_from_lms: (space.rgb_from_xyz * m1_inv).0,
            lms_from_lab: M2.inverse().expect("M2 is invertible").0,
        }
    }

    /// Runs `f` with `space`'s frame: built once for the spaces scotopia
    /// knows, on the spot for any other.
    pub(super) fn with<R>(space: &RgbColorSpace, f: impl FnOnce(&Frame) -> R) -> R {
        static FRAMES: OnceLock<Vec<Frame>> = OnceLock::new();
        for (i, known) in RgbSpace::ALL.iter().enumerate() {
            if std::ptr::eq(known.def(), space) {
                let frames = FRAMES
                    .get_or_init(|| RgbSpace::ALL.iter().map(|s| Frame::new(s.def())).collect());
                return f(&frames[i]);
            }
        }
        f(&Frame::new(space))
    }

    #[inline(always)]
    pub(super) fn oklab_of_xyz(&self, xyz: [f64; 3]) -> [f64; 3] {
        apply(&M2.0, cbrt3(apply(&M1.0, xyz)))
    }

    #[inline(always)]
    pub(super) fn oklab_of_rgb(&self, rgb: [f64; 3]) -> [f64; 3] {
        apply(&M2.0, cbrt3(apply(&self.lms_from_rgb, rgb)))
    }
}

/// What clipping the colour at chroma C does: the clipped colour's
/// distance ΔEOK from the unclipped one, and that distance's slope dΔE/dC.
#[derive(Debug, Clone, Copy)]
pub(super) struct Clipped {
    pub e: f64,
    pub slope: f64,
}

/// The line of lightness `l` and a hue in a [`Frame`].
pub(super) struct HueLine<'a> {
    frame: &'a Frame,
    l: f64,
    /// The hue's (cos, sin).
    hue: (f64, f64),
    /// lms′ at chroma 0, and per unit chroma.
    base: [f64; 3],
    dir: [f64; 3],
}

impl<'a> HueLine<'a> {
    pub(super) fn new(frame: &'a Frame, l: f64, hue: (f64, f64)) -> Self {
        Self {
            frame,
            l,
            hue,
            base: apply(&frame.lms_from_lab, [l, 0.0, 0.0]),
            dir: apply(&frame.lms_from_lab, [0.0, hue.0, hue.1]),
        }
    }

    /// The colour's Oklab at chroma `c`.
    #[inline(always)]
    fn lab(&self, c: f64) -> [f64; 3] {
        [self.l, c * self.hue.0, c * self.hue.1]
    }

    /// Linear RGB at chroma `c`.
    #[inline(always)]
    pub(super) fn rgb(&self, c: f64) -> [f64; 3] {
        let t = |j: usize| {
            let t = self.base[j] + c * self.dir[j];
            t * t * t
        };
        apply(&self.frame.rgb_from_lms, [t(0), t(1), t(2)])
    }

    /// Linear RGB at chroma `c` with its first and second derivatives.
    #[inline(always)]
    fn rgb_derivatives(&self, c: f64) -> [[f64; 3]; 3] {
        let t: [f64; 3] = std::array::from_fn(|j| self.base[j] + c * self.dir[j]);
        let v = self.dir;
        let m = &self.frame.rgb_from_lms;
        [
            apply(m, std::array::from_fn(|j| t[j] * t[j] * t[j])),
            apply(m, std::array::from_fn(|j| 3.0 * t[j] * t[j] * v[j])),
            apply(m, std::array::from_fn(|j| 6.0 * t[j] * v[j] * v[j])),
        ]
    }

    /// Which channels clipping at chroma `c` moves, and to which face: a
    /// bit per channel and face.
    #[inline(always)]
    pub(super) fn clipped_channels(&self, c: f64) -> u8 {
        let rgb = self.rgb(c);
        (0..3).fold(0, |bits, i| {
            bits | u8::from(rgb[i] < 0.0) << (2 * i) | u8::from(rgb[i] > 1.0) << (2 * i + 1)
        })
    }

    /// Clipping at chroma `c`, without the slope.
    #[inline(always)]
    pub(super) fn clip_at(&self, c: f64) -> ([f64; 3], f64) {
        let lab = self.frame.oklab_of_rgb(clip(self.rgb(c)));
        (lab, distance(lab, self.lab(c)))
    }

    /// Clipping at chroma `c`, with the slope: unclipped channels move
    /// with the colour, clipped ones stay; the cube root's derivative is
    /// 1/(3 ∛x²).
    pub(super) fn clip_with_slope(&self, c: f64) -> Clipped {
        let [rgb, drgb, _] = self.rgb_derivatives(c);
        let moving = rgb.map(|x| x > 0.0 && x < 1.0);
        let q = clip(rgb);
        let dq: [f64; 3] = std::array::from_fn(|i| if moving[i] { drgb[i] } else { 0.0 });
        let lms = apply(&self.frame.lms_from_rgb, q);
        let dlms = apply(&self.frame.lms_from_rgb, dq);
        let root = cbrt3(lms);
        let droot: [f64; 3] = std::array::from_fn(|j| {
            if root[j] != 0.0 {
                dlms[j] / (3.0 * root[j] * root[j])
            } else {
                0.0
            }
        });
        let lab = apply(&M2.0, root);
        let dlab = apply(&M2.0, droot);
        let at = self.lab(c);
        let d = [lab[0] - at[0], lab[1] - at[1], lab[2] - at[2]];
        let dd = [dlab[0], dlab[1] - self.hue.0, dlab[2] - self.hue.1];
        let e = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
        let slope = (d[0] * dd[0] + d[1] * dd[1] + d[2] * dd[2]) / e;
        Clipped { e, slope }
    }

    /// Where the line leaves the RGB cube, by Halley's method from
    /// `start`: each channel followed toward the face it is heading for,
    /// the nearest crossing taken, until a step moves less than `settled`.
    /// Only the channels outside at `start` are followed when there are
    /// such (the line, on its way out to `start`, left through one of them).
    pub(super) fn boundary_estimate(&self, start: f64, settled: f64) -> f64 {
        let f = self.rgb(start);
        let outside = f.map(|x| !(0.0..=1.0).contains(&x));
        let follow = if outside.iter().any(|&o| o) {
            outside
        } else {
            [true; 3]
        };
        let mut c = start;
        for _ in 0..8 {
            let t: [f64; 3] = std::array::from_fn(|j| self.base[j] + c * self.dir[j]);
            let v = self.dir;
            let cube = [t[0] * t[0] * t[0], t[1] * t[1] * t[1], t[2] * t[2] * t[2]];
            let d1 = [t[0] * t[0] * v[0], t[1] * t[1] * v[1], t[2] * t[2] * v[2]];
            let d2 = [t[0] * v[0] * v[0], t[1] * v[1] * v[1], t[2] * v[2] * v[2]];
            let mut next = f64::INFINITY;
            for (&followed, row) in follow.iter().zip(&self.frame.rgb_from_lms) {
                if !followed {
                    continue;
                }
                let dot = |x: [f64; 3]| row[0] * x[0] + row[1] * x[1] + row[2] * x[2];
                let (f, df, ddf) = (dot(cube), 3.0 * dot(d1), 6.0 * dot(d2));
                let face = if f > 1.0 || (f >= 0.0 && df >= 0.0) {
                    1.0
                } else {
                    0.0
                };
                let g = f - face;
                let halley = 2.0 * df * df - g * ddf;
                // Halley's step where its denominator is safe, else Newton's.
                let step = if halley > df * df {
                    -2.0 * g * df / halley
                } else {
                    -g / df
                };
                let candidate = c + step;
                if candidate >= 0.0 && candidate < next {
                    next = candidate;
                }
            }
            if !next.is_finite() {
                return c;
            }
            let moved = (next - c).abs();
            c = next;
            if moved <= settled {
                break;
            }
        }
        c
    }

    /// How fast the clip distance grows with chroma just past `edge`, a
    /// point on the gamut's boundary: there the clip is the colour
    /// itself, so no cube root is needed — only the channels that leave
    /// stop moving.
    pub(super) fn exit_slope(&self, edge: f64) -> f64 {
        let [rgb, drgb, _] = self.rgb_derivatives(edge);
        let leaving =
            |i: usize| (rgb[i] >= 1.0 - 1e-9 && drgb[i] > 0.0) || (rgb[i] <= 1e-9 && drgb[i] < 0.0);
        let dq: [f64; 3] = std::array::from_fn(|i| if leaving(i) { 0.0 } else { drgb[i] });
        let dlms = apply(&self.frame.lms_from_rgb, dq);
        let t: [f64; 3] = std::array::from_fn(|j| self.base[j] + edge * self.dir[j]);
        let droot: [f64; 3] = std::array::from_fn(|j| dlms[j] / (3.0 * t[j] * t[j]));
        let dlab = apply(&M2.0, droot);
        let dd = [dlab[0], dlab[1] - self.hue.0, dlab[2] - self.hue.1];
        (dd[0] * dd[0] + dd[1] * dd[1] + dd[2] * dd[2]).sqrt()
    }
}

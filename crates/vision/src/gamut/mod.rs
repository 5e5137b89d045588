//! Gamut mapping to a display's primaries by CSS Color 4's algorithm
//! (W3C CSS Color Module Level 4, §13.2 "binary search gamut mapping with
//! local MINDE"; ../shared/vision-equations.md §7): reduce chroma in OkLCh
//! at constant lightness and hue until clipping the colour moves it less
//! than a just-noticeable difference, then clip. Unlike clipping each
//! channel, hue and lightness survive; colours already in gamut are
//! returned unchanged.
//!
//! One step is scotopia's own: that final clip may turn the hue by several
//! degrees (6° for Rec.2020 blue into sRGB, where Oklab's blue bends), so
//! the clipped colour's lightness and chroma are put back on the original
//! hue, its chroma lowered to the gamut boundary if that leaves it
//! outside. The result stays within about one JND of CSS's (at most 0.023
//! ΔEOK on the test colours) and keeps the hue exactly (docs/vision.md).
//!
//! [`map_to_gamut`] gives [`map_to_gamut_reference`]'s result (the
//! algorithm step by step, kept as the oracle) for a fraction of the
//! cost. On a line of constant lightness and hue each linear RGB channel
//! is a cubic in chroma, and the clip distance's slope has a closed form,
//! so the CSS search's outcome can be predicted: where the distance
//! crosses JND − ε and JND, from a parabola that starts at the gamut
//! boundary (Halley's method) and then Newton's method. The bisection is
//! replayed against the prediction and only the steps that settle it are
//! evaluated — the chroma where it stops, the final bracket, and any step
//! near a crossing where another channel starts clipping (the distance
//! can turn there); a prediction that fails is refined, or the search run
//! step by step. The hue restoration's bisection runs as the reference's,
//! without branches. A colour on the gamut's surface to rounding, where
//! the two computations could fall on either side, takes the reference.
//! Cube roots are [`crate::wide_math::cbrt`]'s (a few ulps).

mod line;
mod reference;
mod search;

pub use reference::map_to_gamut_reference;

use line::{Frame, HueLine};
use scotopia_color::space::RgbColorSpace;

/// ΔEOK of a just-noticeable difference (CSS Color 4).
pub const JND: f64 = 0.02;
/// Chroma resolution of the search (CSS Color 4's ε).
pub const EPSILON: f64 = 0.0001;

#[inline(always)]
fn in_gamut(rgb: [f64; 3]) -> bool {
    let inside = |c: f64| (0.0..=1.0).contains(&c);
    inside(rgb[0]) && inside(rgb[1]) && inside(rgb[2])
}

#[inline(always)]
fn clip(rgb: [f64; 3]) -> [f64; 3] {
    let clip = |c: f64| if c.is_nan() { 0.0 } else { c.clamp(0.0, 1.0) };
    [clip(rgb[0]), clip(rgb[1]), clip(rgb[2])]
}

/// Maps XYZ (relative: the display's white has Y = 1, D65) into `space`'s
/// gamut, returning linear RGB in [0, 1]: [`map_to_gamut_reference`]'s
/// result, to rounding (its tests bound the difference).
pub fn map_to_gamut(xyz: [f64; 3], space: &RgbColorSpace) -> [f64; 3] {
    // `space.xyz_to_rgb`, inlined: the same products and sums.
    let m = &space.rgb_from_xyz.0;
    let row = |r: usize| m[r][0] * xyz[0] + m[r][1] * xyz[1] + m[r][2] * xyz[2];
    let rgb = [row(0), row(1), row(2)];
    if in_gamut(rgb) {
        return rgb;
    }
    Frame::with(space, |frame| {
        map_outside(frame, xyz, rgb).unwrap_or_else(|| map_to_gamut_reference(xyz, space))
    })
}

/// An out-of-gamut colour (`xyz`, its `rgb`) mapped; `None` where the
/// fast path cannot vouch for its answer.
fn map_outside(frame: &Frame, xyz: [f64; 3], rgb: [f64; 3]) -> Option<[f64; 3]> {
    // The origin in Oklab, and the clipped colour's Oklab: independent,
    // so their cube roots overlap.
    let origin = frame.oklab_of_xyz(xyz);
    let clipped_lab = frame.oklab_of_rgb(clip(rgb));
    let l = origin[0];
    // Beyond white or black there is no chroma to keep.
    if l >= 1.0 {
        return Some([1.0; 3]);
    }
    if l.is_nan() || l <= 0.0 {
        return Some([0.0; 3]);
    }
    let c = line::chroma(origin);
    if !(c > 0.0 && c.is_finite()) {
        return None;
    }
    // The hue's cosine and sine (a/C, b/C: what OkLCh's h gives, to an ulp).
    let hue = (origin[1] / c, origin[2] / c);
    let e0 = line::distance(clipped_lab, origin);
    let lab = if e0 < JND {
        clipped_lab
    } else {
        let line = HueLine::new(frame, l, hue);
        search::css_color_4(&line, c, e0)?
    };
    search::restore_hue(frame, lab, hue)
}

#[cfg(test)]
mod tests;

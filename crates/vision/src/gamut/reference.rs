//! The reference: CSS Color 4's binary search with local MINDE and
//! scotopia's hue restoration exactly as specified (../../shared/
//! vision-equations.md §7), through `scotopia_color`'s Oklab and libm's
//! correctly rounded cube root. [`super::map_to_gamut`] gives its results
//! faster; the tests hold the two together.

use super::{clip, in_gamut, EPSILON, JND};
use scotopia_color::space::{
    delta_e_ok, oklab_to_oklch, oklab_to_xyz, xyz_to_oklab, RgbColorSpace,
};

/// [`super::map_to_gamut`] by the letter of the algorithm: XYZ (relative,
/// the display's white at Y = 1, D65) into `space`'s gamut, as linear RGB
/// in [0, 1].
pub fn map_to_gamut_reference(xyz: [f64; 3], space: &RgbColorSpace) -> [f64; 3] {
    let rgb = space.xyz_to_rgb(xyz);
    if in_gamut(rgb) {
        return rgb;
    }
    let origin = xyz_to_oklab(xyz);
    let lch = oklab_to_oklch(origin);
    let l = lch[0];
    // Beyond white or black there is no chroma to keep.
    if l >= 1.0 {
        return [1.0; 3];
    }
    if l.is_nan() || l <= 0.0 {
        return [0.0; 3];
    }
    // The hue's sine and cosine, for both searches (taken once).
    let hue = lch[2].to_radians().sin_cos();
    let (_, clipped_lab) = css_color_4(rgb, origin, lch, hue, space);
    restore_hue(clipped_lab, hue, space)
}

/// OkLCh → Oklab at a hue fixed by its (sine, cosine): the searches below
/// move chroma only, so the hue's sine and cosine are taken once
/// (`oklch_to_oklab` computes the same products).
fn oklab_at(l: f64, chroma: f64, (sin, cos): (f64, f64)) -> [f64; 3] {
    [l, chroma * cos, chroma * sin]
}

/// CSS Color 4's binary search with local MINDE, for an out-of-gamut
/// colour (`rgb` in `space`, `origin` in Oklab and `lch` in OkLCh,
/// 0 < L < 1; `hue` the sine and cosine of its hue). Returns the result
/// with its Oklab, which the search computed (restoring the hue needs it).
pub(super) fn css_color_4(
    rgb: [f64; 3],
    origin: [f64; 3],
    lch: [f64; 3],
    hue: (f64, f64),
    space: &RgbColorSpace,
) -> ([f64; 3], [f64; 3]) {
    let [l, c, _] = lch;
    let oklab_of = |rgb: [f64; 3]| xyz_to_oklab(space.rgb_to_xyz(rgb));
    let mut clipped = clip(rgb);
    let mut clipped_lab = oklab_of(clipped);
    if delta_e_ok(clipped_lab, origin) < JND {
        return (clipped, clipped_lab);
    }
    let (mut min, mut max, mut min_in_gamut) = (0.0, c, true);
    while max - min > EPSILON {
        let chroma = 0.5 * (min + max);
        let current = oklab_at(l, chroma, hue);
        let rgb = space.xyz_to_rgb(oklab_to_xyz(current));
        if min_in_gamut && in_gamut(rgb) {
            min = chroma;
            continue;
        }
        clipped = clip(rgb);
        clipped_lab = oklab_of(clipped);
        let e = delta_e_ok(clipped_lab, current);
        if e < JND {
            if JND - e < EPSILON {
                return (clipped, clipped_lab);
            }
            min_in_gamut = false;
            min = chroma;
        } else {
            max = chroma;
        }
    }
    (clipped, clipped_lab)
}

/// The in-gamut colour whose Oklab is `lab` turned back to the hue whose
/// sine and cosine are `hue`, at its own OkLCh lightness and chroma, with
/// chroma lowered (bisection to ε) until the result is in gamut; grey at
/// that lightness always is.
fn restore_hue(lab: [f64; 3], hue: (f64, f64), space: &RgbColorSpace) -> [f64; 3] {
    let [l, c, _] = oklab_to_oklch(lab);
    let at = |chroma: f64| space.xyz_to_rgb(oklab_to_xyz(oklab_at(l, chroma, hue)));
    let full = at(c);
    if in_gamut(full) {
        return full;
    }
    let (mut lo, mut hi) = (0.0, c);
    while hi - lo > EPSILON {
        let mid = 0.5 * (lo + hi);
        if in_gamut(at(mid)) {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    clip(at(lo))
}

#[cfg(test)]
mod tests {
    use super::*;
    use scotopia_color::space::RgbSpace;

    fn hue(xyz: [f64; 3]) -> f64 {
        oklab_to_oklch(xyz_to_oklab(xyz))[2]
    }

    #[test]
    fn in_gamut_colours_are_unchanged() {
        let srgb = RgbSpace::Srgb.def();
        for rgb in [
            [0.2, 0.5, 0.9],
            [1.0, 1.0, 1.0],
            [0.0, 0.3, 0.0],
            [0.7, 0.1, 0.4],
        ] {
            let out = map_to_gamut_reference(srgb.rgb_to_xyz(rgb), srgb);
            for k in 0..3 {
                assert!((out[k] - rgb[k]).abs() < 1e-12, "{rgb:?} → {out:?}");
            }
        }
    }

    #[test]
    fn out_of_gamut_colours_land_inside_with_their_hue() {
        // Saturated Rec.2020 and spectral-locus-like colours into sRGB and
        // P3, at several lightnesses.
        let rec2020 = RgbSpace::Rec2020.def();
        let mut worst_hue = 0.0f64;
        for space in [RgbSpace::Srgb.def(), RgbSpace::DisplayP3.def()] {
            for rgb in [
                [1.0, 0.0, 0.0],
                [0.0, 1.0, 0.0],
                [0.0, 0.0, 1.0],
                [0.0, 0.8, 0.9],
                [0.9, 0.0, 0.8],
                [0.6, 0.55, 0.0],
                [0.05, 0.3, 0.02],
                [0.3, 0.02, 0.05],
            ] {
                let xyz = rec2020.rgb_to_xyz(rgb);
                let out = map_to_gamut_reference(xyz, space);
                assert!(out.iter().all(|c| (0.0..=1.0).contains(c)), "{out:?}");
                let dh = (hue(space.rgb_to_xyz(out)) - hue(xyz) + 540.0).rem_euclid(360.0) - 180.0;
                worst_hue = worst_hue.max(dh.abs());
                let origin = xyz_to_oklab(xyz);
                let lch = oklab_to_oklch(origin);
                let hue = lch[2].to_radians().sin_cos();
                let (css, css_lab) = css_color_4(space.xyz_to_rgb(xyz), origin, lch, hue, space);
                // The Oklab it returns is its result's.
                assert_eq!(css_lab, xyz_to_oklab(space.rgb_to_xyz(css)));
                let ok = |rgb: [f64; 3]| xyz_to_oklab(space.rgb_to_xyz(rgb));
                // Within about one JND of CSS Color 4's own answer.
                assert!(delta_e_ok(ok(out), ok(css)) < 1.5 * JND, "{rgb:?}");
            }
        }
        assert!(worst_hue < 1.0, "hue moved {worst_hue}°");
        // Per-channel clipping of the same colours moves hue far more (the
        // test can fail): pure Rec.2020 green clipped into sRGB.
        let xyz = rec2020.rgb_to_xyz([0.05, 0.3, 0.02]);
        let srgb = RgbSpace::Srgb.def();
        let naive = clip(srgb.xyz_to_rgb(xyz));
        let dh = (hue(srgb.rgb_to_xyz(naive)) - hue(xyz) + 540.0).rem_euclid(360.0) - 180.0;
        assert!(dh.abs() > 1.0, "{dh}");
    }

    #[test]
    fn beyond_white_is_white_and_black_is_black() {
        let srgb = RgbSpace::Srgb.def();
        assert_eq!(map_to_gamut_reference([2.0, 2.1, 2.0], srgb), [1.0; 3]);
        assert_eq!(map_to_gamut_reference([0.0, 0.0, 0.0], srgb), [0.0; 3]);
    }
}

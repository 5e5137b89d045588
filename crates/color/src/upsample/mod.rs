//! RGB → spectrum, three methods behind one interface, each producing the
//! three kinds of spectrum a renderer needs:
//!
//! - `Reflectance`: RGB in [0, 1]³, a spectrum in [0, 1] whose colour under
//!   the space's white illuminant is the RGB.
//! - `Unbounded`: any non-negative RGB, m·2 · reflectance(RGB / (2m)) with m
//!   the largest component — half-height reflectances are smooth, far from the
//!   sigmoid's box-like limit (the same choice as pbrt-v4).
//! - `Illuminant`: the unbounded spectrum times the space's white
//!   illuminant normalised to unit luminance-weighted mean, so RGB (1, 1, 1)
//!   emits the space's white as brightly as an equal-energy radiance of 1.

pub mod jakob2019;
mod primaries;
mod roundtrip;
mod smits;
pub mod weights;

use std::sync::Arc;

pub use roundtrip::{rgb_cube, round_trip, round_trip_colours, RoundTrip};

use crate::error::ColorError;
use crate::space::RgbSpace;
use crate::spectrum::{RgbSigmoid, Spectrum, Tabulated};
use crate::{LAMBDA_MAX, LAMBDA_MIN};

/// How an RGB colour becomes a spectrum.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum UpsampleMethod {
    /// Jakob & Hanika 2019: sigmoid of a quadratic (the default).
    Jakob2019,
    /// Smits 1999: sums of seven fixed basis spectra.
    Smits,
    /// Naive: three boxes weighted by R, G, B (a baseline only).
    Primaries,
}

impl UpsampleMethod {
    pub const ALL: [UpsampleMethod; 3] = [
        UpsampleMethod::Jakob2019,
        UpsampleMethod::Smits,
        UpsampleMethod::Primaries,
    ];

    pub fn name(self) -> &'static str {
        match self {
            UpsampleMethod::Jakob2019 => "jakob2019",
            UpsampleMethod::Smits => "smits",
            UpsampleMethod::Primaries => "primaries",
        }
    }

    pub fn from_name(name: &str) -> Result<Self, ColorError> {
        Self::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(name.trim()))
            .ok_or_else(|| ColorError::UnknownName {
                what: "RGB-to-spectrum method",
                name: name.into(),
                known: "jakob2019, smits, primaries".into(),
            })
    }
}

/// What the spectrum will be used as.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum SpectrumKind {
    Reflectance,
    Unbounded,
    Illuminant,
}

impl SpectrumKind {
    pub const ALL: [SpectrumKind; 3] = [
        SpectrumKind::Reflectance,
        SpectrumKind::Unbounded,
        SpectrumKind::Illuminant,
    ];

    pub fn name(self) -> &'static str {
        match self {
            SpectrumKind::Reflectance => "reflectance",
            SpectrumKind::Unbounded => "unbounded",
            SpectrumKind::Illuminant => "illuminant",
        }
    }

    pub fn from_name(name: &str) -> Result<Self, ColorError> {
        Self::ALL
            .into_iter()
            .find(|k| k.name().eq_ignore_ascii_case(name.trim()))
            .ok_or_else(|| ColorError::UnknownName {
                what: "spectrum kind",
                name: name.into(),
                known: "reflectance, unbounded, illuminant".into(),
            })
    }
}

/// The reflectance spectrum of `rgb` ∈ [0, 1]³ by `method` (no checks).
fn reflectance(
    rgb: [f32; 3],
    space: RgbSpace,
    method: UpsampleMethod,
) -> Result<Spectrum, ColorError> {
    if rgb == [0.0; 3] {
        return Ok(Spectrum::Constant(0.0));
    }
    Ok(match method {
        UpsampleMethod::Jakob2019 => Spectrum::Sigmoid(RgbSigmoid {
            coeffs: jakob2019::coefficients(rgb, space)?,
            scale: 1.0,
            illuminant: None,
        }),
        UpsampleMethod::Smits => Spectrum::tabulated(smits::reflectance(rgb)),
        UpsampleMethod::Primaries => Spectrum::tabulated(primaries::reflectance(rgb)),
    })
}

/// Multiplies a spectrum by a tabulated illuminant.
fn times_illuminant(s: Spectrum, illuminant: &Arc<Tabulated>) -> Spectrum {
    match s {
        Spectrum::Sigmoid(g) => Spectrum::Sigmoid(RgbSigmoid {
            illuminant: Some(illuminant.clone()),
            ..g
        }),
        Spectrum::Constant(0.0) => Spectrum::Constant(0.0),
        other => Spectrum::tabulated(Tabulated::from_fn(LAMBDA_MIN, LAMBDA_MAX, 1.0, |l| {
            other.eval(l) * illuminant.eval(l)
        })),
    }
}

/// The spectrum of linear RGB colour `rgb` in `space`, by `method`, for use
/// as `kind`. Errors for negative or non-finite components (outside the
/// space's gamut) and for reflectances above 1.
pub fn rgb_to_spectrum(
    rgb: [f32; 3],
    space: RgbSpace,
    method: UpsampleMethod,
    kind: SpectrumKind,
) -> Result<Spectrum, ColorError> {
    if rgb.iter().any(|v| !v.is_finite() || *v < 0.0) {
        return Err(ColorError::InvalidRgb(format!(
            "RGB {rgb:?} has a negative or non-finite component: it is outside the {} gamut",
            space.name()
        )));
    }
    let m = rgb.iter().copied().fold(0.0f32, f32::max);
    match kind {
        SpectrumKind::Reflectance => {
            if m > 1.0 {
                return Err(ColorError::InvalidRgb(format!(
                    "reflectance RGB {rgb:?} has a component above 1; use the unbounded or \
                     illuminant kind for brighter colours"
                )));
            }
            reflectance(rgb, space, method)
        }
        SpectrumKind::Unbounded | SpectrumKind::Illuminant => {
            let unbounded = if m == 0.0 {
                Spectrum::Constant(0.0)
            } else {
                let scale = 2.0 * m;
                reflectance(rgb.map(|v| v / scale), space, method)?.scaled(scale)
            };
            Ok(if kind == SpectrumKind::Illuminant {
                times_illuminant(unbounded, &space.def().illuminant_normalised)
            } else {
                unbounded
            })
        }
    }
}

/// Jakob & Hanika 2019 coefficients and scale of one texel: the spectrum is
/// `scale · S(poly(coeffs))`, times the space's normalised illuminant for
/// the illuminant kind (which the caller applies once per texture). A
/// reflectance is clamped to [0, 1]³ (a texture may exceed it by rounding
/// or by an EXR's range); emission is scaled as in `rgb_to_spectrum`.
/// Non-finite or negative components count as 0.
pub fn jakob2019_texel(
    rgb: [f32; 3],
    space: RgbSpace,
    kind: SpectrumKind,
) -> Result<([f32; 3], f32), ColorError> {
    let rgb = rgb.map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 });
    let m = rgb.iter().copied().fold(0.0f32, f32::max);
    if m == 0.0 {
        return Ok(([0.0; 3], 0.0));
    }
    match kind {
        SpectrumKind::Reflectance => Ok((
            jakob2019::coefficients(rgb.map(|v| v.min(1.0)), space)?,
            1.0,
        )),
        SpectrumKind::Unbounded | SpectrumKind::Illuminant => {
            let scale = 2.0 * m;
            Ok((
                jakob2019::coefficients(rgb.map(|v| v / scale), space)?,
                scale,
            ))
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texels_match_rgb_to_spectrum() {
        let space = RgbSpace::Srgb;
        for (rgb, kind) in [
            ([0.2, 0.5, 0.7], SpectrumKind::Reflectance),
            ([3.0, 0.5, 0.1], SpectrumKind::Unbounded),
            ([0.9, 0.9, 0.2], SpectrumKind::Illuminant),
        ] {
            let (coeffs, scale) = jakob2019_texel(rgb, space, kind).unwrap();
            let s = rgb_to_spectrum(rgb, space, UpsampleMethod::Jakob2019, kind).unwrap();
            let illuminant = &space.def().illuminant_normalised;
            for l in (360..=830).step_by(10) {
                let l = l as f32;
                let mut v = scale * RgbSigmoid::reflectance(&coeffs, l);
                if kind == SpectrumKind::Illuminant {
                    v *= illuminant.eval(l);
                }
                assert!(
                    (v - s.eval(l)).abs() <= 1e-6 * s.eval(l).max(1.0),
                    "{rgb:?} {l}"
                );
            }
        }
        assert_eq!(
            jakob2019_texel([0.0; 3], space, SpectrumKind::Reflectance).unwrap(),
            ([0.0; 3], 0.0)
        );
        // Out-of-range reflectance is clamped, not an error.
        let (c, s) =
            jakob2019_texel([1.5, -0.2, f32::NAN], space, SpectrumKind::Reflectance).unwrap();
        assert_eq!(
            (c, s),
            jakob2019_texel([1.0, 0.0, 0.0], space, SpectrumKind::Reflectance).unwrap()
        );
    }

    #[test]
    fn names_parse() {
        for m in UpsampleMethod::ALL {
            assert_eq!(UpsampleMethod::from_name(m.name()).unwrap(), m);
        }
        for k in SpectrumKind::ALL {
            assert_eq!(SpectrumKind::from_name(k.name()).unwrap(), k);
        }
        assert!(UpsampleMethod::from_name("magic").is_err());
    }

    #[test]
    fn bad_rgb_is_an_error() {
        let go = |rgb, kind| rgb_to_spectrum(rgb, RgbSpace::Srgb, UpsampleMethod::Smits, kind);
        assert!(go([-0.1, 0.5, 0.5], SpectrumKind::Unbounded).is_err());
        assert!(go([f32::NAN, 0.5, 0.5], SpectrumKind::Unbounded).is_err());
        let e = go([1.5, 0.5, 0.5], SpectrumKind::Reflectance)
            .unwrap_err()
            .to_string();
        assert!(e.contains("unbounded"), "{e}");
        assert!(go([1.5, 0.5, 0.5], SpectrumKind::Unbounded).is_ok());
        assert_eq!(
            go([0.0; 3], SpectrumKind::Illuminant).unwrap(),
            Spectrum::Constant(0.0)
        );
    }

    #[test]
    fn unbounded_scales_linearly_for_linear_methods() {
        for method in [UpsampleMethod::Smits, UpsampleMethod::Primaries] {
            let a = rgb_to_spectrum(
                [0.2, 0.4, 0.1],
                RgbSpace::Srgb,
                method,
                SpectrumKind::Unbounded,
            )
            .unwrap();
            let b = rgb_to_spectrum(
                [2.0, 4.0, 1.0],
                RgbSpace::Srgb,
                method,
                SpectrumKind::Unbounded,
            )
            .unwrap();
            for l in (360..=830).step_by(10) {
                let l = l as f32;
                assert!((b.eval(l) - 10.0 * a.eval(l)).abs() < 1e-5 * b.eval(l).max(1.0));
            }
        }
    }
}

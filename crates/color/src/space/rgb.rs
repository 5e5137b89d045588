//! Linear RGB colour spaces defined by their primaries and white point; the
//! XYZ ↔ RGB matrices are derived from them (SMPTE RP 177-1993 §3.3).

use std::sync::{Arc, OnceLock};

use super::Mat3;
use crate::cie;
use crate::error::ColorError;
use crate::photometry::integrate_observers;
use crate::spectrum::{Spectrum, Tabulated};

/// The RGB spaces scotopia knows.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum RgbSpace {
    /// IEC 61966-2-1 sRGB (ITU-R BT.709 primaries), D65.
    Srgb,
    /// Display P3: SMPTE EG 432-1 (DCI-P3) primaries, D65.
    DisplayP3,
    /// ITU-R BT.2020 primaries, D65.
    Rec2020,
    /// ACEScg: ACES AP1 primaries (SMPTE ST 2065-1 / Academy S-2014-004), ACES white.
    AcesCg,
}

impl RgbSpace {
    pub const ALL: [RgbSpace; 4] = [
        RgbSpace::Srgb,
        RgbSpace::DisplayP3,
        RgbSpace::Rec2020,
        RgbSpace::AcesCg,
    ];

    /// The command-line name.
    pub fn name(self) -> &'static str {
        match self {
            RgbSpace::Srgb => "srgb",
            RgbSpace::DisplayP3 => "p3",
            RgbSpace::Rec2020 => "rec2020",
            RgbSpace::AcesCg => "acescg",
        }
    }

    /// Parses a name (`srgb`, `p3`, `rec2020`, `acescg`, and common spellings).
    pub fn from_name(name: &str) -> Result<Self, ColorError> {
        let n: String = name
            .chars()
            .filter(|c| c.is_ascii_alphanumeric())
            .collect::<String>()
            .to_ascii_lowercase();
        Ok(match n.as_str() {
            "srgb" | "rec709" | "bt709" => RgbSpace::Srgb,
            "p3" | "displayp3" | "p3d65" => RgbSpace::DisplayP3,
            "rec2020" | "bt2020" => RgbSpace::Rec2020,
            "acescg" | "ap1" => RgbSpace::AcesCg,
            _ => {
                return Err(ColorError::UnknownName {
                    what: "colour space",
                    name: name.to_string(),
                    known: "srgb, p3, rec2020, acescg".into(),
                })
            }
        })
    }

    /// The space's definition, built once.
    pub fn def(self) -> &'static RgbColorSpace {
        static SPACES: OnceLock<Vec<RgbColorSpace>> = OnceLock::new();
        let spaces = SPACES.get_or_init(|| RgbSpace::ALL.iter().map(|s| s.build()).collect());
        &spaces[self as usize]
    }

    fn build(self) -> RgbColorSpace {
        const D65: [f64; 2] = [0.3127, 0.3290];
        let d65 = || cie::illuminant("D65").expect("D65 is built in");
        let (primaries, white, illuminant) = match self {
            RgbSpace::Srgb => ([[0.64, 0.33], [0.30, 0.60], [0.15, 0.06]], D65, d65()),
            RgbSpace::DisplayP3 => ([[0.680, 0.320], [0.265, 0.690], [0.150, 0.060]], D65, d65()),
            RgbSpace::Rec2020 => ([[0.708, 0.292], [0.170, 0.797], [0.131, 0.046]], D65, d65()),
            RgbSpace::AcesCg => (
                [[0.713, 0.293], [0.165, 0.830], [0.128, 0.044]],
                // ACES white, Academy TB-2014-004: CIE daylight at 6000 K ("D60").
                [0.32168, 0.33767],
                Spectrum::tabulated(cie::daylight(6000.0).expect("6000 K is in range")),
            ),
        };
        RgbColorSpace::new(self.name(), primaries, white, illuminant)
            .expect("built-in primaries are independent")
    }
}

/// A linear RGB space: primaries, white point, the spectral illuminant of
/// its white (for reflectance round trips and emission), and the matrices.
#[derive(Debug, Clone)]
pub struct RgbColorSpace {
    pub name: &'static str,
    pub primaries: [[f64; 2]; 3],
    pub white: [f64; 2],
    /// Spectral power of the white illuminant, as the CIE tabulates it.
    pub illuminant: Spectrum,
    /// The illuminant scaled to a luminance-weighted mean of 1
    /// (∫ I ȳ dλ = ∫ ȳ dλ): an RGB emitter of (1, 1, 1) is as bright as an
    /// equal-energy radiance of 1 W·sr⁻¹·m⁻²·nm⁻¹.
    pub illuminant_normalised: Arc<Tabulated>,
    pub xyz_from_rgb: Mat3,
    pub rgb_from_xyz: Mat3,
}

/// XYZ with Y = 1 of the chromaticity (x, y).
pub fn xy_to_xyz([x, y]: [f64; 2]) -> [f64; 3] {
    [x / y, 1.0, (1.0 - x - y) / y]
}

impl RgbColorSpace {
    /// Derives the matrices: the columns of XYZ←RGB are the primaries' XYZ,
    /// scaled so that RGB (1, 1, 1) maps to the white with Y = 1.
    pub fn new(
        name: &'static str,
        primaries: [[f64; 2]; 3],
        white: [f64; 2],
        illuminant: Spectrum,
    ) -> Result<Self, ColorError> {
        let p = Mat3::from_columns(primaries.map(xy_to_xyz));
        let p_inv = p.inverse().ok_or_else(|| {
            ColorError::OutOfRange(format!("{name}: primaries are not linearly independent"))
        })?;
        let s = p_inv.apply(xy_to_xyz(white));
        let xyz_from_rgb = p * Mat3::diagonal(s);
        let rgb_from_xyz = xyz_from_rgb.inverse().ok_or_else(|| {
            ColorError::OutOfRange(format!("{name}: white point gives a singular matrix"))
        })?;
        let y_mean =
            integrate_observers(&illuminant)[1] / integrate_observers(&Spectrum::Constant(1.0))[1];
        let table = match &illuminant {
            Spectrum::Tabulated(t) => (**t).clone(),
            other => Tabulated::from_fn(300.0, 830.0, 1.0, |l| other.eval(l)),
        };
        Ok(Self {
            name,
            primaries,
            white,
            illuminant_normalised: Arc::new(table.scaled((1.0 / y_mean) as f32)),
            illuminant,
            xyz_from_rgb,
            rgb_from_xyz,
        })
    }

    /// White point XYZ with Y = 1.
    pub fn white_xyz(&self) -> [f64; 3] {
        xy_to_xyz(self.white)
    }

    pub fn rgb_to_xyz(&self, rgb: [f64; 3]) -> [f64; 3] {
        self.xyz_from_rgb.apply(rgb)
    }

    pub fn xyz_to_rgb(&self, xyz: [f64; 3]) -> [f64; 3] {
        self.rgb_from_xyz.apply(xyz)
    }

    /// Matrix taking this space's RGB to `other`'s, with no chromatic
    /// adaptation (XYZ is shared); adapt explicitly when whites differ.
    pub fn to_space(&self, other: &RgbColorSpace) -> Mat3 {
        other.rgb_from_xyz * self.xyz_from_rgb
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn srgb_matrix_matches_iec_61966_2_1() {
        // IEC 61966-2-1 (amended) XYZ←RGB to 4 decimals.
        let m = RgbSpace::Srgb.def().xyz_from_rgb.0;
        let expected = [
            [0.4124, 0.3576, 0.1805],
            [0.2126, 0.7152, 0.0722],
            [0.0193, 0.1192, 0.9505],
        ];
        for r in 0..3 {
            for c in 0..3 {
                assert!(
                    (m[r][c] - expected[r][c]).abs() < 1.5e-4,
                    "{r},{c}: {}",
                    m[r][c]
                );
            }
        }
    }

    #[test]
    fn white_maps_to_white_and_names_parse() {
        for space in RgbSpace::ALL {
            let d = space.def();
            let xyz = d.rgb_to_xyz([1.0, 1.0, 1.0]);
            let w = d.white_xyz();
            for k in 0..3 {
                assert!((xyz[k] - w[k]).abs() < 1e-12);
            }
            assert_eq!(RgbSpace::from_name(space.name()).unwrap(), space);
            let y =
                integrate_observers(&Spectrum::tabulated((*d.illuminant_normalised).clone()))[1];
            assert!((y / integrate_observers(&Spectrum::Constant(1.0))[1] - 1.0).abs() < 1e-5);
        }
        assert_eq!(
            RgbSpace::from_name("Display-P3").unwrap(),
            RgbSpace::DisplayP3
        );
        assert!(RgbSpace::from_name("cmyk")
            .unwrap_err()
            .to_string()
            .contains("srgb, p3"));
    }
}

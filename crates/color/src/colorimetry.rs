//! What `scotopia spectrum` reports about one spectrum: its absolute
//! photometry with the chromaticity, CCT and S/P ratio that follow from it.

use crate::cct::{cct_from_xy, Cct};
use crate::photometry::{spectrum_to_xyzv, Xyzv};
use crate::spectrum::Spectrum;
use crate::{LAMBDA_MAX, LAMBDA_MIN};

/// Everything `scotopia spectrum` reports about one spectrum.
#[derive(Debug, Clone, PartialEq)]
pub struct Colorimetry {
    /// Absolute X, Y, Z, V′ (the spectrum read as radiance in W·sr⁻¹·m⁻²·nm⁻¹;
    /// a reflectance under an equal-energy illuminant of 1 W·sr⁻¹·m⁻²·nm⁻¹).
    pub xyzv: Xyzv,
    pub xy: Option<[f64; 2]>,
    /// CCT and Duv; `None` when the chromaticity is farther than 0.05 from the
    /// Planckian locus or outside 1000–100000 K, where CCT has no meaning.
    pub cct: Option<Cct>,
    pub sp_ratio: Option<f64>,
    /// 360, 361, …, 830 nm.
    pub wavelengths: Vec<u32>,
    pub values: Vec<f32>,
}

impl Colorimetry {
    pub fn of(s: &Spectrum) -> Self {
        let xyzv = spectrum_to_xyzv(s);
        let xy = xyzv.xy();
        let cct = xy.and_then(cct_from_xy).filter(|c| c.duv.abs() <= 0.05);
        Self {
            xyzv,
            xy,
            cct,
            sp_ratio: xyzv.sp_ratio(),
            wavelengths: (LAMBDA_MIN as u32..=LAMBDA_MAX as u32).collect(),
            values: s.on_grid(LAMBDA_MIN, LAMBDA_MAX, 1.0),
        }
    }
}

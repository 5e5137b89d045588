//! The CIE daylight (D-series) illuminants for any correlated colour
//! temperature from 4000 K to 25000 K, CIE 015:2018 §4.1.2.

use std::sync::OnceLock;

use crate::error::ColorError;
use crate::io::{parse_table, Table};
use crate::spectrum::Tabulated;

const BASIS_CSV: &str = include_str!("../../../../data/cie/daylight_basis_s0_s1_s2.csv");

fn basis() -> &'static Table {
    static BASIS: OnceLock<Table> = OnceLock::new();
    BASIS.get_or_init(|| {
        // Embedded table, part of the build.
        parse_table(BASIS_CSV, "data/cie/daylight_basis_s0_s1_s2.csv", 3, true)
            .expect("embedded daylight basis")
    })
}

/// Chromaticity (x_D, y_D) of CIE daylight at `cct` kelvin, CIE 015:2018 eq. 4.7–4.9.
pub fn daylight_chromaticity(cct: f64) -> Result<[f64; 2], ColorError> {
    if !(4000.0..=25000.0).contains(&cct) {
        return Err(ColorError::OutOfRange(format!(
            "CIE daylight is defined from 4000 K to 25000 K, got {cct} K"
        )));
    }
    let (t, t2, t3) = (cct, cct * cct, cct * cct * cct);
    // CIE 015:2018 eq. 4.7 (4000–7000 K) and 4.8 (7000–25000 K).
    let x = if cct <= 7000.0 {
        -4.6070e9 / t3 + 2.9678e6 / t2 + 0.09911e3 / t + 0.244063
    } else {
        -2.0064e9 / t3 + 1.9018e6 / t2 + 0.24748e3 / t + 0.237040
    };
    // CIE 015:2018 eq. 4.9.
    let y = -3.000 * x * x + 2.870 * x - 0.275;
    Ok([x, y])
}

/// S(λ) = S₀ + M₁S₁ + M₂S₂, CIE 015:2018 eq. 4.10–4.11, 300–830 nm at 5 nm,
/// with M₁, M₂ rounded to three decimals as CIE 015:2018 §4.1.2 prescribes
/// (so generated and tabulated D illuminants agree).
fn from_chromaticity([x, y]: [f64; 2]) -> Tabulated {
    let m = 0.0241 + 0.2562 * x - 0.7341 * y;
    let m1 = ((-1.3515 - 1.7703 * x + 5.9114 * y) / m * 1000.0).round() / 1000.0;
    let m2 = ((0.0300 - 31.4424 * x + 30.0717 * y) / m * 1000.0).round() / 1000.0;
    let b = basis();
    let value = (0..b.wavelengths.len())
        .map(|i| (b.columns[0][i] + m1 * b.columns[1][i] + m2 * b.columns[2][i]) as f32)
        .collect();
    // The basis table is valid (checked by tests), so this cannot fail.
    Tabulated::new(b.wavelengths.iter().map(|&w| w as f32).collect(), value)
        .expect("daylight basis wavelengths")
}

/// CIE daylight at `cct` kelvin (4000–25000 K), relative spectral power (≈100 at 560 nm).
pub fn daylight(cct: f64) -> Result<Tabulated, ColorError> {
    Ok(from_chromaticity(daylight_chromaticity(cct)?))
}

/// A named D illuminant (D50, D55, D75 from their nominal 5000, 5500, 7500 K):
/// the nominal CCT is scaled by 1.4388/1.4380 for the change in c₂ since their
/// definition, as CIE 015:2018 §4.1.2 prescribes.
pub fn daylight_named(nominal: f64) -> Tabulated {
    let cct = nominal * 1.4388 / 1.4380;
    // Named temperatures are within 4000–25000 K.
    from_chromaticity(daylight_chromaticity(cct).expect("named CCT in range"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn range_is_checked() {
        assert!(daylight(3999.0).is_err());
        assert!(daylight(25001.0).is_err());
        assert!(daylight(4000.0).is_ok() && daylight(25000.0).is_ok());
    }
}

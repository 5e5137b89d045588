//! The CIE observers and illuminants, and the age-dependent density of the
//! eye's lens, from the tables in `data/cie` (each
//! file names its source), parsed once on first use.

mod daylight;
mod illuminant;
mod lens;

use std::sync::OnceLock;

pub use daylight::{daylight, daylight_chromaticity, daylight_named};
pub use illuminant::{illuminant, illuminant_a, ILLUMINANT_NAMES};
pub use lens::{
    lens_channel_factors, lens_density, lens_transmittance_relative, LENS_MIN_AGE,
    LENS_REFERENCE_AGE,
};

use crate::io::parse_table;
use crate::{LAMBDA_MAX, LAMBDA_MIN};

const CMF_CSV: &str = include_str!("../../../../data/cie/cie1931_2deg_xyz.csv");
const VPRIME_CSV: &str = include_str!("../../../../data/cie/cie1951_scotopic_vprime.csv");

/// Number of 1 nm samples over 360–830 nm.
pub const SAMPLES_1NM: usize = (LAMBDA_MAX - LAMBDA_MIN) as usize + 1;

/// x̄, ȳ, z̄ (CIE 1931 2°) and V′ (CIE 1951 scotopic) at every nm of 360–830.
fn observer_table() -> &'static [[f32; 4]] {
    static TABLE: OnceLock<Vec<[f32; 4]>> = OnceLock::new();
    TABLE.get_or_init(|| {
        // The embedded tables are part of the build; a parse failure is a bug.
        let cmf = parse_table(CMF_CSV, "data/cie/cie1931_2deg_xyz.csv", 3, false)
            .expect("embedded CIE 1931 table");
        let vp = parse_table(VPRIME_CSV, "data/cie/cie1951_scotopic_vprime.csv", 1, false)
            .expect("embedded CIE 1951 table");
        assert_eq!(
            cmf.wavelengths.len(),
            SAMPLES_1NM,
            "CIE 1931 table: 360–830 nm at 1 nm"
        );
        (0..SAMPLES_1NM)
            .map(|i| {
                let lambda = LAMBDA_MIN as f64 + i as f64;
                let v = vp
                    .wavelengths
                    .iter()
                    .position(|&w| w == lambda)
                    .map_or(0.0, |j| vp.columns[0][j]);
                [
                    cmf.columns[0][i] as f32,
                    cmf.columns[1][i] as f32,
                    cmf.columns[2][i] as f32,
                    v as f32,
                ]
            })
            .collect()
    })
}

/// x̄(λ), ȳ(λ), z̄(λ), V′(λ) at `lambda` nm, linear between the 1 nm samples,
/// zero outside 360–830 nm.
#[inline]
pub fn observers(lambda: f32) -> [f32; 4] {
    let table = observer_table();
    let x = lambda - LAMBDA_MIN;
    if !(x >= 0.0 && x <= (SAMPLES_1NM - 1) as f32) {
        return [0.0; 4];
    }
    let i = (x as usize).min(SAMPLES_1NM - 2);
    let t = x - i as f32;
    let (a, b) = (table[i], table[i + 1]);
    std::array::from_fn(|k| a[k] + t * (b[k] - a[k]))
}

/// CIE 1931 2° colour-matching functions at `lambda` nm.
#[inline]
pub fn xyz_bar(lambda: f32) -> [f32; 3] {
    let o = observers(lambda);
    [o[0], o[1], o[2]]
}

/// CIE 1951 scotopic luminous efficiency V′ at `lambda` nm.
#[inline]
pub fn v_prime(lambda: f32) -> f32 {
    observers(lambda)[3]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn observer_values_from_the_tables() {
        // CIE 1931: ȳ(555) = 1.0; x̄(600) = 1.0622. CIE 1951: V′(507) = 1.
        assert!((xyz_bar(555.0)[1] - 1.0).abs() < 1e-6);
        assert!((xyz_bar(600.0)[0] - 1.0622).abs() < 1e-4);
        assert!((v_prime(507.0) - 1.0).abs() < 1e-6);
        assert_eq!(v_prime(370.0), 0.0);
        assert_eq!(observers(359.0), [0.0; 4]);
        assert_eq!(observers(831.0), [0.0; 4]);
        // Halfway between samples is the mean of the two.
        let mid = xyz_bar(555.5)[1];
        assert!((mid - 0.5 * (xyz_bar(555.0)[1] + xyz_bar(556.0)[1])).abs() < 1e-6);
    }

    #[test]
    fn cmf_sums_match_the_standard() {
        // Σ x̄ = Σ ȳ = Σ z̄ ≈ 106.86 at 1 nm over 360–830 (equal-energy white is x = y = 1/3).
        let sums = (0..SAMPLES_1NM).fold([0.0f64; 3], |mut s, i| {
            let c = xyz_bar(LAMBDA_MIN + i as f32);
            for k in 0..3 {
                s[k] += c[k] as f64;
            }
            s
        });
        for s in sums {
            assert!((s / 106.857 - 1.0).abs() < 1e-3, "{sums:?}");
        }
    }
}

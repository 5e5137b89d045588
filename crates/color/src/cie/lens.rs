//! The optical density of the eye's lens and other ocular media, and how it
//! grows with the observer's age: the two-component model of Pokorny, Smith
//! & Lutze 1987 (Appl. Opt. 26:1437) with the components of CIE 170-1:2006
//! (`data/cie/cie2006_ocular_media_density.csv`, which names its source).
//!
//! D(λ, A) = D₁(λ)·f(A) + D₂(λ): D₁ is the part of the lens that yellows with
//! age, D₂ the part that does not. The table is for CIE 170-1's reference
//! observer, 32 years old (f(32) = 1), with a small pupil (≤ 3 mm; CIE 170-1
//! scales the density by 0.86207 for a pupil over 7 mm, not modelled here).
//!
//! Outside the model's data:
//! - ages below 20 take the 20-year density: the formula's first branch
//!   starts at 20 years and CIE 170-1 uses the model for 20–80; carried down
//!   to age 1 its straight line would remove 62 % of D₁, a guess no data
//!   here supports. Ages above 80 follow the second branch's straight line
//!   (the lens keeps yellowing).
//! - below 390 nm the 390 nm components are held (the real lens keeps
//!   darkening into the UV, so this underestimates the age effect there, but
//!   z̄ puts 0.14 % of its weight below 390 nm, x̄ 0.03 %, ȳ and V′ less);
//!   above the table the density is zero, as it is from 660 nm on in it.

use std::sync::OnceLock;

use crate::cie::observers;
use crate::io::parse_table;
use crate::{LAMBDA_MAX, LAMBDA_MIN};

const LENS_CSV: &str = include_str!("../../../../data/cie/cie2006_ocular_media_density.csv");
const LENS_PATH: &str = "data/cie/cie2006_ocular_media_density.csv";

/// The age at which D = D₁ + D₂: CIE 170-1:2006's reference observer, and
/// where Pokorny, Smith & Lutze 1987's age factor 1 + 0.02·(A − 32) is 1.
pub const LENS_REFERENCE_AGE: f64 = 32.0;

/// The youngest age the formula is used at; younger eyes take its value.
/// Pokorny, Smith & Lutze 1987's first branch starts at 20 (CIE 170-1:2006: 20–80).
pub const LENS_MIN_AGE: f64 = 20.0;

/// D₁ and D₂ on a uniform grid: first wavelength, step, and the samples.
struct Components {
    first: f64,
    step: f64,
    d1: Vec<f64>,
    d2: Vec<f64>,
}

fn components() -> &'static Components {
    static TABLE: OnceLock<Components> = OnceLock::new();
    TABLE.get_or_init(|| {
        // The embedded table is part of the build; a parse failure is a bug.
        let table = parse_table(LENS_CSV, LENS_PATH, 2, false).expect("embedded lens table");
        let w = &table.wavelengths;
        let step = w[1] - w[0];
        assert!(
            w.windows(2).all(|p| (p[1] - p[0] - step).abs() < 1e-9),
            "{LENS_PATH}: uniform wavelength step"
        );
        let mut columns = table.columns.into_iter();
        Components {
            first: w[0],
            step,
            d1: columns.next().expect("d_ocul_1"),
            d2: columns.next().expect("d_ocul_2"),
        }
    })
}

/// (D₁(λ), D₂(λ)) at `lambda_nm`, linear between the 5 nm samples, the
/// first sample's values below the table and the last's (zero) above it.
fn components_at(lambda_nm: f64) -> (f64, f64) {
    let c = components();
    let last = (c.d1.len() - 1) as f64;
    let x = ((lambda_nm - c.first) / c.step).clamp(0.0, last);
    let i = (x as usize).min(c.d1.len() - 2);
    let t = x - i as f64;
    let lerp = |v: &[f64]| v[i] + t * (v[i + 1] - v[i]);
    (lerp(&c.d1), lerp(&c.d2))
}

/// The factor f(A) on D₁ at age `age` years: Pokorny, Smith & Lutze 1987,
/// as CIE 170-1:2006 gives it, with ages below 20 held at 20.
fn age_factor(age: f64) -> f64 {
    let age = age.max(LENS_MIN_AGE);
    if age <= 60.0 {
        // Pokorny, Smith & Lutze 1987, 20 ≤ A ≤ 60: 1 + 0.02·(A − 32).
        1.0 + 0.02 * (age - LENS_REFERENCE_AGE)
    } else {
        // Pokorny, Smith & Lutze 1987, A > 60: 1.56 + 0.0667·(A − 60).
        1.56 + 0.0667 * (age - 60.0)
    }
}

/// Optical density (log₁₀ units) of the lens and ocular media at
/// `lambda_nm` for an observer of `age` years:
/// D₁(λ)·f(A) + D₂(λ) (Pokorny, Smith & Lutze 1987; CIE 170-1:2006).
pub fn lens_density(lambda_nm: f64, age: f64) -> f64 {
    let (d1, d2) = components_at(lambda_nm);
    d1 * age_factor(age) + d2
}

/// Transmittance of the lens and ocular media of an observer of `age` years
/// relative to the 32-year-old reference, 10^−(D(λ, A) − D(λ, 32)): the CIE
/// observers already include the reference lens, so this is the filter an
/// older (below 1) or younger (above 1) eye adds to them.
pub fn lens_transmittance_relative(lambda_nm: f64, age: f64) -> f64 {
    // D₂ cancels and f(32) = 1: D(λ, A) − D(λ, 32) = D₁(λ)·(f(A) − 1).
    let (d1, _) = components_at(lambda_nm);
    10f64.powf(-d1 * (age_factor(age) - 1.0))
}

/// For the film's channels X, Y, Z, V′ (CIE 1931 x̄, ȳ, z̄ and CIE 1951 V′):
/// ∫ cmf(λ)·T_rel(λ)·E(λ) dλ / ∫ cmf(λ)·E(λ) dλ with E an equal-energy
/// spectrum, T_rel = [`lens_transmittance_relative`], over 360–830 nm at 1 nm.
///
/// The pipeline holds only X, Y, Z, V′, not spectra, so the lens of an
/// observer of `age` years scales each channel by the factor for a flat
/// spectrum: exact for equal-energy light, approximate for others (a bluish
/// source loses a little more than this, a reddish one a little less).
pub fn lens_channel_factors(age: f64) -> [f64; 4] {
    let mut filtered = [0.0f64; 4];
    let mut total = [0.0f64; 4];
    for l in (LAMBDA_MIN as u32)..=(LAMBDA_MAX as u32) {
        let weights = observers(l as f32);
        let t = lens_transmittance_relative(l as f64, age);
        for c in 0..4 {
            total[c] += weights[c] as f64;
            filtered[c] += weights[c] as f64 * t;
        }
    }
    std::array::from_fn(|c| filtered[c] / total[c])
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: f64, b: f64, tol: f64) -> bool {
        (a - b).abs() <= tol
    }

    #[test]
    fn density_at_the_reference_age_is_the_sum_of_the_components() {
        // Samples of the table: (λ, D₁, D₂).
        for (l, d1, d2) in [
            (390.0, 0.608146, 1.904054),
            (400.0, 0.661837, 1.103063),
            (450.0, 0.258499, 0.004381),
            (500.0, 0.1537, 0.0),
            (650.0, 0.00318, 0.0),
        ] {
            let d = lens_density(l, LENS_REFERENCE_AGE);
            assert!(close(d, d1 + d2, 1e-12), "{l} nm: {d}");
        }
        // Stockman, Sharpe & Fach 1999 Table 3, the 32-year lens: 1.7649 at 400 nm.
        assert!(close(lens_density(400.0, 32.0), 1.7649, 1e-9));
        // Between samples the components are linear.
        let mid = lens_density(402.5, 32.0);
        let ends = 0.5 * (lens_density(400.0, 32.0) + lens_density(405.0, 32.0));
        assert!(close(mid, ends, 1e-12));
    }

    #[test]
    fn the_reference_eye_changes_nothing() {
        for l in [360.0, 390.0, 420.0, 555.0, 700.0] {
            assert_eq!(lens_transmittance_relative(l, 32.0), 1.0);
        }
        for f in lens_channel_factors(32.0) {
            assert!(close(f, 1.0, 1e-12), "{f}");
        }
    }

    #[test]
    fn an_older_eye_loses_blue() {
        let (t400, t600) = (
            lens_transmittance_relative(400.0, 70.0),
            lens_transmittance_relative(600.0, 70.0),
        );
        assert!(t400 < 0.5 * t600, "400 nm {t400}, 600 nm {t600}");
        let [x, y, z, v] = lens_channel_factors(70.0);
        assert!(z < y - 0.15, "Z {z}, Y {y}");
        // V′ peaks at 507 nm, bluer than ȳ at 555: it loses more than Y.
        assert!(v < y && y < 1.0 && x < 1.0, "{x} {y} {z} {v}");
        // A younger eye than the reference transmits more.
        assert!(lens_channel_factors(25.0).iter().all(|&f| f > 1.0));
    }

    #[test]
    fn the_age_formula_at_its_seams() {
        // Continuous at 60 (1 + 0.02·28 = 1.56), held below 20.
        let (a, b) = (lens_density(420.0, 60.0), lens_density(420.0, 60.0 + 1e-9));
        assert!(close(a, b, 1e-9));
        assert_eq!(lens_density(420.0, 5.0), lens_density(420.0, 20.0));
        assert_eq!(lens_channel_factors(1.0), lens_channel_factors(20.0));
        // Density grows with age at every age.
        let mut previous = 0.0;
        for age in (20..=100).step_by(5) {
            let d = lens_density(420.0, age as f64);
            assert!(d > previous, "{age}");
            previous = d;
        }
    }

    #[test]
    fn outside_the_table() {
        // Held at the 390 nm values below, zero above (the table is zero from 660 nm).
        assert_eq!(lens_density(360.0, 70.0), lens_density(390.0, 70.0));
        assert_eq!(lens_density(830.0, 70.0), 0.0);
        assert_eq!(lens_density(900.0, 70.0), 0.0);
        assert_eq!(lens_transmittance_relative(700.0, 80.0), 1.0);
    }

    #[test]
    fn densities_match_luxpy() {
        // From luxpy 1.12.5, luxpy.toolboxes.indvcmf.individual_observer_cmf_model
        // ._d_ocular(age) (its default CIE TC 1-97 data), at 5 nm samples:
        // (age, [D at 400, 420, 450, 500, 550 nm]).
        let expected = [
            (20.0, [1.6060591, 0.6213387, 0.2008402, 0.116812, 0.0652536]),
            (25.0, [1.6722428, 0.6641059, 0.2266901, 0.132182, 0.0738396]),
            (32.0, [1.7649, 0.72398, 0.26288, 0.1537, 0.08586]),
            (45.0, [1.9369776, 0.8351747, 0.3300897, 0.193662, 0.1081836]),
            (60.0, [2.1355287, 0.9634763, 0.4076394, 0.239772, 0.1339416]),
            (70.0, [2.576974, 1.2487335, 0.5800583, 0.3422899, 0.1912102]),
            (
                80.0,
                [3.0184193, 1.5339908, 0.7524771, 0.4448078, 0.2484788],
            ),
        ];
        for (age, row) in expected {
            for (l, want) in [400.0, 420.0, 450.0, 500.0, 550.0].into_iter().zip(row) {
                let got = lens_density(l, age);
                assert!(close(got, want, 2e-7), "{l} nm, {age} y: {got} vs {want}");
            }
        }
        // Between samples luxpy interpolates its 0.1 nm tables (cubic for D₂),
        // here linear between 5 nm: luxpy gives 2.3626472 at 402.5 nm, 70 y.
        assert!(close(lens_density(402.5, 70.0), 2.3626472, 1e-3));
    }

    #[test]
    fn channel_factors_match_luxpy() {
        // From luxpy 1.12.5: densities of individual_observer_cmf_model._d_ocular(age)
        // put on 1 nm by numpy.interp (held at 390 nm below, as here), weights
        // luxpy._CMF['1931_2'] and ['1951_20_scotopic'], equal-energy sums over
        // 360–830 nm; [X, Y, Z, V′]. luxpy's cubic D₂ and 0.1 nm tables between
        // the 5 nm samples put its factors up to 3e-4 from these.
        let expected = [
            (20.0, [1.047795, 1.044867, 1.163788, 1.094422]),
            (25.0, [1.027165, 1.025835, 1.092164, 1.053806]),
            (50.0, [0.93811, 0.937632, 0.800292, 0.876305]),
            (70.0, [0.823673, 0.808291, 0.477949, 0.646782]),
            (80.0, [0.757785, 0.725383, 0.327267, 0.518129]),
        ];
        for (age, want) in expected {
            let got = lens_channel_factors(age);
            for c in 0..4 {
                assert!(close(got[c], want[c], 1e-3), "{age} y: {got:?} vs {want:?}");
            }
        }
    }
}

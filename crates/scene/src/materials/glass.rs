//! Dispersive dielectrics by the Sellmeier equation, coefficients in
//! `data/glasses.csv` (each with its source).

use scotopia_color::{Spectrum, Tabulated, LAMBDA_MAX, LAMBDA_MIN};

const CSV: &str = include_str!("../../../../data/glasses.csv");

/// The names `named_glass` knows.
pub const GLASS_NAMES: [&str; 6] = ["bk7", "sf11", "f2", "fused silica", "diamond", "water"];

/// n(λ) = √(1 + Σ Bᵢ λ² / (λ² − Cᵢ)), λ in µm, Cᵢ in µm² (Sellmeier 1871).
pub fn sellmeier_index(b: &[f64], c: &[f64], lambda_nm: f64) -> f64 {
    let l2 = (lambda_nm * 1e-3).powi(2);
    let sum: f64 = b.iter().zip(c).map(|(b, c)| b * l2 / (l2 - c)).sum();
    (1.0 + sum).sqrt()
}

/// The index of a named dielectric, tabulated at 1 nm over 360–830 nm.
pub fn named_glass(name: &str) -> Option<Spectrum> {
    let index = GLASS_NAMES
        .iter()
        .position(|n| n.eq_ignore_ascii_case(name.trim()))?;
    // The rows are in GLASS_NAMES order; the embedded table is checked by a test.
    let line = CSV
        .lines()
        .filter(|l| !l.starts_with('#') && !l.starts_with("name,"))
        .nth(index)?;
    // Embedded, checked by a test: every field after the name is a number.
    let coeffs: Vec<f64> = line
        .split(',')
        .skip(1)
        .map(|f| f.trim().parse().expect("numeric Sellmeier coefficient"))
        .collect();
    let (b, c): (Vec<f64>, Vec<f64>) = coeffs.chunks(2).map(|p| (p[0], p[1])).unzip();
    Some(Spectrum::tabulated(Tabulated::from_fn(
        LAMBDA_MIN,
        LAMBDA_MAX,
        1.0,
        |l| sellmeier_index(&b, &c, l as f64) as f32,
    )))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn catalogue_indices_at_the_d_line() {
        // n_d at 587.56 nm from the catalogues/papers: N-BK7 1.5168, SF11
        // 1.78472, F2 1.62004, fused silica 1.4585, diamond 2.4175 (589 nm),
        // water 1.3330 (589 nm, 20 °C).
        let nd = [
            ("bk7", 587.56, 1.5168),
            ("sf11", 587.56, 1.78472),
            ("f2", 587.56, 1.62004),
            ("fused silica", 587.56, 1.4585),
            ("diamond", 589.0, 2.4175),
            ("water", 589.0, 1.3330),
        ];
        for (name, l, n) in nd {
            let s = named_glass(name).unwrap();
            let got = s.eval(l);
            assert!((got - n).abs() < 1.5e-3, "{name}: {got} vs {n}");
        }
        // Normal dispersion: larger in the blue.
        let bk7 = named_glass("BK7").unwrap();
        assert!(bk7.eval(400.0) > bk7.eval(700.0));
        assert!(named_glass("unobtainium").is_none());
    }
}

//! CIE standard and named illuminants by name: A, D50, D55, D65, D75, E, F1–F12.

use std::sync::OnceLock;

use super::daylight::daylight_named;
use crate::error::ColorError;
use crate::io::parse_spectrum;
use crate::spectrum::{Spectrum, Tabulated};

/// The names `illuminant` accepts (case-insensitive; `FL1`… also read as `F1`…).
pub const ILLUMINANT_NAMES: [&str; 18] = [
    "A", "D50", "D55", "D65", "D75", "E", "F1", "F2", "F3", "F4", "F5", "F6", "F7", "F8", "F9",
    "F10", "F11", "F12",
];

const D65_CSV: &str = include_str!("../../../../data/cie/illuminant_d65.csv");
const F_CSV: [&str; 12] = [
    include_str!("../../../../data/cie/illuminant_f1.csv"),
    include_str!("../../../../data/cie/illuminant_f2.csv"),
    include_str!("../../../../data/cie/illuminant_f3.csv"),
    include_str!("../../../../data/cie/illuminant_f4.csv"),
    include_str!("../../../../data/cie/illuminant_f5.csv"),
    include_str!("../../../../data/cie/illuminant_f6.csv"),
    include_str!("../../../../data/cie/illuminant_f7.csv"),
    include_str!("../../../../data/cie/illuminant_f8.csv"),
    include_str!("../../../../data/cie/illuminant_f9.csv"),
    include_str!("../../../../data/cie/illuminant_f10.csv"),
    include_str!("../../../../data/cie/illuminant_f11.csv"),
    include_str!("../../../../data/cie/illuminant_f12.csv"),
];

/// CIE standard illuminant A, 300–830 nm at 1 nm (CIE 015:2018, eq. 4.1):
/// S_A(λ) = 100 (560/λ)⁵ (e^{c₂/(2848·560)} − 1) / (e^{c₂/(2848·λ)} − 1),
/// c₂ = 1.435·10⁷ nm·K as fixed by the standard (not the current CODATA value).
pub fn illuminant_a() -> Tabulated {
    const C2: f64 = 1.435e7;
    const T: f64 = 2848.0;
    Tabulated::from_fn(300.0, 830.0, 1.0, |l| {
        let l = l as f64;
        (100.0 * (560.0 / l).powi(5) * (C2 / (T * 560.0)).exp_m1() / (C2 / (T * l)).exp_m1()) as f32
    })
}

/// A CIE illuminant by name, relative spectral power as tabulated by the CIE
/// (100 at 560 nm for A and the D series; E is 1 everywhere).
pub fn illuminant(name: &str) -> Result<Spectrum, ColorError> {
    static CACHE: OnceLock<Vec<(&'static str, Spectrum)>> = OnceLock::new();
    let upper = name.trim().to_ascii_uppercase();
    let key = upper
        .strip_prefix("FL")
        .map_or(upper.clone(), |n| format!("F{n}"));
    let table = CACHE.get_or_init(|| ILLUMINANT_NAMES.iter().map(|&n| (n, build(n))).collect());
    table
        .iter()
        .find(|(n, _)| *n == key)
        .map(|(_, s)| s.clone())
        .ok_or_else(|| ColorError::UnknownName {
            what: "illuminant",
            name: name.to_string(),
            known: ILLUMINANT_NAMES.join(", "),
        })
}

fn build(name: &str) -> Spectrum {
    let parse = |csv: &str, file: &str| -> Spectrum {
        // Embedded tables are part of the build; a parse failure is a bug.
        Spectrum::tabulated(parse_spectrum(csv, file, false).expect("embedded CIE illuminant"))
    };
    match name {
        "A" => Spectrum::tabulated(illuminant_a()),
        "E" => Spectrum::Constant(1.0),
        "D65" => parse(D65_CSV, "data/cie/illuminant_d65.csv"),
        "D50" | "D55" | "D75" => {
            let nominal: f64 = name[1..].parse::<f64>().expect("digits") * 100.0;
            Spectrum::tabulated(daylight_named(nominal))
        }
        f => {
            let i: usize = f[1..].parse().expect("F number");
            parse(F_CSV[i - 1], "data/cie/illuminant_fN.csv")
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_name_resolves() {
        for n in ILLUMINANT_NAMES {
            let s = illuminant(n).unwrap();
            assert!(s.eval(560.0) > 0.0, "{n}");
        }
        assert_eq!(illuminant("fl11").unwrap(), illuminant("F11").unwrap());
        let e = illuminant("D93").unwrap_err().to_string();
        assert!(
            e.contains("unknown illuminant 'D93'") && e.contains("F12"),
            "{e}"
        );
    }

    #[test]
    fn a_and_d65_are_100_at_560() {
        assert!((illuminant("A").unwrap().eval(560.0) - 100.0).abs() < 1e-4);
        assert!((illuminant("D65").unwrap().eval(560.0) - 100.0).abs() < 1e-4);
        // CIE 015:2018 table of illuminant A: 0.930483 at 300 nm, 9.7951 at 380 nm,
        // 241.675 at 780 nm.
        let a = illuminant_a();
        assert!(
            (a.eval(300.0) - 0.930_483).abs() < 1e-5,
            "{}",
            a.eval(300.0)
        );
        assert!((a.eval(380.0) - 9.7951).abs() < 1e-3, "{}", a.eval(380.0));
        assert!((a.eval(780.0) - 241.675).abs() < 1e-2, "{}", a.eval(780.0));
    }

    #[test]
    fn d65_from_the_basis_matches_the_table() {
        // D65 is the D-series at 6504 K; the CIE table agrees with the basis
        // to the table's rounding (a few 0.01 of 100).
        let d65 = illuminant("D65").unwrap();
        let gen = daylight_named(6500.0);
        for l in (300..=830).step_by(5) {
            let (a, b) = (d65.eval(l as f32), gen.eval(l as f32));
            assert!((a - b).abs() < 0.05, "{l} nm: {a} vs {b}");
        }
    }
}

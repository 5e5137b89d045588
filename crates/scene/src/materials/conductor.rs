//! Measured complex refractive indices of metals, from `data/conductors/`.

use scotopia_color::io::parse_table;
use scotopia_color::{Spectrum, Tabulated};

/// The conductor names `named_conductor` knows (Mitsuba's chemical symbols).
pub const CONDUCTOR_NAMES: [&str; 6] = ["Au", "Ag", "Cu", "Al", "Cr", "a-C"];

const FILES: [(&str, &str); 6] = [
    ("Au", include_str!("../../../../data/conductors/au.csv")),
    ("Ag", include_str!("../../../../data/conductors/ag.csv")),
    ("Cu", include_str!("../../../../data/conductors/cu.csv")),
    ("Al", include_str!("../../../../data/conductors/al.csv")),
    ("Cr", include_str!("../../../../data/conductors/cr.csv")),
    ("a-C", include_str!("../../../../data/conductors/a-c.csv")),
];

/// (η(λ), κ(λ)) of a named metal, case-insensitive; `None` if unknown.
pub fn named_conductor(name: &str) -> Option<(Spectrum, Spectrum)> {
    let (symbol, csv) = FILES
        .iter()
        .find(|(n, _)| n.eq_ignore_ascii_case(name.trim()))?;
    // The embedded tables are part of the build (checked by a test).
    let t = parse_table(
        csv,
        &format!("data/conductors/{}.csv", symbol.to_lowercase()),
        2,
        false,
    )
    .expect("embedded conductor table");
    let l: Vec<f32> = t.wavelengths.iter().map(|&w| w as f32).collect();
    let column = |c: &Vec<f64>| {
        Spectrum::tabulated(
            Tabulated::new(l.clone(), c.iter().map(|&v| v as f32).collect()).expect("increasing"),
        )
    };
    Some((column(&t.columns[0]), column(&t.columns[1])))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_table_loads_and_covers_the_visible_range() {
        for n in CONDUCTOR_NAMES {
            let (eta, k) = named_conductor(n).unwrap();
            for l in [360.0, 555.0, 830.0] {
                assert!(eta.eval(l) > 0.0 && k.eval(l) > 0.0, "{n} at {l}");
            }
        }
        assert!(named_conductor("gold").is_none());
        // Gold is dark in the blue and bright in the red: Johnson & Christy
        // at 659.5 nm, η = 0.14, κ = 3.697 (read from a grid within 10⁻⁴
        // of the table's peak, κ = 5.7).
        let (eta, k) = named_conductor("au").unwrap();
        assert!((eta.eval(659.5) - 0.14).abs() < 6e-4 && (k.eval(659.5) - 3.697).abs() < 6e-4);
    }
}

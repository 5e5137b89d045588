//! Smits 1999, "An RGB-to-Spectrum Conversion for Reflectances": the colour
//! is white times the smallest component, plus the secondary (cyan, magenta or
//! yellow) times the middle excess, plus the primary (red, green or blue) times
//! the largest excess; the seven basis spectra are the paper's, in
//! `data/smits1999.csv`, interpolated linearly and held constant beyond
//! 380–720 nm.

use std::sync::OnceLock;

use crate::io::{parse_table, Table};
use crate::spectrum::Tabulated;
use crate::{LAMBDA_MAX, LAMBDA_MIN};

const BASIS_CSV: &str = include_str!("../../../../data/smits1999.csv");
const WHITE: usize = 0;
const CYAN: usize = 1;
const MAGENTA: usize = 2;
const YELLOW: usize = 3;
const RED: usize = 4;
const GREEN: usize = 5;
const BLUE: usize = 6;

fn basis() -> &'static Table {
    static B: OnceLock<Table> = OnceLock::new();
    // Embedded table, part of the build.
    B.get_or_init(|| {
        parse_table(BASIS_CSV, "data/smits1999.csv", 7, false).expect("embedded Smits table")
    })
}

/// The Smits spectrum of a reflectance `rgb`, at the basis wavelengths with
/// the end values repeated at 360 and 830 nm.
pub fn reflectance(rgb: [f32; 3]) -> Tabulated {
    let [r, g, b] = rgb.map(|v| v as f64);
    // (basis, weight) pairs, Smits 1999 §3.
    let terms: [(usize, f64); 3] = if r <= g && r <= b {
        if g <= b {
            [(WHITE, r), (CYAN, g - r), (BLUE, b - g)]
        } else {
            [(WHITE, r), (CYAN, b - r), (GREEN, g - b)]
        }
    } else if g <= r && g <= b {
        if r <= b {
            [(WHITE, g), (MAGENTA, r - g), (BLUE, b - r)]
        } else {
            [(WHITE, g), (MAGENTA, b - g), (RED, r - b)]
        }
    } else if r <= g {
        [(WHITE, b), (YELLOW, r - b), (GREEN, g - r)]
    } else {
        [(WHITE, b), (YELLOW, g - b), (RED, r - g)]
    };
    let t = basis();
    let values: Vec<f32> = (0..t.wavelengths.len())
        .map(|i| terms.iter().map(|&(k, w)| w * t.columns[k][i]).sum::<f64>() as f32)
        .collect();
    let mut lambda: Vec<f32> = t.wavelengths.iter().map(|&w| w as f32).collect();
    let mut value = values.clone();
    lambda.insert(0, LAMBDA_MIN);
    value.insert(0, values[0]);
    lambda.push(LAMBDA_MAX);
    value.push(values[values.len() - 1]);
    // The basis wavelengths lie strictly inside 360–830 nm.
    Tabulated::new(lambda, value).expect("Smits wavelengths increase")
}

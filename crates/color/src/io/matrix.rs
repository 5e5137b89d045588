//! Reading a bispectral (Donaldson) matrix: a header row whose first field
//! is a label and whose others are the excitation wavelengths (nm), then
//! one row per emission wavelength: that wavelength, then one value per
//! excitation wavelength. Separators and comments as for spectra.
//!
//! ```text
//! # emission \ excitation
//! nm, 360, 370, 380
//! 360, 0.80, 0, 0
//! 370, 0.001, 0.81, 0
//! ```

use std::path::Path;

use super::{numbers, rows};
use crate::error::ColorError;

/// A matrix as read: `values[r * excitation.len() + c]` is the cell of
/// emission wavelength r and excitation wavelength c.
#[derive(Debug, Clone, PartialEq)]
pub struct Matrix {
    pub excitation: Vec<f32>,
    pub emission: Vec<f32>,
    pub values: Vec<f32>,
}

fn increasing(axis: &[f64]) -> Option<usize> {
    (1..axis.len()).find(|&i| axis[i] <= axis[i - 1])
}

/// Parses a matrix from `text`; `source` names the file in errors.
pub fn parse_matrix(text: &str, source: &str) -> Result<Matrix, ColorError> {
    let err = |line: usize, message: String| ColorError::SpectrumFile {
        path: source.to_string(),
        line,
        message,
    };
    let mut lines = rows(text);
    let Some((header_line, header)) = lines.next() else {
        return Err(ColorError::EmptySpectrumFile {
            path: source.to_string(),
        });
    };
    let excitation = numbers(&header[1..]).map_err(|m| {
        err(
            header_line,
            format!("{m}: the header row is a label, then the excitation wavelengths in nm"),
        )
    })?;
    if excitation.len() < 2 {
        return Err(err(
            header_line,
            "the header row needs a label and at least two excitation wavelengths".into(),
        ));
    }
    if let Some(i) = increasing(&excitation) {
        return Err(err(
            header_line,
            format!(
                "excitation wavelength {} nm does not increase",
                excitation[i]
            ),
        ));
    }
    let mut emission = Vec::new();
    let mut values = Vec::new();
    for (line, fields) in lines {
        if fields.len() != excitation.len() + 1 {
            return Err(err(
                line,
                format!(
                    "expected {} fields (the emission wavelength and one value per \
                     excitation wavelength), found {}",
                    excitation.len() + 1,
                    fields.len()
                ),
            ));
        }
        let row = numbers(&fields).map_err(|m| err(line, m))?;
        if let Some(&prev) = emission.last() {
            if row[0] <= prev {
                return Err(err(
                    line,
                    format!(
                        "emission wavelength {} nm does not increase (previous row: {prev} nm)",
                        row[0]
                    ),
                ));
            }
        }
        emission.push(row[0]);
        values.extend(row[1..].iter().map(|&v| v as f32));
    }
    if emission.len() < 2 {
        return Err(err(
            header_line,
            "a matrix needs at least two rows of emission wavelengths".into(),
        ));
    }
    let all = excitation.iter().chain(&emission);
    if all.clone().any(|&l| l <= 0.0) || all.clone().all(|&l| l < 100.0) {
        return Err(err(
            header_line,
            "wavelengths must be positive and in nm".into(),
        ));
    }
    Ok(Matrix {
        excitation: excitation.iter().map(|&l| l as f32).collect(),
        emission: emission.iter().map(|&l| l as f32).collect(),
        values,
    })
}

/// Reads a matrix file.
pub fn read_matrix_file(path: impl AsRef<Path>) -> Result<Matrix, ColorError> {
    let (text, name) = super::read_text(path.as_ref())?;
    parse_matrix(&text, &name)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn message(text: &str) -> String {
        parse_matrix(text, "paper.csv").unwrap_err().to_string()
    }

    #[test]
    fn reads_header_rows_and_comments() {
        let m = parse_matrix(
            "# a brightener\nnm,360,370,380\n360,0.8,0,0 # first\n\n370;0.01;0.81;0\n380 0.02 0.01 0.82\n",
            "x",
        )
        .unwrap();
        assert_eq!(m.excitation, vec![360.0, 370.0, 380.0]);
        assert_eq!(m.emission, vec![360.0, 370.0, 380.0]);
        assert_eq!(m.values[3], 0.01);
        assert_eq!(m.values[8], 0.82);
    }

    #[test]
    fn bad_input_names_file_and_line() {
        assert!(message("").starts_with("paper.csv: no spectral data"));
        assert!(message("nm,360,x\n").starts_with("paper.csv:1: 'x' is not a number"));
        assert!(message("nm,360\n").contains("at least two excitation"));
        assert!(message("nm,370,360\n").contains("excitation wavelength 360 nm does not increase"));
        assert!(
            message("nm,360,370\n360,1,0\n370,0\n").starts_with("paper.csv:3: expected 3 fields")
        );
        assert!(message("nm,360,370\n360,1,0\n360,0,1\n")
            .starts_with("paper.csv:3: emission wavelength 360"));
        assert!(
            message("nm,360,370\n360,1,nan\n").starts_with("paper.csv:2: 'nan' is not a finite")
        );
        assert!(message("nm,360,370\n360,1,0\n").contains("at least two rows"));
        assert!(message("nm,0.36,0.37\n0.36,1,0\n0.37,0,1\n").contains("in nm"));
    }
}

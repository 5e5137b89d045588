//! Reading spectral tables: CSV or `.spd` text, one `wavelength,value` row a
//! line (commas, semicolons, tabs or spaces between fields), `#` comments, an
//! optional header row. Errors name the file and line.

use std::path::Path;

use crate::error::ColorError;
use crate::spectrum::Tabulated;
use crate::{LAMBDA_MAX, LAMBDA_MIN};

mod limited;
mod lines;
mod matrix;

pub use limited::{read_limited, read_text_limited, MIB};
pub use lines::lines;
pub use matrix::{parse_matrix, read_matrix_file, Matrix};

/// The largest spectrum or matrix file read: tabulated data is a few
/// thousand lines (a 1 nm table from 300 to 2500 nm is ~30 KiB), so
/// 64 MiB is generous and stops `/dev/zero` or a runaway file.
pub const DATA_FILE_LIMIT: u64 = 64 * MIB;

/// The non-empty lines of `text` with their 1-based numbers, split into
/// fields (commas, semicolons, tabs or spaces), `#` comments removed.
fn rows(text: &str) -> impl Iterator<Item = (usize, Vec<&str>)> {
    lines(text).enumerate().filter_map(|(index, raw)| {
        let content = raw.split('#').next().unwrap_or("").trim();
        (!content.is_empty()).then(|| {
            let fields = content
                .split(|c: char| c == ',' || c == ';' || c.is_whitespace())
                .filter(|f| !f.is_empty())
                .collect();
            (index + 1, fields)
        })
    })
}

/// The fields as finite numbers, or what is wrong with the first bad one.
fn numbers(fields: &[&str]) -> Result<Vec<f64>, String> {
    fields
        .iter()
        .map(|field| match field.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(format!("'{field}' is not a finite number")),
            Err(_) => Err(format!("'{field}' is not a number")),
        })
        .collect()
}

/// Columns of a spectral table: the wavelengths and one vector per value column.
#[derive(Debug, Clone)]
pub struct Table {
    pub wavelengths: Vec<f64>,
    pub columns: Vec<Vec<f64>>,
}

/// Parses a table of `1 + value_columns` numeric columns from `text`.
/// `source` names the file in errors. Wavelengths must be finite, positive
/// and strictly increasing; values must be finite, and non-negative unless
/// `allow_negative`.
pub fn parse_table(
    text: &str,
    source: &str,
    value_columns: usize,
    allow_negative: bool,
) -> Result<Table, ColorError> {
    let err = |line: usize, message: String| ColorError::SpectrumFile {
        path: source.to_string(),
        line,
        message,
    };
    let mut table = Table {
        wavelengths: Vec::new(),
        columns: vec![Vec::new(); value_columns],
    };
    let mut seen_content = false;
    for (line_no, fields) in rows(text) {
        // A first row whose leading field is not a number is a header.
        let first_row = !seen_content;
        seen_content = true;
        if first_row && fields[0].parse::<f64>().is_err() {
            continue;
        }
        if fields.len() != value_columns + 1 {
            return Err(err(
                line_no,
                format!(
                    "expected {} fields (wavelength and {} value{}), found {}",
                    value_columns + 1,
                    value_columns,
                    if value_columns == 1 { "" } else { "s" },
                    fields.len()
                ),
            ));
        }
        let numbers = numbers(&fields).map_err(|m| err(line_no, m))?;
        let lambda = numbers[0];
        if lambda <= 0.0 {
            return Err(err(
                line_no,
                format!("wavelength {lambda} nm is not positive"),
            ));
        }
        if let Some(&prev) = table.wavelengths.last() {
            if lambda <= prev {
                return Err(err(
                    line_no,
                    format!("wavelength {lambda} nm does not increase (previous row: {prev} nm)"),
                ));
            }
        }
        for (k, column) in table.columns.iter_mut().enumerate() {
            let v = numbers[k + 1];
            if v < 0.0 && !allow_negative {
                return Err(err(line_no, format!("negative value {v} at {lambda} nm")));
            }
            column.push(v);
        }
        table.wavelengths.push(lambda);
    }
    if table.wavelengths.is_empty() {
        return Err(ColorError::EmptySpectrumFile {
            path: source.to_string(),
        });
    }
    Ok(table)
}

/// Parses a two-column spectrum (`wavelength,value`) into a tabulated spectrum.
/// The spectrum must overlap scotopia's 360–830 nm range (wavelengths in nm).
pub fn parse_spectrum(
    text: &str,
    source: &str,
    allow_negative: bool,
) -> Result<Tabulated, ColorError> {
    let table = parse_table(text, source, 1, allow_negative)?;
    let (first, last) = (
        table.wavelengths[0],
        table.wavelengths[table.wavelengths.len() - 1],
    );
    if last < LAMBDA_MIN as f64 || first > LAMBDA_MAX as f64 {
        return Err(ColorError::SpectrumFile {
            path: source.to_string(),
            line: 1,
            message: format!(
                "wavelengths {first}–{last} do not overlap {LAMBDA_MIN}–{LAMBDA_MAX} nm \
                 (wavelengths must be in nm)"
            ),
        });
    }
    let column = &table.columns[0];
    Tabulated::new(
        table.wavelengths.iter().map(|&w| w as f32).collect(),
        column.iter().map(|&v| v as f32).collect(),
    )
    .map_err(|e| ColorError::SpectrumFile {
        path: source.to_string(),
        line: 1,
        message: e.to_string(),
    })
}

/// Reads a spectrum file (CSV or `.spd`). Values may not be negative.
pub fn read_spectrum_file(path: impl AsRef<Path>) -> Result<Tabulated, ColorError> {
    let (text, name) = read_text(path.as_ref())?;
    parse_spectrum(&text, &name, false)
}

/// A data file's text and the name its errors give.
fn read_text(path: &Path) -> Result<(String, String), ColorError> {
    let name = path.display().to_string();
    let text = read_text_limited(path, DATA_FILE_LIMIT).map_err(|cause| ColorError::Io {
        path: name.clone(),
        cause,
    })?;
    Ok((text, name))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn message(text: &str) -> String {
        parse_spectrum(text, "lamp.csv", false)
            .unwrap_err()
            .to_string()
    }

    #[test]
    fn reads_csv_spd_header_and_comments() {
        let s = parse_spectrum(
            "# lamp\nwavelength,value\n400,1\n500 2 # peak\n600;0.5\n",
            "x",
            false,
        )
        .unwrap();
        assert_eq!(s.eval(500.0), 2.0);
        assert_eq!(s.eval(450.0), 1.5);
    }

    #[test]
    fn bad_input_names_file_and_line() {
        assert_eq!(
            message(""),
            "lamp.csv: no spectral data (expected lines of 'wavelength,value')"
        );
        assert_eq!(message("# only a comment\n"), message(""));
        assert!(message("400,1\n500,abc\n").starts_with("lamp.csv:2: 'abc' is not a number"));
        assert!(message("400,1\n400,2\n")
            .starts_with("lamp.csv:2: wavelength 400 nm does not increase"));
        assert!(message("400,1\n390,2\n").contains("does not increase"));
        assert!(message("400,1\n\n500,NaN\n").starts_with("lamp.csv:3: 'NaN' is not a finite"));
        assert!(message("400,1\n500,inf\n").contains("not a finite"));
        assert!(message("400,1\n500,-0.1\n").starts_with("lamp.csv:2: negative value"));
        assert!(message("400,1,2\n").starts_with("lamp.csv:1: expected 2 fields"));
        assert!(message("wavelength,value\n400\n").starts_with("lamp.csv:2: expected 2 fields"));
        assert!(message("0.4,1\n0.5,1\n").contains("must be in nm"));
    }

    #[test]
    fn cr_crlf_and_lf_line_endings_read_alike() {
        let lf = parse_spectrum("wavelength,value\n400,1\n500,2\n", "x", false).unwrap();
        for text in [
            "wavelength,value\r400,1\r500,2\r",
            "wavelength,value\r\n400,1\r\n500,2\r\n",
        ] {
            let s = parse_spectrum(text, "x", false).unwrap();
            assert_eq!(
                (s.eval(400.0), s.eval(500.0)),
                (lf.eval(400.0), lf.eval(500.0))
            );
        }
        // Line numbers count CR-only lines too.
        assert!(message("400,1\r500,abc\r").starts_with("lamp.csv:2: 'abc'"));
    }

    #[test]
    fn negative_values_allowed_when_asked() {
        let t = parse_table("400,-1,2\n500,1,-2\n", "basis", 2, true).unwrap();
        assert_eq!(t.columns[1], vec![2.0, -2.0]);
    }

    #[test]
    fn missing_file_is_an_error_naming_it() {
        let e = read_spectrum_file("/nonexistent/lamp.spd")
            .unwrap_err()
            .to_string();
        assert!(e.starts_with("/nonexistent/lamp.spd: "), "{e}");
    }
}

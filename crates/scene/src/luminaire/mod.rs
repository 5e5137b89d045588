//! Photometric files (issue 24): IES LM-63 (1986, 1991, 1995, 2002, 2019)
//! and EULUMDAT (`.ldt`), recognised by their content, read into a type C
//! [`Photometry`] in candela over the whole sphere. Errors name the file
//! and line, and what was expected there.
//!
//! Layouts followed (facts from the standards' descriptions, no code):
//! - ANSI/IESNA LM-63-02, "Standard File Format for the Electronic
//!   Transfer of Photometric Data" (the 1995 layout differs in the second
//!   field of the ballast line: the ballast-lamp photometric factor, a
//!   multiplier, where 2002 has "future use"); ANSI/IES LM-63-19 keeps the
//!   2002 numbers (that field becomes the "file generation type") and
//!   gives negative opening dimensions shape meanings. Lighting Analysts'
//!   summaries: docs.agi32.com, "IESNA LM-63 Format".
//! - EULUMDAT: A. W. Stockmar, "EULUMDAT – ein Leuchtendatenformat für den
//!   europäischen Beleuchtungsplaner", Licht '90, pp. 641–644, and
//!   "EULUMDAT/2", CIBSE National Lighting Conference 1998, pp. 353–362;
//!   the line table as given at docs.agi32.com ("EULUMDAT File Format")
//!   and helios32.com/Eulumdat.htm.

mod distribution;
mod eulumdat;
mod ies;

pub use distribution::{Format, Opening, Photometry, Symmetry, Tilt};

use std::path::Path;

/// The largest photometric file read: a 0.5° × 0.5° full-sphere table is
/// ~260 000 numbers (a few MiB), so 64 MiB is generous and stops
/// `/dev/zero` or a runaway file.
pub const LUMINAIRE_FILE_LIMIT: u64 = 64 * scotopia_color::io::MIB;

/// The most angles of either kind a file may declare: 0.01° steps over a
/// full circle; stops a corrupt count from asking for gigabytes.
pub(crate) const MAX_ANGLES: usize = 36_001;

/// A photometric file that cannot be read or used.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}{}: {message}", if *line == 0 { String::new() } else { format!(":{line}") })]
pub struct LuminaireError {
    pub file: String,
    /// 1-based; 0: the file as a whole.
    pub line: usize,
    pub message: String,
}

pub(crate) fn error(file: &str, line: usize, message: impl Into<String>) -> LuminaireError {
    LuminaireError {
        file: file.to_string(),
        line,
        message: message.into(),
    }
}

/// Reads an IES LM-63 or EULUMDAT file, whichever its content is.
pub fn read_luminaire(path: impl AsRef<Path>) -> Result<Photometry, LuminaireError> {
    let path = path.as_ref();
    let name = path.display().to_string();
    let bytes = scotopia_color::io::read_limited(path, LUMINAIRE_FILE_LIMIT)
        .map_err(|e| error(&name, 0, e.to_string()))?;
    parse_luminaire(&decode(&bytes), &name)
}

/// Parses the text of an IES LM-63 or EULUMDAT file; `source` names it in
/// errors. Lines may end in LF, CRLF or CR alone.
///
/// The format is decided by structure, not by words in free text (a
/// EULUMDAT company called "IES Ltd" or a luminaire named "TILT=0°" is
/// still EULUMDAT): EULUMDAT has its type and symmetry indicators as whole
/// numbers on lines 2 and 3, where an IES file has keyword lines or its
/// `TILT=` line; IES has an `IESNA…`/`IES:LM-63…` first line or a `TILT=`
/// line (1986 files have free text before it). A file that looks like
/// both is read as EULUMDAT, and as IES only if that fails and IES
/// succeeds; the error reported is that of the format its first line
/// claims (an LM-63 header: IES), else EULUMDAT's.
pub fn parse_luminaire(text: &str, source: &str) -> Result<Photometry, LuminaireError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let lines: Vec<&str> = scotopia_color::io::lines(text).collect();
    match (ies::is_ies(&lines), eulumdat::is_eulumdat(&lines)) {
        (true, false) => ies::parse(&lines, source),
        (_, true) => eulumdat::parse(&lines, source).or_else(|ldt| {
            if !ies::is_ies(&lines) {
                return Err(ldt);
            }
            ies::parse(&lines, source).map_err(|e| if ies::has_header(&lines) { e } else { ldt })
        }),
        (false, false) => Err(error(
            source,
            1,
            "not a photometric file: no IESNA/IES:LM-63 header or TILT= line (IES LM-63), \
             and lines 2–3 are not EULUMDAT's type indicator (0–3) and symmetry indicator (0–4)",
        )),
    }
}

/// Text from bytes: UTF-8 where valid, else Latin-1 (EULUMDAT files from
/// European manufacturers often are), so names with accents never stop a
/// file whose numbers are plain ASCII.
fn decode(bytes: &[u8]) -> String {
    match std::str::from_utf8(bytes) {
        Ok(s) => s.to_string(),
        Err(_) => bytes.iter().map(|&b| b as char).collect(),
    }
}

/// Whitespace- (and, for IES, comma-) separated numbers with their line
/// numbers, read in order.
pub(crate) struct Tokens<'a> {
    items: Vec<(usize, &'a str)>,
    pos: usize,
    file: &'a str,
    /// Where "the file ends" is reported.
    end_line: usize,
}

impl<'a> Tokens<'a> {
    /// The tokens of `lines`, whose first is line `first_line` (1-based).
    pub(crate) fn new(lines: &[&'a str], first_line: usize, commas: bool, file: &'a str) -> Self {
        let mut items = Vec::new();
        for (k, line) in lines.iter().enumerate() {
            let split = line
                .split(|c: char| c.is_whitespace() || (commas && c == ','))
                .filter(|t| !t.is_empty());
            items.extend(split.map(|t| (first_line + k, t)));
        }
        // "The file ends" is reported at the last line holding a number
        // (else the line before these).
        let end_line = items
            .last()
            .map(|&(line, _)| line)
            .unwrap_or(first_line.saturating_sub(1).max(1));
        Tokens {
            items,
            pos: 0,
            file,
            end_line,
        }
    }

    pub(crate) fn remaining(&self) -> usize {
        self.items.len() - self.pos
    }

    /// The next token, if any.
    pub(crate) fn peek(&self) -> Option<(usize, &'a str)> {
        self.items.get(self.pos).copied()
    }

    /// The next number (finite; a decimal comma when `commas` was false is
    /// read as a point), or an error saying `what` was expected.
    pub(crate) fn number(&mut self, what: &str) -> Result<(usize, f64), LuminaireError> {
        let Some((line, token)) = self.peek() else {
            return Err(error(
                self.file,
                self.end_line,
                format!("the file ends: expected {what}"),
            ));
        };
        self.pos += 1;
        match parse_number(token) {
            Some(v) => Ok((line, v)),
            None => Err(error(
                self.file,
                line,
                format!("expected {what}, found '{token}'"),
            )),
        }
    }

    /// The next intensity of a table: a non-negative number times
    /// `factor`, finite in f32. `what` names it for an error (and is only
    /// formatted for one: tables run to millions of values); `unit` is the
    /// file's word for it.
    pub(crate) fn intensity(
        &mut self,
        factor: f64,
        unit: &str,
        what: impl Fn() -> String,
    ) -> Result<f32, LuminaireError> {
        let (line, v) = match self.peek().map(|(_, token)| parse_number(token)) {
            Some(Some(_)) => self.number("")?,
            _ => self.number(&what())?,
        };
        if v < 0.0 {
            return Err(error(
                self.file,
                line,
                format!("negative {unit} {v} (the {})", what()),
            ));
        }
        let scaled = (v * factor) as f32;
        if !scaled.is_finite() {
            return Err(error(
                self.file,
                line,
                format!("{unit} {v} × {factor} exceeds single precision"),
            ));
        }
        Ok(scaled)
    }

    /// The next number as a whole number within `min..=max`.
    pub(crate) fn integer(
        &mut self,
        what: &str,
        min: i64,
        max: i64,
    ) -> Result<(usize, i64), LuminaireError> {
        let (line, v) = self.number(what)?;
        integer_in(v, min, max).map(|n| (line, n)).ok_or_else(|| {
            error(
                self.file,
                line,
                format!("{what} must be a whole number from {min} to {max}, got {v}"),
            )
        })
    }
}

/// A finite number; `12,5` (a decimal comma, as EULUMDAT files from
/// European software have) reads as 12.5.
pub(crate) fn parse_number(token: &str) -> Option<f64> {
    let t = token.trim();
    let v = match t.parse::<f64>() {
        Ok(v) => v,
        Err(_) if t.contains(',') && !t.contains('.') => t.replace(',', ".").parse().ok()?,
        Err(_) => return None,
    };
    v.is_finite().then_some(v)
}

/// `v` as an integer within `min..=max`, if it is one.
pub(crate) fn integer_in(v: f64, min: i64, max: i64) -> Option<i64> {
    (v.fract() == 0.0 && v >= min as f64 && v <= max as f64).then_some(v as i64)
}

/// Checks a list of angles is strictly increasing within `lo..=hi`; the
/// error names the line of the first bad one.
pub(crate) fn check_angles(
    file: &str,
    what: &str,
    angles: &[(usize, f64)],
    lo: f64,
    hi: f64,
) -> Result<(), LuminaireError> {
    for (k, &(line, a)) in angles.iter().enumerate() {
        if a < lo || a > hi {
            return Err(error(
                file,
                line,
                format!("{what} {a}° is out of range (expected {lo}° to {hi}°)"),
            ));
        }
        if k > 0 && a <= angles[k - 1].1 {
            return Err(error(
                file,
                line,
                format!(
                    "{what} {a}° does not increase (the previous one is {}°)",
                    angles[k - 1].1
                ),
            ));
        }
    }
    Ok(())
}

//! IES LM-63 files (1986, 1991, 1995, 2002, 2019).
//!
//! Layout (LM-63-02 §5; 1995 and 2019 as noted):
//! 1. A header line `IESNA:LM-63-1995`, `IESNA:LM-63-2002`,
//!    `IES:LM-63-2019` (`IESNA91` for 1991; none in 1986 files).
//! 2. Keyword lines (`[TEST] …`, any order; 1986: free text), skipped.
//! 3. `TILT=NONE`, `TILT=INCLUDE` followed by the lamp-to-luminaire
//!    geometry (1–3), the number of tilt angles n, n angles and n
//!    multiplying factors; or `TILT=<file>`, a separate tilt file, which
//!    scotopia does not read (an error asking for TILT=INCLUDE: LM-63-2019
//!    dropped the form).
//! 4. Numbers, separated by blanks, commas or line breaks anywhere: number
//!    of lamps, lumens per lamp (−1: absolute photometry), candela
//!    multiplier, number of vertical angles, number of horizontal angles,
//!    photometric type (1 C, 2 B, 3 A), units (1 feet, 2 metres), width,
//!    length, height of the luminous opening; ballast factor, then the
//!    ballast-lamp photometric factor (1986–1995) or "future use" (2002)
//!    or the file generation type (2019), then input watts; the vertical
//!    angles, the horizontal angles, and the candela values, all vertical
//!    angles of the first horizontal angle, then of the next, and so on.
//!
//! Candela = value × multiplier × ballast factor (× the ballast-lamp
//! photometric factor in files before 2002). Only type C is rendered;
//! types A and B are read and refused with an error naming the file.

use super::distribution::{Format, Opening, Photometry, Symmetry, Tilt};
use super::{check_angles, error, LuminaireError, Tokens, MAX_ANGLES};

/// An IES file: its first line is an LM-63 header, or some line is `TILT=…`.
pub(super) fn is_ies(lines: &[&str]) -> bool {
    has_header(lines) || tilt_line(lines).is_some()
}

/// The first line is an LM-63 header (`IESNA…`, `IES:…`).
pub(super) fn has_header(lines: &[&str]) -> bool {
    let first = lines
        .first()
        .map(|l| l.trim_start().to_ascii_uppercase())
        .unwrap_or_default();
    first.starts_with("IESNA") || first.starts_with("IES:")
}

/// The index of the `TILT=` line and what follows the `=`.
fn tilt_line<'a>(lines: &[&'a str]) -> Option<(usize, &'a str)> {
    lines.iter().enumerate().find_map(|(k, line)| {
        let t = line.trim_start();
        let head = t.get(..4)?;
        if !head.eq_ignore_ascii_case("TILT") {
            return None;
        }
        t[4..].trim_start().strip_prefix('=').map(|v| (k, v.trim()))
    })
}

/// The year of the LM-63 version the header names.
fn version_year(first_line: &str) -> u16 {
    let upper = first_line.trim().to_ascii_uppercase();
    if let Some(pos) = upper.find("LM-63-") {
        let digits: String = upper[pos + 6..]
            .chars()
            .take_while(|c| c.is_ascii_digit())
            .collect();
        return match digits.parse::<u16>() {
            Ok(y) if digits.len() == 4 => y,
            Ok(y) if digits.len() == 2 && y < 80 => 2000 + y,
            Ok(y) if digits.len() == 2 => 1900 + y,
            // An unreadable year: the current layout.
            _ => 2019,
        };
    }
    if upper.starts_with("IESNA91") || upper.starts_with("IESNA:91") {
        1991
    } else {
        1986
    }
}

pub(super) fn parse(lines: &[&str], file: &str) -> Result<Photometry, LuminaireError> {
    let year = version_year(lines.first().copied().unwrap_or(""));
    let Some((tilt_at, tilt_value)) = tilt_line(lines) else {
        return Err(error(
            file,
            lines
                .iter()
                .rposition(|l| !l.trim().is_empty())
                .map_or(1, |k| k + 1),
            "the file ends without a TILT= line (expected TILT=NONE, TILT=INCLUDE or \
             TILT=<file> after the keywords)",
        ));
    };
    let mut t = Tokens::new(&lines[tilt_at + 1..], tilt_at + 2, true, file);

    let tilt = match tilt_value.to_ascii_uppercase().as_str() {
        "NONE" => None,
        "INCLUDE" => Some(read_tilt(&mut t, file)?),
        "" => {
            return Err(error(
                file,
                tilt_at + 1,
                "TILT= is empty (expected NONE, INCLUDE or a file name)",
            ))
        }
        _ => {
            return Err(error(
                file,
                tilt_at + 1,
                format!(
                    "TILT={tilt_value}: tilt data in a separate file is not supported \
                     (include it with TILT=INCLUDE, or TILT=NONE)"
                ),
            ))
        }
    };

    let (_, lamps) = t.integer("the number of lamps", 1, i64::MAX)?;
    let (lumens_line, lumens_per_lamp) =
        t.number("the lumens per lamp (−1: absolute photometry)")?;
    let lamp_lumens = if lumens_per_lamp == -1.0 {
        None
    } else if lumens_per_lamp > 0.0 {
        Some(lumens_per_lamp * lamps as f64)
    } else {
        return Err(error(
            file,
            lumens_line,
            format!(
                "lumens per lamp {lumens_per_lamp} must be positive, or −1 for absolute photometry"
            ),
        ));
    };
    let multiplier = non_negative(&mut t, file, "the candela multiplier")?;
    let max = MAX_ANGLES as i64;
    let (_, nv) = t.integer("the number of vertical angles", 2, max)?;
    let (_, nh) = t.integer("the number of horizontal angles", 1, max)?;
    let (type_line, photometric_type) = t.integer("the photometric type (1 C, 2 B, 3 A)", 1, 3)?;
    let (_, units) = t.integer("the units type (1 feet, 2 metres)", 1, 2)?;
    let to_metres = if units == 1 { 0.3048 } else { 1.0 };
    let (_, width) = t.number("the luminous opening's width")?;
    let (_, length) = t.number("the luminous opening's length")?;
    let (_, height) = t.number("the luminous opening's height")?;
    let ballast = non_negative(&mut t, file, "the ballast factor")?;
    let third = if year < 2002 {
        non_negative(&mut t, file, "the ballast-lamp photometric factor")?
    } else {
        // 2002: "future use"; 2019: the file generation type. Neither scales.
        t.number(if year < 2019 {
            "the future-use field (1)"
        } else {
            "the file generation type"
        })?;
        1.0
    };
    let (_, watts) = t.number("the input watts")?;

    let (nv, nh) = (nv as usize, nh as usize);
    let vertical = read_list(&mut t, nv, "vertical angle")?;
    let horizontal = read_list(&mut t, nh, "horizontal angle")?;
    let factor = multiplier * ballast * third;
    // Allocation bounded by what the file holds: a count larger than the
    // data fails at the end of the file, not in the allocator.
    let total = nv * nh;
    let mut planes: Vec<Vec<f32>> = Vec::with_capacity(nh.min(t.remaining() / nv + 1));
    for (j, &(_, h)) in horizontal.iter().enumerate() {
        let mut column = Vec::with_capacity(nv);
        for (i, &(_, v)) in vertical.iter().enumerate() {
            column.push(t.intensity(factor, "candela", || {
                format!(
                    "candela value {} of {total} (horizontal angle {h}°, vertical angle {v}°)",
                    j * nv + i + 1
                )
            })?);
        }
        planes.push(column);
    }
    if let Some((line, token)) = t.peek() {
        return Err(error(
            file,
            line,
            format!(
                "'{token}' after the last of the {nv} × {nh} candela values \
                 (expected the end of the file: are the numbers of angles right?)"
            ),
        ));
    }

    if photometric_type != 1 {
        let name = if photometric_type == 2 { "B" } else { "A" };
        return Err(error(
            file,
            type_line,
            format!(
                "photometric type {name} ({photometric_type}) is not supported: \
                 scotopia renders type C (1) photometry only"
            ),
        ));
    }
    check_angles(file, "vertical angle", &vertical, 0.0, 180.0)?;
    check_angles(file, "horizontal angle", &horizontal, 0.0, 360.0)?;
    let symmetry = horizontal_symmetry(&horizontal, file)?;

    let gamma = vertical.iter().map(|&(_, a)| a).collect();
    let planes = horizontal.iter().map(|&(_, c)| c).zip(planes).collect();
    let mut p = Photometry::from_planes(Format::Ies { year }, gamma, planes, symmetry)
        .map_err(|m| error(file, horizontal[0].0, m))?;
    p.opening = Opening {
        width_m: width * to_metres,
        length_m: length * to_metres,
        height_m: height * to_metres,
    };
    p.lamp_lumens = lamp_lumens;
    p.input_watts = (watts > 0.0).then_some(watts);
    p.tilt = tilt;
    Ok(p)
}

/// The symmetry type C horizontal angles imply (LM-63-02 §5.13; the
/// 90°–270° case from LM-63-1995).
fn horizontal_symmetry(h: &[(usize, f64)], file: &str) -> Result<Symmetry, LuminaireError> {
    let (first, last) = (h[0].1, h[h.len() - 1].1);
    Ok(if h.len() == 1 {
        Symmetry::Rotational
    } else if first == 0.0 && last == 90.0 {
        Symmetry::Quadrant
    } else if first == 0.0 && last == 180.0 {
        Symmetry::AboutC0C180
    } else if first == 0.0 {
        Symmetry::None
    } else if first == 90.0 && last == 270.0 {
        Symmetry::AboutC90C270
    } else {
        return Err(error(
            file,
            h[0].0,
            format!(
                "type C horizontal angles run from {first}° to {last}° (expected to start \
                 at 0° and end at 0°, 90°, 180° or 360°, or to run from 90° to 270°)"
            ),
        ));
    })
}

fn read_tilt(t: &mut Tokens, file: &str) -> Result<Tilt, LuminaireError> {
    let (_, geometry) = t.integer("the lamp-to-luminaire geometry (1–3) of TILT=INCLUDE", 1, 3)?;
    let (_, n) = t.integer("the number of tilt angles", 1, MAX_ANGLES as i64)?;
    let angles = read_list(t, n as usize, "tilt angle")?;
    check_angles(file, "tilt angle", &angles, 0.0, 180.0)?;
    let mut factors = Vec::with_capacity(angles.len());
    for k in 0..angles.len() {
        factors.push(non_negative(
            t,
            file,
            &format!("tilt multiplying factor {}", k + 1),
        )?);
    }
    Ok(Tilt {
        lamp_to_luminaire_geometry: geometry as u8,
        angles_deg: angles.into_iter().map(|(_, a)| a).collect(),
        factors,
    })
}

/// `n` numbers with their lines (allocation bounded by what is left).
fn read_list(t: &mut Tokens, n: usize, what: &str) -> Result<Vec<(usize, f64)>, LuminaireError> {
    let mut out = Vec::with_capacity(n.min(t.remaining()));
    for k in 0..n {
        out.push(t.number(&format!("{what} {} of {n}", k + 1))?);
    }
    Ok(out)
}

fn non_negative(t: &mut Tokens, file: &str, what: &str) -> Result<f64, LuminaireError> {
    let (line, v) = t.number(what)?;
    if v < 0.0 {
        return Err(error(file, line, format!("{what} {v} is negative")));
    }
    Ok(v)
}

//! EULUMDAT (`.ldt`) files: one field a line, at fixed line numbers.
//!
//! Lines (Stockmar 1990/1998; the table at docs.agi32.com and
//! helios32.com/Eulumdat.htm): 1 company; 2 type indicator Ityp (0–3);
//! 3 symmetry indicator Isym (0–4); 4 Mc, the number of C planes in
//! 0–360°; 5 Dc; 6 Ng, the number of γ angles per plane; 7 Dg; 8–12
//! report number, luminaire name and number, file name, date/user; 13–15
//! luminaire length (or diameter), width (0: circular), height in mm;
//! 16–17 luminous area length (or diameter) and width (0: circular) in mm;
//! 18–21 luminous area heights at C0, C90, C180, C270 in mm; 22 downward
//! flux fraction %; 23 light output ratio %; 24 conversion factor for the
//! intensities; 25 tilt during measurement; 26 n, the number of lamp
//! sets; then n lines each of: number of lamps, lamp type, **total**
//! luminous flux of the set in lm, colour appearance, colour rendering,
//! wattage with ballast; then 10 lines of direct ratios (room indices
//! 0.6–5); then the Mc C angles, the Ng γ angles, and the intensities in
//! cd/klm, plane after plane, Ng values each, for the planes Isym
//! requires: 0 all Mc; 1 one; 2 C0–C180 (Mc/2 + 1); 3 C270 through C0 to
//! C90 (Mc/2 + 1, starting at plane 3·Mc/4 + 1 of the C angles, as the
//! specification's Mc1 = 3·Mc/4 + 1, Mc2 = Mc1 + Mc/2 says; some readers
//! take C90–C270 instead, a mirror image of this); 4 C0–C90 (Mc/4 + 1).
//!
//! Candela = cd/klm × (Σ of the sets' total flux) / 1000 × the conversion
//! factor (line 24). Decimal commas are read as points.

use super::distribution::{Format, Opening, Photometry, Symmetry};
use super::{check_angles, error, integer_in, parse_number, LuminaireError, Tokens, MAX_ANGLES};

/// Lines 2 and 3 hold EULUMDAT's type and symmetry indicators.
pub(super) fn is_eulumdat(lines: &[&str]) -> bool {
    let int = |k: usize, max: i64| {
        lines
            .get(k)
            .and_then(|l| parse_number(l))
            .and_then(|v| integer_in(v, 0, max))
            .is_some()
    };
    int(1, 3) && int(2, 4)
}

/// Numbered header lines, each a field.
struct Header<'a> {
    lines: &'a [&'a str],
    file: &'a str,
}

impl Header<'_> {
    /// Line `n` (1-based) as a number.
    fn number(&self, n: usize, what: &str) -> Result<f64, LuminaireError> {
        let Some(text) = self.lines.get(n - 1) else {
            return Err(error(
                self.file,
                self.lines.len(),
                format!("the file ends: expected line {n}, {what}"),
            ));
        };
        parse_number(text).ok_or_else(|| {
            error(
                self.file,
                n,
                format!("expected {what}, found '{}'", text.trim()),
            )
        })
    }

    fn integer(&self, n: usize, what: &str, min: i64, max: i64) -> Result<i64, LuminaireError> {
        let v = self.number(n, what)?;
        integer_in(v, min, max).ok_or_else(|| {
            error(
                self.file,
                n,
                format!("{what} must be a whole number from {min} to {max}, got {v}"),
            )
        })
    }

    /// Line `n` must exist (a text field).
    fn present(&self, n: usize, what: &str) -> Result<(), LuminaireError> {
        if n > self.lines.len() {
            return Err(error(
                self.file,
                self.lines.len(),
                format!("the file ends: expected line {n}, {what}"),
            ));
        }
        Ok(())
    }
}

pub(super) fn parse(lines: &[&str], file: &str) -> Result<Photometry, LuminaireError> {
    let h = Header { lines, file };
    let isym = h.integer(3, "the symmetry indicator Isym", 0, 4)?;
    let max = MAX_ANGLES as i64;
    let mc = h.integer(4, "Mc, the number of C planes", 1, max)? as usize;
    let ng = h.integer(6, "Ng, the number of γ angles", 2, max)? as usize;
    let mm = 1e-3;
    let area_length = h.number(16, "the luminous area's length or diameter (mm)")?;
    let area_width = h.number(17, "the luminous area's width (mm; 0: circular)")?;
    let mut area_height: f64 = 0.0;
    for (n, plane) in [(18, "C0"), (19, "C90"), (20, "C180"), (21, "C270")] {
        area_height =
            area_height.max(h.number(n, &format!("the luminous area's height at {plane} (mm)"))?);
    }
    let conversion = h.number(24, "the conversion factor for luminous intensities")?;
    if conversion <= 0.0 {
        return Err(error(
            file,
            24,
            format!("the conversion factor {conversion} must be positive"),
        ));
    }
    let sets = h.integer(26, "n, the number of lamp sets", 1, 1000)? as usize;
    let mut flux = 0.0;
    let mut watts = 0.0;
    for k in 0..sets {
        let set = k + 1;
        h.number(27 + k, &format!("the number of lamps of set {set}"))?;
        h.present(27 + sets + k, &format!("the lamp type of set {set}"))?;
        let line = 27 + 2 * sets + k;
        let f = h.number(
            line,
            &format!("the total luminous flux of lamp set {set} (lm)"),
        )?;
        if f < 0.0 {
            return Err(error(file, line, format!("negative luminous flux {f} lm")));
        }
        flux += f;
        h.present(
            27 + 4 * sets + k,
            &format!("the colour rendering of set {set}"),
        )?;
        watts += h
            .number(
                27 + 5 * sets + k,
                &format!("the wattage of lamp set {set} (W)"),
            )?
            .max(0.0);
    }
    if flux <= 0.0 {
        return Err(error(
            file,
            27 + 2 * sets,
            "the lamps' total luminous flux is 0 lm: the intensities (cd/klm) cannot be \
             converted to candela",
        ));
    }
    let ratios = 27 + 6 * sets;
    h.present(ratios + 9, "the direct ratios (10 lines)")?;
    let data_start = ratios + 10; // 1-based line of the first C angle
    let mut t = Tokens::new(&lines[data_start - 1..], data_start, false, file);

    // Which of the C angles the stored planes are, by Isym.
    let multiple = |k: usize| {
        if mc.is_multiple_of(k) {
            Ok(())
        } else {
            Err(error(
                file,
                4,
                format!("Mc = {mc} must be a multiple of {k} for symmetry indicator {isym}"),
            ))
        }
    };
    let (indices, symmetry, expect): (Vec<usize>, Symmetry, Option<(f64, f64)>) = match isym {
        0 => ((0..mc).collect(), Symmetry::None, None),
        1 => (vec![0], Symmetry::Rotational, None),
        2 => {
            multiple(2)?;
            (
                (0..=mc / 2).collect(),
                Symmetry::AboutC0C180,
                Some((0.0, 180.0)),
            )
        }
        3 => {
            multiple(4)?;
            let first = 3 * mc / 4;
            let idx = (0..=mc / 2).map(|k| (first + k) % mc).collect();
            (idx, Symmetry::AboutC90C270, Some((270.0, 90.0)))
        }
        _ => {
            multiple(4)?;
            (
                (0..=mc / 4).collect(),
                Symmetry::Quadrant,
                Some((0.0, 90.0)),
            )
        }
    };
    let c_angles = read_list(&mut t, mc, "C angle")?;
    let gammas = read_list(&mut t, ng, "γ angle")?;
    check_angles(file, "C angle", &c_angles, 0.0, 360.0 - 1e-9)?;
    if c_angles[0].1 != 0.0 {
        return Err(error(
            file,
            c_angles[0].0,
            format!("the first C angle is {}° (expected 0°)", c_angles[0].1),
        ));
    }
    check_angles(file, "γ angle", &gammas, 0.0, 180.0)?;

    if let Some((from, to)) = expect {
        let a = c_angles[indices[0]].1;
        let b = c_angles[indices[indices.len() - 1]].1;
        if a != from || b != to {
            return Err(error(
                file,
                c_angles[indices[indices.len() - 1]].0,
                format!(
                    "symmetry indicator {isym} stores the planes C{from}° to C{to}°, but the C \
                     angles give C{a}° to C{b}° (are the C angles evenly spaced?)"
                ),
            ));
        }
    }

    let factor = flux / 1000.0 * conversion;
    let total = indices.len() * ng;
    let mut planes = Vec::with_capacity(indices.len().min(t.remaining() / ng + 1));
    for (p, &index) in indices.iter().enumerate() {
        let c = c_angles[index].1;
        let mut column = Vec::with_capacity(ng);
        for (i, &(_, g)) in gammas.iter().enumerate() {
            column.push(t.intensity(factor, "intensity", || {
                format!(
                    "intensity {} of {total} (C {c}°, γ {g}°, in cd/klm)",
                    p * ng + i + 1
                )
            })?);
        }
        planes.push((c, column));
    }
    if let Some((line, token)) = t.peek() {
        return Err(error(
            file,
            line,
            format!(
                "'{token}' after the last of the {total} intensities (expected the end of the \
                 file: are Mc, Ng and Isym right?)"
            ),
        ));
    }

    let gamma = gammas.iter().map(|&(_, g)| g).collect();
    let mut p = Photometry::from_planes(Format::Eulumdat, gamma, planes, symmetry)
        .map_err(|m| error(file, data_start, m))?;
    let length = area_length * mm;
    let width = area_width * mm;
    p.opening = if width == 0.0 {
        // Circular: LM-63-2019's code, negative width = length = diameter.
        Opening {
            width_m: -length,
            length_m: -length,
            height_m: area_height * mm,
        }
    } else {
        Opening {
            width_m: width,
            length_m: length,
            height_m: area_height * mm,
        }
    };
    p.lamp_lumens = Some(flux);
    p.input_watts = (watts > 0.0).then_some(watts);
    Ok(p)
}

fn read_list(t: &mut Tokens, n: usize, what: &str) -> Result<Vec<(usize, f64)>, LuminaireError> {
    let mut out = Vec::with_capacity(n.min(t.remaining()));
    for k in 0..n {
        out.push(t.number(&format!("{what} {} of {n}", k + 1))?);
    }
    Ok(out)
}

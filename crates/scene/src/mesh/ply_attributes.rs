//! A PLY element's other properties grouped into named mesh attributes,
//! by Mitsuba 3's rules (src/shapes/ply.h, `find_other_fields`):
//!
//! - `r g b` (or `red green blue`), with `a` (`alpha`) if present, are the
//!   attribute `{vertex|face}_color`;
//! - consecutive properties `{prefix}_{x y z w}`, `_{r g b a}`, `_{0 1 2 3}`
//!   or `_{1 2 3 4}` are the attribute `{vertex|face}_{prefix}` (with
//!   `_color` appended for the r g b a scheme), of 1 or 3 numbers;
//! - anything else is left out with a note (the loader's warning).
//!
//! Values as Mitsuba converts them: floating-point properties as they are;
//! integer ones normalised by their type's largest value and decoded from
//! the sRGB curve — except `uchar`, which Mitsuba 3 keeps as it is (0–255;
//! its integer range test starts at `char`), with a note.

use super::ply_scalar::Scalar;
use scotopia_color::space::srgb_decode;

/// Where each attribute's numbers come from in an element's records.
#[derive(Debug, Default)]
pub(super) struct Plan {
    /// Name, and the property index of each component.
    pub attributes: Vec<(String, Vec<usize>)>,
}

/// The four naming schemes, by position: x y z w, r g b a, 0 1 2 3, 1 2 3 4.
const SCHEMES: [[char; 4]; 4] = [
    ['x', 'y', 'z', 'w'],
    ['r', 'g', 'b', 'a'],
    ['0', '1', '2', '3'],
    ['1', '2', '3', '4'],
];

/// Groups the scalar properties `props` (name, type; `None` for lists) of
/// element `element` (`vertex` or `face`) other than `reserved` into
/// attributes; `notes` collects what is left out or read as it is.
pub(super) fn plan(
    element: &str,
    props: &[(&str, Option<Scalar>)],
    reserved: &[&str],
    notes: &mut Vec<String>,
) -> Plan {
    let mut plan = Plan::default();
    let find = |name: &str| props.iter().position(|(n, t)| *n == name && t.is_some());
    let mut used: Vec<usize> = reserved.iter().filter_map(|n| find(n)).collect();

    // Colours named without a prefix.
    for names in [["r", "g", "b", "a"], ["red", "green", "blue", "alpha"]] {
        let rgb: Vec<Option<usize>> = names[..3].iter().map(|n| find(n)).collect();
        if let [Some(r), Some(g), Some(b)] = rgb[..] {
            let mut sources = vec![r, g, b];
            sources.extend(find(names[3]));
            used.extend(&sources);
            plan.attributes.push((format!("{element}_color"), sources));
            break;
        }
    }

    // Prefixed groups, in the order of the properties.
    let mut seen: Vec<String> = Vec::new();
    let mut current: Option<(String, usize, Vec<usize>)> = None;
    let flush = |current: &mut Option<(String, usize, Vec<usize>)>,
                 plan: &mut Plan,
                 notes: &mut Vec<String>| {
        if let Some((prefix, scheme, sources)) = current.take() {
            if sources.len() == 1 || sources.len() == 3 {
                let colour = if scheme == 1 { "_color" } else { "" };
                plan.attributes
                    .push((format!("{element}_{prefix}{colour}"), sources));
            } else {
                notes.push(format!(
                    "{element} attribute '{prefix}' has {} fields, not 1 or 3: ignored",
                    sources.len()
                ));
            }
        }
    };
    for (i, &(name, t)) in props.iter().enumerate() {
        if used.contains(&i) || t.is_none() {
            continue;
        }
        let Some((prefix, postfix)) = name.rsplit_once('_') else {
            flush(&mut current, &mut plan, notes);
            notes.push(format!(
                "{element} property '{name}' has no '_' suffix naming a component: ignored"
            ));
            continue;
        };
        let mut chars = postfix.chars();
        let (Some(c), None) = (chars.next(), chars.next()) else {
            flush(&mut current, &mut plan, notes);
            notes.push(format!(
                "{element} property '{name}': a component suffix is one letter: ignored"
            ));
            continue;
        };
        if current.as_ref().is_some_and(|(p, _, _)| p != prefix) {
            flush(&mut current, &mut plan, notes);
        }
        match &mut current {
            Some((_, scheme, sources)) => {
                if sources.len() < 4 && SCHEMES[*scheme][sources.len()] == c {
                    sources.push(i);
                } else {
                    notes.push(format!(
                        "{element} attribute '{prefix}': '{name}' breaks its sequence of \
                         components: the attribute is ignored"
                    ));
                    current = None;
                    seen.push(prefix.to_string());
                }
            }
            None if seen.iter().any(|p| p == prefix) => notes.push(format!(
                "{element} property '{name}': its attribute '{prefix}' was already read: ignored"
            )),
            None => match SCHEMES.iter().position(|s| s[0] == c) {
                Some(scheme) => {
                    seen.push(prefix.to_string());
                    current = Some((prefix.to_string(), scheme, vec![i]));
                }
                None => notes.push(format!(
                    "{element} property '{name}': an attribute starts with a component \
                     x, r, 0 or 1: ignored"
                )),
            },
        }
    }
    flush(&mut current, &mut plan, notes);

    // A name read twice keeps its first (Mitsuba refuses the second).
    let mut kept: Vec<(String, Vec<usize>)> = Vec::new();
    for (name, sources) in plan.attributes.drain(..) {
        if kept.iter().any(|(n, _)| *n == name) {
            notes.push(format!("a second attribute '{name}' is ignored"));
        } else {
            kept.push((name, sources));
        }
    }
    plan.attributes = kept;

    for (name, sources) in &plan.attributes {
        if sources.iter().any(|&i| props[i].1 == Some(Scalar::U8)) {
            notes.push(format!(
                "attribute '{name}' is stored as uchar: its values are read as they are \
                 (0–255), as Mitsuba 3 reads them; attributes are expected in [0, 1]"
            ));
        }
    }
    plan
}

impl Plan {
    /// Appends one record's attribute values (`values` holds the record's
    /// properties, typed by `props`) to `out`, one vector per attribute.
    pub fn push(&self, values: &[f64], props: &[(&str, Option<Scalar>)], out: &mut [Vec<f32>]) {
        for ((_, sources), out) in self.attributes.iter().zip(out) {
            for &i in sources {
                out.push(convert(values[i], props[i].1));
            }
        }
    }
}

/// A property's value as Mitsuba converts it to a float (see the module
/// notes).
fn convert(v: f64, t: Option<Scalar>) -> f32 {
    let max = match t {
        Some(Scalar::I8) => i8::MAX as f64,
        Some(Scalar::I16) => i16::MAX as f64,
        Some(Scalar::U16) => u16::MAX as f64,
        Some(Scalar::I32) => i32::MAX as f64,
        Some(Scalar::U32) => u32::MAX as f64,
        Some(Scalar::U8 | Scalar::F32 | Scalar::F64) | None => return v as f32,
    };
    let x = (v / max).clamp(-1.0, 1.0);
    (x.signum() * srgb_decode(x.abs())) as f32
}

#[cfg(test)]
mod tests {
    use super::*;

    fn names(plan: &Plan) -> Vec<(&str, usize)> {
        plan.attributes
            .iter()
            .map(|(n, s)| (n.as_str(), s.len()))
            .collect()
    }

    #[test]
    fn groups_follow_mitsubas_naming() {
        let f = Some(Scalar::F32);
        let props = [
            ("x", f),
            ("y", f),
            ("z", f),
            ("red", Some(Scalar::U8)),
            ("green", Some(Scalar::U8)),
            ("blue", Some(Scalar::U8)),
            ("color_0", f),
            ("color_1", f),
            ("color_2", f),
            ("albedo_r", f),
            ("albedo_g", f),
            ("albedo_b", f),
            ("weight_0", f),
            ("pair_x", f),
            ("pair_y", f),
            ("loose", f),
            ("list", None),
        ];
        let mut notes = Vec::new();
        let plan = plan("vertex", &props, &["x", "y", "z"], &mut notes);
        assert_eq!(
            names(&plan),
            vec![
                ("vertex_color", 3),
                ("vertex_albedo_color", 3),
                ("vertex_weight", 1),
            ]
        );
        assert!(notes.iter().any(|n| n.contains("'pair' has 2 fields")));
        assert!(notes.iter().any(|n| n.contains("'loose'")));
        assert!(notes.iter().any(|n| n.contains("uchar")));
        assert!(notes
            .iter()
            .any(|n| n.contains("second attribute 'vertex_color'")));
    }

    #[test]
    fn integers_convert_as_mitsuba_converts_them() {
        // Checked against Mitsuba 3.9.1's PLY loader.
        assert_eq!(convert(128.0, Some(Scalar::U8)), 128.0);
        assert!((convert(1000.0, Some(Scalar::U16)) - 0.001_181_04).abs() < 1e-7);
        assert!((convert(-5.0, Some(Scalar::I8)) + 0.003_047_22).abs() < 1e-7);
        assert!((convert(50.0, Some(Scalar::I8)) - 0.128_496).abs() < 1e-6);
        assert_eq!(convert(0.25, Some(Scalar::F64)), 0.25);
    }
}

//! Reading values from nodes: numbers, vectors and `<transform>` blocks.

use scotopia_render::math::{Transform, Vec3};

use super::error::SceneError;
use super::parse::Node;

/// Parses a list of numbers separated by commas and/or spaces; every
/// number must be finite.
pub fn parse_floats(node: &Node, text: &str) -> Result<Vec<f32>, SceneError> {
    text.split(|c: char| c == ',' || c.is_whitespace())
        .filter(|s| !s.is_empty())
        .map(|s| {
            let v: f32 = s
                .parse()
                .map_err(|_| node.error(format!("'{s}' is not a number")))?;
            if v.is_finite() {
                Ok(v)
            } else {
                Err(node.error(format!("'{s}' is not a finite number")))
            }
        })
        .collect()
}

/// An `<rgb value="r, g, b">` (or one number for grey).
pub fn parse_rgb(node: &Node) -> Result<[f32; 3], SceneError> {
    match parse_floats(node, node.require("value")?)?.as_slice() {
        [r, g, b] => Ok([*r, *g, *b]),
        [v] => Ok([*v; 3]),
        _ => Err(node.error("expected 3 numbers (R, G, B)")),
    }
}

/// A 3-vector from `value="x y z"` (or `value="s"` → (s, s, s) when
/// `splat`), else from the `x`, `y`, `z` attributes with default `fill`.
fn vector(node: &Node, fill: f32, splat: bool) -> Result<Vec3, SceneError> {
    if let Some(v) = node.attr("value") {
        let f = parse_floats(node, v)?;
        return match f.len() {
            3 => Ok(Vec3::new(f[0], f[1], f[2])),
            1 if splat => Ok(Vec3::splat(f[0])),
            n => Err(node.error(format!("expected 3 numbers in 'value', found {n}"))),
        };
    }
    let mut out = [fill; 3];
    for (i, k) in ["x", "y", "z"].iter().enumerate() {
        if let Some(v) = node.attr(k) {
            let f = parse_floats(node, v)?;
            if f.len() != 1 {
                return Err(node.error(format!("attribute '{k}' must be one number")));
            }
            out[i] = f[0];
        }
    }
    Ok(Vec3::from(out))
}

/// A point-like attribute such as lookat's `origin="0, 1, 2"`.
fn point_attr(node: &Node, name: &str) -> Result<Vec3, SceneError> {
    let f = parse_floats(node, node.require(name)?)?;
    if f.len() != 3 {
        return Err(node.error(format!("'{name}' needs 3 numbers, found {}", f.len())));
    }
    Ok(Vec3::new(f[0], f[1], f[2]))
}

/// The transform a `<transform>` element describes: its operations in
/// document order, each applied after the previous (Mitsuba's rule).
pub fn read_transform(node: &Node) -> Result<Transform, SceneError> {
    let mut t = Transform::IDENTITY;
    for op in &node.children {
        let degenerate =
            || op.error("degenerate transform (zero scale, zero axis or singular matrix)");
        let m = match op.tag.as_str() {
            "translate" => Transform::translate(vector(op, 0.0, false)?),
            "scale" => Transform::scale(vector(op, 1.0, true)?).ok_or_else(degenerate)?,
            "rotate" => {
                let angle = parse_floats(op, op.require("angle")?)?;
                if angle.len() != 1 {
                    return Err(op.error("'angle' must be one number"));
                }
                Transform::rotate(vector(op, 0.0, false)?, angle[0]).ok_or_else(degenerate)?
            }
            "matrix" => {
                let f = parse_floats(op, op.require("value")?)?;
                let m: [[f64; 4]; 4] = match f.len() {
                    16 => std::array::from_fn(|r| std::array::from_fn(|c| f[4 * r + c] as f64)),
                    9 => std::array::from_fn(|r| {
                        std::array::from_fn(|c| match (r, c) {
                            (3, 3) => 1.0,
                            (3, _) | (_, 3) => 0.0,
                            _ => f[3 * r + c] as f64,
                        })
                    }),
                    n => {
                        return Err(op.error(format!("a matrix needs 16 (or 9) numbers, found {n}")))
                    }
                };
                Transform::from_matrix(m).ok_or_else(degenerate)?
            }
            "lookat" => {
                let up = if op.attr("up").is_some() {
                    point_attr(op, "up")?
                } else {
                    Vec3::new(0.0, 1.0, 0.0)
                };
                Transform::look_at(point_attr(op, "origin")?, point_attr(op, "target")?, up)
                    .ok_or_else(|| {
                        op.error("origin equals target, or up is parallel to the view direction")
                    })?
            }
            other => return Err(op.error(format!("unknown transform operation <{other}>"))),
        };
        t = m.then_after(&t);
    }
    Ok(t)
}

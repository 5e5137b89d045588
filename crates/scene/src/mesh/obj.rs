//! Wavefront OBJ: `v`, `vt`, `vn` and `f` (polygons fanned into
//! triangles, negative indices counted from the end); groups, smoothing and
//! materials are ignored. Each distinct (v, vt, vn) corner becomes one
//! vertex, as Mitsuba does.

use std::collections::HashMap;
use std::path::Path;

use scotopia_render::math::Vec3;

use super::{MeshData, MeshError};

pub fn read_obj(path: &Path) -> Result<MeshData, MeshError> {
    let file = path.display().to_string();
    let bytes = super::read_mesh_file(path)?;
    let text = String::from_utf8(bytes).map_err(|e| MeshError {
        file: file.clone(),
        line: 0,
        message: format!(
            "not UTF-8 text (invalid byte at offset {})",
            e.utf8_error().valid_up_to()
        ),
    })?;
    parse_obj(&text, &file)
}

/// Parses OBJ text; `file` names it in errors.
pub fn parse_obj(text: &str, file: &str) -> Result<MeshData, MeshError> {
    let mut v: Vec<Vec3> = Vec::new();
    let mut vt: Vec<[f32; 2]> = Vec::new();
    let mut vn: Vec<Vec3> = Vec::new();
    let mut corners: HashMap<(usize, Option<usize>, Option<usize>), u32> = HashMap::new();
    let mut out = MeshData::default();
    let (mut positions, mut uvs, mut normals) = (Vec::new(), Vec::new(), Vec::new());
    let mut points = Vec::new();
    let (mut all_uv, mut all_normal) = (true, true);

    for (i, raw) in text.lines().enumerate() {
        let line = i + 1;
        let err = |message: String| MeshError {
            file: file.to_string(),
            line,
            message,
        };
        let content = raw.split('#').next().unwrap_or("").trim();
        let mut parts = content.split_whitespace();
        let Some(keyword) = parts.next() else {
            continue;
        };
        let numbers = |parts: std::str::SplitWhitespace, n: usize| -> Result<Vec<f32>, MeshError> {
            let vals: Vec<f32> = parts
                .map(|s| {
                    s.parse::<f32>()
                        .ok()
                        .filter(|x| x.is_finite())
                        .ok_or_else(|| err(format!("'{s}' is not a finite number")))
                })
                .collect::<Result<_, _>>()?;
            if vals.len() < n {
                return Err(err(format!(
                    "'{keyword}' needs {n} numbers, found {}",
                    vals.len()
                )));
            }
            Ok(vals)
        };
        match keyword {
            "v" => {
                let p = numbers(parts, 3)?;
                v.push(Vec3::new(p[0], p[1], p[2]));
            }
            "vt" => {
                let p = numbers(parts, 2)?;
                vt.push([p[0], p[1]]);
            }
            "vn" => {
                let p = numbers(parts, 3)?;
                vn.push(Vec3::new(p[0], p[1], p[2]));
            }
            "f" => {
                let mut face = Vec::new();
                for corner in parts {
                    let mut fields = corner.split('/');
                    let resolve = |s: Option<&str>,
                                   len: usize,
                                   what: &str|
                     -> Result<Option<usize>, MeshError> {
                        match s {
                            None | Some("") => Ok(None),
                            Some(s) => {
                                let i: i64 = s
                                    .parse()
                                    .map_err(|_| err(format!("'{s}' is not an index")))?;
                                let idx = if i > 0 { i - 1 } else { len as i64 + i };
                                if i == 0 || idx < 0 || idx >= len as i64 {
                                    return Err(err(format!(
                                        "{what} index {i} is out of range (1..={len})"
                                    )));
                                }
                                Ok(Some(idx as usize))
                            }
                        }
                    };
                    let pi = resolve(fields.next(), v.len(), "vertex")?
                        .ok_or_else(|| err("a face corner has no vertex".into()))?;
                    let ti = resolve(fields.next(), vt.len(), "texture")?;
                    let ni = resolve(fields.next(), vn.len(), "normal")?;
                    let key = (pi, ti, ni);
                    let next = positions.len() as u32;
                    let id = *corners.entry(key).or_insert_with(|| {
                        positions.push(v[pi]);
                        points.push(pi as u32);
                        uvs.push(ti.map(|t| vt[t]));
                        normals.push(ni.map(|n| vn[n]));
                        next
                    });
                    all_uv &= ti.is_some();
                    all_normal &= ni.is_some();
                    face.push(id);
                }
                if face.len() < 3 {
                    return Err(err(format!(
                        "a face needs at least 3 corners, found {}",
                        face.len()
                    )));
                }
                for k in 1..face.len() - 1 {
                    out.indices.push([face[0], face[k], face[k + 1]]);
                }
            }
            // Grouping, smoothing and materials do not change the geometry.
            "o" | "g" | "s" | "usemtl" | "mtllib" | "l" | "p" => {}
            other => return Err(err(format!("unknown OBJ statement '{other}'"))),
        }
    }
    if out.indices.is_empty() {
        return Err(MeshError {
            file: file.to_string(),
            line: text.lines().count(),
            message: "no faces".into(),
        });
    }
    // Attributes only when every corner has one (a partial set is dropped).
    out.uvs = all_uv.then(|| uvs.into_iter().map(|t| t.unwrap_or([0.0, 0.0])).collect());
    out.normals = all_normal.then(|| {
        normals
            .into_iter()
            .map(|n| n.unwrap_or(Vec3::ZERO))
            .collect()
    });
    out.positions = positions;
    out.points = Some(points);
    Ok(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quad_with_attributes() {
        let m = parse_obj(
            "# a quad\nv 0 0 0\nv 1 0 0\nv 1 1 0\nv 0 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nvn 0 0 1\ng q\nf 1/1/1 2/2/1 3/3/1 -1/-1/-1\n",
            "q.obj",
        )
        .unwrap();
        assert_eq!(m.indices, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(m.positions.len(), 4);
        assert_eq!(m.uvs.as_ref().unwrap()[2], [1.0, 1.0]);
        assert_eq!(m.normals.as_ref().unwrap()[0], Vec3::new(0.0, 0.0, 1.0));
        let plain = parse_obj("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n", "t.obj").unwrap();
        assert!(plain.uvs.is_none() && plain.normals.is_none());
    }

    #[test]
    fn errors_name_file_and_line() {
        let e = |t: &str| parse_obj(t, "m.obj").unwrap_err().to_string();
        assert!(e("v 0 0 0\nv 1 x 0\n").starts_with("m.obj:2: 'x' is not a finite number"));
        assert!(e("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 4\n")
            .starts_with("m.obj:4: vertex index 4 is out of range"));
        assert!(
            e("v 0 0 0\nv 1 0 0\nf 1 2\n").starts_with("m.obj:3: a face needs at least 3 corners")
        );
        assert!(e("v 0 0 0\nv 1 0 0\nv 0 1 0\nf 0 1 2\n").contains("out of range"));
        assert!(e("v 0 0 0\n").contains("no faces"));
        assert!(e("v 0 0 nan\n").contains("not a finite"));
        assert!(e("bogus 1\n").contains("unknown OBJ statement"));
    }
}

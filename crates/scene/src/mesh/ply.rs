//! PLY (Stanford polygon files), ASCII and binary of either byte order:
//! vertex positions, normals (`nx ny nz`) and texture coordinates
//! (`u v`, `s t` or `texture_u texture_v`), faces as index lists (fanned
//! into triangles), and the vertices' and faces' other properties as named
//! attributes (`ply_attributes`). Other elements are skipped. Errors name
//! the header or data line, or the byte offset in binary data.

use std::path::Path;

use scotopia_render::geometry::Attribute;
use scotopia_render::math::Vec3;

use super::ply_attributes::{self, Plan};
use super::ply_scalar::Scalar;
use super::{MeshData, MeshError};

/// Vertex properties read as geometry, not attributes.
const VERTEX_RESERVED: [&str; 14] = [
    "x",
    "y",
    "z",
    "nx",
    "ny",
    "nz",
    "u",
    "v",
    "s",
    "t",
    "texture_u",
    "texture_v",
    "texture_s",
    "texture_t",
];

#[derive(Debug, Clone)]
enum Property {
    Scalar(String, Scalar),
    List(String, Scalar, Scalar),
}

#[derive(Debug, Clone)]
struct Element {
    name: String,
    count: usize,
    properties: Vec<Property>,
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Format {
    Ascii,
    Little,
    Big,
}

/// Reads numbers from the data section, in either encoding.
struct Reader<'a> {
    format: Format,
    bytes: &'a [u8],
    pos: usize,
    /// ASCII: the tokens of the data section with their line numbers.
    tokens: Vec<(&'a str, usize)>,
    next: usize,
    file: &'a str,
}

impl Reader<'_> {
    fn err(&self, message: String) -> MeshError {
        let line = match self.format {
            Format::Ascii => self
                .tokens
                .get(self.next.saturating_sub(1))
                .map_or(0, |t| t.1),
            _ => 0,
        };
        let message = match self.format {
            Format::Ascii => message,
            _ => format!("byte {}: {message}", self.pos),
        };
        MeshError {
            file: self.file.to_string(),
            line,
            message,
        }
    }

    fn read(&mut self, t: Scalar) -> Result<f64, MeshError> {
        if self.format == Format::Ascii {
            let Some(&(tok, _)) = self.tokens.get(self.next) else {
                return Err(self.err("the data ends early".into()));
            };
            self.next += 1;
            return tok
                .parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| self.err(format!("'{tok}' is not a finite number")));
        }
        let n = t.size();
        let Some(raw) = self.bytes.get(self.pos..self.pos + n) else {
            return Err(self.err("the data ends early".into()));
        };
        let mut b = [0u8; 8];
        b[..n].copy_from_slice(raw);
        if self.format == Format::Big {
            b[..n].reverse();
        }
        self.pos += n;
        let v = match t {
            Scalar::I8 => b[0] as i8 as f64,
            Scalar::U8 => b[0] as f64,
            Scalar::I16 => i16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::U16 => u16::from_le_bytes([b[0], b[1]]) as f64,
            Scalar::I32 => i32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::U32 => u32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F32 => f32::from_le_bytes([b[0], b[1], b[2], b[3]]) as f64,
            Scalar::F64 => f64::from_le_bytes(b),
        };
        if !v.is_finite() {
            return Err(self.err("a value is not finite".into()));
        }
        Ok(v)
    }
}

pub fn read_ply(path: &Path) -> Result<MeshData, MeshError> {
    let file = path.display().to_string();
    let bytes = super::read_mesh_file(path)?;
    parse_ply(&bytes, &file)
}

/// Parses PLY bytes; `file` names them in errors.
pub fn parse_ply(bytes: &[u8], file: &str) -> Result<MeshData, MeshError> {
    let err = |line: usize, message: String| MeshError {
        file: file.to_string(),
        line,
        message,
    };
    // The header: ASCII lines up to `end_header`.
    let mut format = None;
    let mut elements: Vec<Element> = Vec::new();
    let mut offset = 0;
    let mut line_no = 0;
    loop {
        let end = bytes[offset..]
            .iter()
            .position(|&b| b == b'\n')
            .ok_or_else(|| err(line_no + 1, "the header has no end_header".into()))?;
        let line = std::str::from_utf8(&bytes[offset..offset + end])
            .map_err(|_| err(line_no + 1, "the header is not text".into()))?
            .trim();
        offset += end + 1;
        line_no += 1;
        let words: Vec<&str> = line.split_whitespace().collect();
        match words.as_slice() {
            ["ply"] if line_no == 1 => {}
            _ if line_no == 1 => return Err(err(1, "not a PLY file (no 'ply' magic)".into())),
            ["format", f, _] => {
                format = Some(match *f {
                    "ascii" => Format::Ascii,
                    "binary_little_endian" => Format::Little,
                    "binary_big_endian" => Format::Big,
                    other => return Err(err(line_no, format!("unknown format '{other}'"))),
                })
            }
            ["comment", ..] | ["obj_info", ..] | [] => {}
            ["element", name, count] => elements.push(Element {
                name: name.to_string(),
                count: count
                    .parse()
                    .map_err(|_| err(line_no, format!("'{count}' is not a count")))?,
                properties: Vec::new(),
            }),
            ["property", "list", c, i, name] => {
                let (c, i) = (Scalar::parse(c), Scalar::parse(i));
                let e = elements
                    .last_mut()
                    .ok_or_else(|| err(line_no, "a property before any element".into()))?;
                match (c, i) {
                    (Some(c), Some(i)) => e.properties.push(Property::List(name.to_string(), c, i)),
                    _ => return Err(err(line_no, "unknown list types".into())),
                }
            }
            ["property", t, name] => {
                let t =
                    Scalar::parse(t).ok_or_else(|| err(line_no, format!("unknown type '{t}'")))?;
                let e = elements
                    .last_mut()
                    .ok_or_else(|| err(line_no, "a property before any element".into()))?;
                e.properties.push(Property::Scalar(name.to_string(), t));
            }
            ["end_header"] => break,
            _ => return Err(err(line_no, format!("cannot read header line '{line}'"))),
        }
    }
    let format = format.ok_or_else(|| err(line_no, "the header has no format line".into()))?;
    let data = &bytes[offset..];
    let text = if format == Format::Ascii {
        std::str::from_utf8(data).map_err(|_| err(line_no + 1, "ASCII data is not text".into()))?
    } else {
        ""
    };
    let mut reader = Reader {
        format,
        bytes: data,
        pos: 0,
        tokens: text
            .lines()
            .enumerate()
            .flat_map(|(i, l)| l.split_whitespace().map(move |t| (t, line_no + 1 + i)))
            .collect(),
        next: 0,
        file,
    };

    let mut mesh = MeshData::default();
    let (mut normals, mut uvs) = (Vec::new(), Vec::new());
    let mut has = (false, false);
    // Attributes: per element, the plan and the values read.
    let mut attributes: Vec<(Plan, Vec<Vec<f32>>)> = Vec::new();
    for e in &elements {
        let typed: Vec<(&str, Option<Scalar>)> = e
            .properties
            .iter()
            .map(|p| match p {
                Property::Scalar(n, t) => (n.as_str(), Some(*t)),
                Property::List(n, _, _) => (n.as_str(), None),
            })
            .collect();
        let mut plan_for = |reserved: &[&str]| {
            let plan = ply_attributes::plan(&e.name, &typed, reserved, &mut mesh.notes);
            let out = vec![Vec::new(); plan.attributes.len()];
            (plan, out)
        };
        if e.name == "vertex" {
            let (plan, mut out) = plan_for(&VERTEX_RESERVED);
            let find = |names: &[&str]| {
                e.properties.iter().position(
                    |p| matches!(p, Property::Scalar(n, _) if names.contains(&n.as_str())),
                )
            };
            let (x, y, z) = (find(&["x"]), find(&["y"]), find(&["z"]));
            let (nx, ny, nz) = (find(&["nx"]), find(&["ny"]), find(&["nz"]));
            let (u, v) = (
                find(&["u", "s", "texture_u", "texture_s"]),
                find(&["v", "t", "texture_v", "texture_t"]),
            );
            if x.is_none() || y.is_none() || z.is_none() {
                return Err(err(0, "the vertex element has no x, y, z".into()));
            }
            has = (
                nx.is_some() && ny.is_some() && nz.is_some(),
                u.is_some() && v.is_some(),
            );
            for _ in 0..e.count {
                let mut values = vec![0.0f64; e.properties.len()];
                for (k, p) in e.properties.iter().enumerate() {
                    values[k] = read_property(&mut reader, p)?;
                }
                let get = |i: Option<usize>| i.map_or(0.0, |i| values[i]) as f32;
                mesh.positions.push(Vec3::new(get(x), get(y), get(z)));
                if has.0 {
                    normals.push(Vec3::new(get(nx), get(ny), get(nz)));
                }
                if has.1 {
                    uvs.push([get(u), get(v)]);
                }
                plan.push(&values, &typed, &mut out);
            }
            attributes.push((plan, out));
        } else if e.name == "face" {
            let list = e
                .properties
                .iter()
                .position(|p| matches!(p, Property::List(n, _, _) if n == "vertex_indices" || n == "vertex_index"));
            let (plan, mut out) = plan_for(&[]);
            let mut values = vec![0.0f64; e.properties.len()];
            for _ in 0..e.count {
                let first = mesh.indices.len();
                for (k, p) in e.properties.iter().enumerate() {
                    match p {
                        Property::List(_, ct, it) if Some(k) == list => {
                            let n = reader.read(*ct)? as usize;
                            if !(3..=1024).contains(&n) {
                                return Err(reader.err(format!("a face with {n} corners")));
                            }
                            let mut face = Vec::with_capacity(n);
                            for _ in 0..n {
                                let i = reader.read(*it)?;
                                if i < 0.0 || i as usize >= mesh.positions.len() {
                                    return Err(reader.err(format!(
                                        "vertex index {i} is out of range ({} vertices)",
                                        mesh.positions.len()
                                    )));
                                }
                                face.push(i as u32);
                            }
                            for j in 1..n - 1 {
                                mesh.indices.push([face[0], face[j], face[j + 1]]);
                            }
                        }
                        other => {
                            values[k] = read_property(&mut reader, other)?;
                        }
                    }
                }
                // A face's attributes, once per triangle of its fan.
                for _ in first..mesh.indices.len() {
                    plan.push(&values, &typed, &mut out);
                }
            }
            attributes.push((plan, out));
        } else {
            for _ in 0..e.count {
                for p in &e.properties {
                    read_property(&mut reader, p)?;
                }
            }
        }
    }
    if mesh.indices.is_empty() {
        return Err(err(0, "no faces".into()));
    }
    mesh.normals = has.0.then_some(normals);
    mesh.uvs = has.1.then_some(uvs);
    for (plan, values) in attributes {
        for ((name, sources), values) in plan.attributes.into_iter().zip(values) {
            mesh.attributes.push(Attribute {
                name,
                dim: sources.len(),
                values,
            });
        }
    }
    Ok(mesh)
}

/// Reads one property (a list is read and discarded, its length bounded);
/// returns a scalar's value.
fn read_property(r: &mut Reader, p: &Property) -> Result<f64, MeshError> {
    match p {
        Property::Scalar(_, t) => r.read(*t),
        Property::List(_, ct, it) => {
            let n = r.read(*ct)?;
            if !(0.0..=1e6).contains(&n) {
                return Err(r.err(format!("a list of {n} items")));
            }
            for _ in 0..n as usize {
                r.read(*it)?;
            }
            Ok(0.0)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const ASCII: &str = "ply\nformat ascii 1.0\ncomment a quad\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\nproperty float nx\nproperty float ny\nproperty float nz\nproperty float u\nproperty float v\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 0 0 1 0 0\n1 0 0 0 0 1 1 0\n1 1 0 0 0 1 1 1\n0 1 0 0 0 1 0 1\n4 0 1 2 3\n";

    fn binary(big: bool) -> Vec<u8> {
        let mut b = format!(
            "ply\nformat {} 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty uchar flags\nproperty list uchar uint vertex_indices\nend_header\n",
            if big { "binary_big_endian" } else { "binary_little_endian" }
        )
        .into_bytes();
        let f = |v: f32| {
            if big {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            }
        };
        let u = |v: u32| {
            if big {
                v.to_be_bytes()
            } else {
                v.to_le_bytes()
            }
        };
        for p in [[0.0f32, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]] {
            for c in p {
                b.extend_from_slice(&f(c));
            }
        }
        b.push(7); // flags, skipped
        b.push(3);
        for i in [0u32, 1, 2] {
            b.extend_from_slice(&u(i));
        }
        b
    }

    #[test]
    fn ascii_with_attributes() {
        let m = parse_ply(ASCII.as_bytes(), "q.ply").unwrap();
        assert_eq!(m.indices, vec![[0, 1, 2], [0, 2, 3]]);
        assert_eq!(m.normals.unwrap()[3], Vec3::new(0.0, 0.0, 1.0));
        assert_eq!(m.uvs.unwrap()[2], [1.0, 1.0]);
    }

    #[test]
    fn binary_both_byte_orders() {
        for big in [false, true] {
            let m = parse_ply(&binary(big), "t.ply").unwrap();
            assert_eq!(m.positions[1], Vec3::new(1.0, 0.0, 0.0));
            assert_eq!(m.indices, vec![[0, 1, 2]]);
            assert!(m.normals.is_none() && m.uvs.is_none());
        }
    }

    #[test]
    fn errors_name_the_place() {
        let e = |b: &[u8]| parse_ply(b, "m.ply").unwrap_err().to_string();
        assert!(e(b"plx\n").starts_with("m.ply:1: not a PLY file"));
        assert!(e(ASCII
            .replace("property float nx", "property quux nx")
            .as_bytes())
        .starts_with("m.ply:8: unknown type 'quux'"));
        assert!(e(ASCII
            .replace("1 1 0 0 0 1 1 1", "1 x 0 0 0 1 1 1")
            .as_bytes())
        .starts_with("m.ply:18: 'x' is not a finite number"));
        assert!(e(ASCII.replace("4 0 1 2 3", "4 0 1 2 9").as_bytes())
            .contains("vertex index 9 is out of range"));
        let mut short = binary(false);
        short.truncate(short.len() - 2);
        assert!(e(&short).contains("byte") && e(&short).contains("ends early"));
        assert!(e(b"ply\nformat ascii 1.0\nelement vertex 1\n").contains("no end_header"));
    }
}

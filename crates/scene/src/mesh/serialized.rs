//! Mitsuba's serialized meshes (`.serialized`), format versions 3 and 4:
//! a sequence of shapes, each a 4-byte header (magic 0x041C, version)
//! followed by one zlib stream, and a dictionary of shape offsets at the
//! end of the file. A shape's stream holds a flag word, its name (version
//! 4, NUL-terminated), the vertex and triangle counts (u64), then arrays of
//! positions, normals, texture coordinates and colours (single or double
//! precision by the flags) and 3 u32 vertex indices per triangle.
//! Everything is little endian. Colours are read and skipped, as Mitsuba
//! does. Every count is checked against the bytes actually present before
//! anything is allocated for it.

use std::io::Read;
use std::path::Path;

use scotopia_render::geometry::Attribute;
use scotopia_render::math::Vec3;

use super::{MeshData, MeshError};

/// The file format identifier (the first u16).
const MAGIC: u16 = 0x041C;

// The flag word of versions 3 and 4.
const HAS_NORMALS: u32 = 0x0001;
const HAS_TEXCOORDS: u32 = 0x0002;
const HAS_COLORS: u32 = 0x0008;
const DOUBLE_PRECISION: u32 = 0x2000;

/// The longest shape name read (version 4); longer means a corrupt stream.
const MAX_NAME: usize = 1 << 16;

/// A shape read from a serialized file: its mesh and (version 4) its name.
#[derive(Debug, Clone, PartialEq)]
pub struct SerializedShape {
    pub name: Option<String>,
    pub mesh: MeshData,
}

pub fn read_serialized(path: &Path, shape_index: usize) -> Result<SerializedShape, MeshError> {
    let file = path.display().to_string();
    let bytes = super::read_mesh_file(path)?;
    parse_serialized(&bytes, shape_index, &file)
}

/// Parses the shape `shape_index` of a serialized file's bytes; `file`
/// names it in errors, which also give the shape index and the byte
/// offset of that shape's header in the file.
pub fn parse_serialized(
    bytes: &[u8],
    shape_index: usize,
    file: &str,
) -> Result<SerializedShape, MeshError> {
    let err = |offset: usize, message: String| MeshError {
        file: file.to_string(),
        line: offset,
        message: format!("shape {shape_index}: {message}"),
    };
    // The file's header.
    let version = header(bytes, 0).map_err(|m| err(0, m))?;
    // Where the shape starts: the first at 0, others from the dictionary.
    let start = if shape_index == 0 {
        0
    } else {
        shape_offset(bytes, version, shape_index).map_err(|m| err(0, m))?
    };
    if start != 0 {
        let v = header(bytes, start).map_err(|m| err(start, m))?;
        if v != version {
            return Err(err(
                start,
                format!("version {v} differs from the file's version {version}"),
            ));
        }
    }
    let stream = &bytes[start + 4..];
    read_shape(stream, version).map_err(|m| err(start, m))
}

/// The version in the 4-byte header at `at`.
fn header(bytes: &[u8], at: usize) -> Result<u16, String> {
    let h = bytes
        .get(at..at.saturating_add(4))
        .ok_or_else(|| "the file is too short for a serialized header".to_string())?;
    let magic = u16::from_le_bytes([h[0], h[1]]);
    if magic != MAGIC {
        return Err(format!(
            "not a serialized mesh (bad magic 0x{magic:04X}, expected 0x{MAGIC:04X})"
        ));
    }
    match u16::from_le_bytes([h[2], h[3]]) {
        v @ (3 | 4) => Ok(v),
        v => Err(format!(
            "serialized format version {v} is not supported (only 3 and 4)"
        )),
    }
}

/// The offset of shape `index` from the dictionary at the end of the
/// file: u64 offsets (u32 in version 3), then the u32 shape count.
fn shape_offset(bytes: &[u8], version: u16, index: usize) -> Result<usize, String> {
    let truncated = || "the file is too short for its shape dictionary".to_string();
    let n = bytes.len();
    let count_at = n.checked_sub(4).ok_or_else(truncated)?;
    let count = u32::from_le_bytes(bytes[count_at..].try_into().map_err(|_| truncated())?) as usize;
    if index >= count {
        return Err(format!(
            "shape index {index} is out of range: the file holds {count} shape{}",
            if count == 1 { "" } else { "s" }
        ));
    }
    let width = if version >= 4 { 8 } else { 4 };
    let at = (count - index)
        .checked_mul(width)
        .and_then(|d| count_at.checked_sub(d))
        .ok_or_else(truncated)?;
    let raw = &bytes[at..at + width];
    let offset = if width == 8 {
        u64::from_le_bytes(raw.try_into().map_err(|_| truncated())?)
    } else {
        u32::from_le_bytes(raw.try_into().map_err(|_| truncated())?) as u64
    };
    usize::try_from(offset)
        .ok()
        .filter(|&o| o < at)
        .ok_or_else(|| format!("the dictionary's offset {offset} lies outside the file"))
}

/// Reads one shape's zlib stream (after its header).
fn read_shape(stream: &[u8], version: u16) -> Result<SerializedShape, String> {
    let mut z = flate2::read::ZlibDecoder::new(stream);
    let mut word = [0u8; 4];
    read_into(&mut z, &mut word, "the flags")?;
    let flags = u32::from_le_bytes(word);
    // The name, NUL-terminated (version 4).
    let name = if version == 4 {
        let mut name = Vec::new();
        let mut byte = [0u8; 1];
        loop {
            read_into(&mut z, &mut byte, "the shape name")?;
            if byte[0] == 0 {
                break;
            }
            name.push(byte[0]);
            if name.len() > MAX_NAME {
                return Err(format!(
                    "the shape name is longer than {MAX_NAME} bytes (corrupt data)"
                ));
            }
        }
        Some(String::from_utf8_lossy(&name).into_owned())
    } else {
        None
    };
    let mut counts = [0u8; 16];
    read_into(&mut z, &mut counts, "the vertex and triangle counts")?;
    let vertices = u64::from_le_bytes(std::array::from_fn(|k| counts[k]));
    let triangles = u64::from_le_bytes(std::array::from_fn(|k| counts[8 + k]));
    if vertices > u32::MAX as u64 {
        return Err(format!(
            "{vertices} vertices: more than 2³² − 1 are not supported"
        ));
    }
    let double = flags & DOUBLE_PRECISION != 0;
    // The arrays; each is read only as far as the stream has data.
    let mut floats = |what: &str, dim: u64| read_floats(&mut z, vertices * dim, double, what);
    let vec3s = |v: Vec<f32>| -> Vec<Vec3> {
        v.chunks_exact(3)
            .map(|c| Vec3::new(c[0], c[1], c[2]))
            .collect()
    };
    let positions = vec3s(floats("vertex positions", 3)?);
    let normals = if flags & HAS_NORMALS != 0 {
        Some(vec3s(floats("vertex normals", 3)?))
    } else {
        None
    };
    let uvs = if flags & HAS_TEXCOORDS != 0 {
        Some(
            floats("texture coordinates", 2)?
                .chunks_exact(2)
                .map(|c| [c[0], c[1]])
                .collect(),
        )
    } else {
        None
    };
    // Vertex colours as the attribute `vertex_color` (Mitsuba 3.9 skips
    // them; scotopia keeps them for `mesh_attribute`).
    let colors = if flags & HAS_COLORS != 0 {
        Some(floats("vertex colors", 3)?)
    } else {
        None
    };
    let bytes = triangles
        .checked_mul(12)
        .ok_or_else(|| format!("{triangles} triangles overflow (corrupt data)"))?;
    let raw = read_exact(&mut z, bytes, "triangle indices")?;
    let mut indices = Vec::with_capacity(raw.len() / 12);
    for (f, c) in raw.chunks_exact(12).enumerate() {
        let tri: [u32; 3] = std::array::from_fn(|k| {
            u32::from_le_bytes([c[4 * k], c[4 * k + 1], c[4 * k + 2], c[4 * k + 3]])
        });
        if let Some(&i) = tri.iter().find(|&&i| i as u64 >= vertices) {
            return Err(format!(
                "triangle {f} refers to vertex {i} but the shape has {vertices} vertices"
            ));
        }
        indices.push(tri);
    }
    if indices.is_empty() {
        return Err("the shape has no triangles".into());
    }
    // The stream's end (and its checksum): data beyond the triangles is
    // ignored, as Mitsuba does, but a broken stream is an error.
    z.read(&mut [0u8; 1])
        .map_err(|e| format!("the compressed stream is corrupt or truncated: {e}"))?;
    Ok(SerializedShape {
        name,
        mesh: MeshData {
            positions,
            normals,
            uvs,
            indices,
            points: None,
            attributes: colors
                .map(|values| Attribute {
                    name: "vertex_color".into(),
                    dim: 3,
                    values,
                })
                .into_iter()
                .collect(),
            notes: Vec::new(),
        },
    })
}

/// `n` numbers, f64 or f32 in the file, as f32.
fn read_floats(z: &mut impl Read, n: u64, double: bool, what: &str) -> Result<Vec<f32>, String> {
    let raw = read_exact(z, n * if double { 8 } else { 4 }, what)?;
    Ok(if double {
        raw.chunks_exact(8)
            .map(|c| f64::from_le_bytes(std::array::from_fn(|k| c[k])) as f32)
            .collect()
    } else {
        raw.chunks_exact(4)
            .map(|c| f32::from_le_bytes(std::array::from_fn(|k| c[k])))
            .collect()
    })
}

/// Reads exactly `n` bytes of decompressed data, growing the buffer only
/// as data arrives (a corrupt count cannot allocate more than the stream
/// holds).
fn read_exact(z: &mut impl Read, n: u64, what: &str) -> Result<Vec<u8>, String> {
    let mut out = Vec::new();
    let got = z
        .take(n)
        .read_to_end(&mut out)
        .map_err(|e| format!("{what}: {e}"))?;
    if (got as u64) < n {
        return Err(format!(
            "truncated: {what} need {n} bytes, the stream has {got}"
        ));
    }
    Ok(out)
}

fn read_into(z: &mut impl Read, buf: &mut [u8], what: &str) -> Result<(), String> {
    let got = read_exact(z, buf.len() as u64, what)?;
    buf.copy_from_slice(&got);
    Ok(())
}

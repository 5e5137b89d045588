//! Mesh files: Wavefront OBJ, PLY and Mitsuba's serialized meshes, read
//! into plain vertex and index arrays. Errors name the file and line (the
//! byte offset for binary PLY and serialized files).

mod obj;
mod ply;
mod ply_attributes;
mod ply_scalar;
mod serialized;

pub use obj::{parse_obj, read_obj};
pub use ply::{parse_ply, read_ply};
pub use serialized::{parse_serialized, read_serialized, SerializedShape};

use std::path::Path;

use scotopia_render::geometry::Attribute;
use scotopia_render::math::Vec3;

/// The largest mesh file read (all three formats are read whole into
/// memory): 4 GiB is ~130 million triangles of binary PLY, more than a
/// scene's mesh files hold one by one (large scenes split their geometry
/// over many files), and stops `/dev/zero` or an endless pipe.
pub const MESH_LIMIT: u64 = 4096 * scotopia_color::io::MIB;

/// A mesh file's bytes, read up to [`MESH_LIMIT`] or a quarter of the
/// memory budget (`scotopia_image::limits`), whichever is smaller: the
/// file's bytes and the arrays parsed from them live together, so a file
/// that cannot be read on this machine stops early instead of after
/// gigabytes.
fn read_mesh_file(path: &Path) -> Result<Vec<u8>, MeshError> {
    let limit = MESH_LIMIT.min(scotopia_image::limits::memory_limit().0 / 2);
    scotopia_color::io::read_limited(path, limit).map_err(|e| MeshError {
        file: path.display().to_string(),
        line: 0,
        message: e.to_string(),
    })
}

/// A triangle mesh as read from a file, in object space.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct MeshData {
    pub positions: Vec<Vec3>,
    pub normals: Option<Vec<Vec3>>,
    pub uvs: Option<Vec<[f32; 2]>>,
    pub indices: Vec<[u32; 3]>,
    /// The surface point of each vertex, where vertices are split copies of
    /// one point (OBJ: the `v` line of a corner split by its `vt`/`vn`), so
    /// computed normals stay smooth across texture seams; `None`: each
    /// vertex is its own point.
    pub points: Option<Vec<u32>>,
    /// Named per-vertex and per-face attributes (PLY's other properties,
    /// serialized vertex colours), per triangle for face attributes.
    pub attributes: Vec<Attribute>,
    /// What the reader left out or read unusually, for the loader's
    /// warnings.
    pub notes: Vec<String>,
}

/// A mesh file that cannot be read.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{file}:{line}: {message}")]
pub struct MeshError {
    pub file: String,
    pub line: usize,
    pub message: String,
}

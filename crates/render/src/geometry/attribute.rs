//! Named per-vertex and per-face data of a mesh, as Mitsuba 3's meshes
//! carry them (`include/mitsuba/render/mesh.h`): a `vertex_*` attribute
//! has one record per vertex, interpolated over a face by barycentric
//! weights; a `face_*` attribute one record per face. A record is `dim`
//! numbers (1 to 4: a weight, an RGB colour, a vector).

use crate::geometry::GeometryError;

#[derive(Debug, Clone, PartialEq)]
pub struct Attribute {
    /// `vertex_…` or `face_…`.
    pub name: String,
    /// Numbers per record.
    pub dim: usize,
    /// `dim` numbers per vertex or per face, record after record.
    pub values: Vec<f32>,
}

impl Attribute {
    /// Whether the records are per face (else per vertex).
    pub fn per_face(&self) -> bool {
        self.name.starts_with("face_")
    }

    /// Checks the name's prefix and that there is one record per vertex
    /// (`vertices`) or per face (`faces`).
    pub fn check(&self, vertices: usize, faces: usize) -> Result<(), GeometryError> {
        if !self.name.starts_with("vertex_") && !self.name.starts_with("face_") {
            return Err(GeometryError::Invalid(format!(
                "attribute '{}': a name must start with 'vertex_' or 'face_'",
                self.name
            )));
        }
        let records = if self.per_face() { faces } else { vertices };
        if !(1..=4).contains(&self.dim) || self.values.len() != self.dim * records {
            return Err(GeometryError::Invalid(format!(
                "attribute '{}': {} numbers are not {records} records of 1 to 4",
                self.name,
                self.values.len()
            )));
        }
        Ok(())
    }
}

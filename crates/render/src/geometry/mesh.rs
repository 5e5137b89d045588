//! Triangle meshes, stored in world space.

use crate::geometry::GeometryError;
use crate::math::{Transform, Vec3};

/// A triangle mesh: world-space positions, optional per-vertex normals and
/// UVs, and vertex-index triples.
#[derive(Debug, Clone, PartialEq)]
pub struct TriangleMesh {
    pub positions: Vec<Vec3>,
    pub normals: Option<Vec<Vec3>>,
    pub uvs: Option<Vec<[f32; 2]>>,
    pub indices: Vec<[u32; 3]>,
}

impl TriangleMesh {
    /// Validates and transforms an object-space mesh to world space. Indices
    /// must be in range and attributes finite, one per vertex.
    pub fn new(
        positions: Vec<Vec3>,
        normals: Option<Vec<Vec3>>,
        uvs: Option<Vec<[f32; 2]>>,
        indices: Vec<[u32; 3]>,
        world_from_object: &Transform,
    ) -> Result<Self, GeometryError> {
        let n = positions.len();
        if let Some(i) = positions.iter().position(|p| !p.is_finite()) {
            return Err(GeometryError::Invalid(format!("vertex {i} is not finite")));
        }
        if let Some((f, tri)) = indices
            .iter()
            .enumerate()
            .find(|(_, t)| t.iter().any(|&i| i as usize >= n))
        {
            return Err(GeometryError::Invalid(format!(
                "face {f} refers to vertex {} but the mesh has {n} vertices",
                tri.iter().max().copied().unwrap_or(0)
            )));
        }
        if normals.as_ref().is_some_and(|v| v.len() != n)
            || uvs.as_ref().is_some_and(|v| v.len() != n)
        {
            return Err(GeometryError::Invalid(
                "normals or UVs are not one per vertex".into(),
            ));
        }
        if normals
            .as_ref()
            .is_some_and(|v| v.iter().any(|p| !p.is_finite()))
        {
            return Err(GeometryError::Invalid(
                "a vertex normal is not finite".into(),
            ));
        }
        // Normals transform as normals (as in Mitsuba); zero-length ones are
        // dropped at use in favour of the geometric normal.
        let positions = positions
            .into_iter()
            .map(|p| world_from_object.point(p))
            .collect();
        let normals = normals.map(|v| v.into_iter().map(|n| world_from_object.normal(n)).collect());
        Ok(Self {
            positions,
            normals,
            uvs,
            indices,
        })
    }

    #[inline]
    pub fn vertices(&self, face: usize) -> (Vec3, Vec3, Vec3) {
        let [a, b, c] = self.indices[face];
        (
            self.positions[a as usize],
            self.positions[b as usize],
            self.positions[c as usize],
        )
    }

    pub fn triangle_count(&self) -> usize {
        self.indices.len()
    }

    /// Area of face `face`.
    pub fn face_area(&self, face: usize) -> f32 {
        let (a, b, c) = self.vertices(face);
        0.5 * (b - a).cross(c - a).length()
    }
}

/// ∂p/∂u and ∂p/∂v over the triangle `p` with texture coordinates `t`
/// (solving the 2×2 system of its two edges, as Mitsuba's mesh does); an
/// arbitrary tangent pair of the face when its coordinates are degenerate.
pub(super) fn uv_derivatives(p: [Vec3; 3], t: [[f32; 2]; 3]) -> (Vec3, Vec3) {
    let (dp0, dp1) = (p[1] - p[0], p[2] - p[0]);
    let (du0, dv0) = (t[1][0] - t[0][0], t[1][1] - t[0][1]);
    let (du1, dv1) = (t[2][0] - t[0][0], t[2][1] - t[0][1]);
    let det = du0 * dv1 - dv0 * du1;
    let dpdu = (dp0 * dv1 - dp1 * dv0) / det;
    let dpdv = (dp1 * du0 - dp0 * du1) / det;
    if det != 0.0 && dpdu.is_finite() && dpdv.is_finite() {
        (dpdu, dpdv)
    } else {
        let f = crate::math::Frame::from_normal(dp0.cross(dp1).normalize());
        (f.s, f.t)
    }
}

//! Triangle meshes, stored in world space.

use crate::geometry::{Attribute, GeometryError};
use crate::math::{Transform, Vec3};

/// A triangle mesh: world-space positions, optional per-vertex normals and
/// UVs, vertex-index triples, and named attributes (what `mesh_attribute`
/// textures read).
#[derive(Debug, Clone, PartialEq)]
pub struct TriangleMesh {
    pub positions: Vec<Vec3>,
    pub normals: Option<Vec<Vec3>>,
    pub uvs: Option<Vec<[f32; 2]>>,
    pub indices: Vec<[u32; 3]>,
    pub attributes: Vec<Attribute>,
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
            attributes: Vec::new(),
        })
    }

    /// Adds named attributes, each checked to have one record per vertex
    /// or per face.
    pub fn with_attributes(mut self, attributes: Vec<Attribute>) -> Result<Self, GeometryError> {
        for a in &attributes {
            a.check(self.positions.len(), self.indices.len())?;
        }
        self.attributes = attributes;
        Ok(self)
    }

    /// The attribute called `name`.
    pub fn attribute(&self, name: &str) -> Option<&Attribute> {
        self.attributes.iter().find(|a| a.name == name)
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

    /// Texture coordinates at barycentrics (b1, b2) of `face`: the vertex
    /// UVs interpolated, or (b1, b2) themselves when the mesh has none (as
    /// Mitsuba). Hits and area samples both read them here.
    #[inline]
    pub fn uv_at(&self, face: usize, b1: f32, b2: f32) -> [f32; 2] {
        let b0 = 1.0 - b1 - b2;
        self.uvs.as_ref().map_or([b1, b2], |t| {
            let [ia, ib, ic] = self.indices[face].map(|i| i as usize);
            std::array::from_fn(|k| t[ia][k] * b0 + t[ib][k] * b1 + t[ic][k] * b2)
        })
    }

    /// Replaces the vertex normals by smooth ones computed from the
    /// world-space faces, as Mitsuba 3 computes them when a mesh has none:
    /// each face adds its unit normal to its three corners, weighted by the
    /// corner's interior angle (Thürmer & Wüthrich 1998, "Computing Vertex
    /// Normals from Polygonal Facets", JGT 3(1)). `point_of_vertex` groups
    /// vertices that are one surface point (an OBJ `v` split by its texture
    /// coordinates), so they share one normal; `None`: each vertex alone.
    /// Degenerate faces add nothing; a point with no contribution gets a
    /// zero normal (the geometric normal is used there).
    pub fn compute_smooth_normals(&mut self, point_of_vertex: Option<&[u32]>) {
        // A map of the wrong length is ignored.
        let point_of_vertex = point_of_vertex.filter(|m| m.len() == self.positions.len());
        let point = |v: u32| point_of_vertex.map_or(v as usize, |m| m[v as usize] as usize);
        let points = point_of_vertex.map_or(self.positions.len(), |m| {
            m.iter().map(|&p| p as usize + 1).max().unwrap_or(0)
        });
        let mut sum = vec![[0.0f64; 3]; points];
        for tri in &self.indices {
            let p = tri.map(|i| self.positions[i as usize]);
            let n = (p[1] - p[0]).cross(p[2] - p[0]).normalize();
            if !n.is_finite() {
                continue;
            }
            for k in 0..3 {
                let a = (p[(k + 1) % 3] - p[k]).normalize();
                let b = (p[(k + 2) % 3] - p[k]).normalize();
                let angle = unit_angle(a, b) as f64;
                let s = &mut sum[point(tri[k])];
                s[0] += n.x as f64 * angle;
                s[1] += n.y as f64 * angle;
                s[2] += n.z as f64 * angle;
            }
        }
        let normals = (0..self.positions.len() as u32)
            .map(|v| {
                let [x, y, z] = sum[point(v)];
                let len = (x * x + y * y + z * z).sqrt();
                if len > 0.0 && len.is_finite() {
                    Vec3::new((x / len) as f32, (y / len) as f32, (z / len) as f32)
                } else {
                    Vec3::ZERO
                }
            })
            .collect();
        self.normals = Some(normals);
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

/// The angle between unit vectors, accurate near 0 and π (the chord
/// formula; asin of half the chord rather than acos of the dot product).
fn unit_angle(a: Vec3, b: Vec3) -> f32 {
    if a.dot(b) < 0.0 {
        std::f32::consts::PI - 2.0 * ((a + b).length() * 0.5).min(1.0).asin()
    } else {
        2.0 * ((b - a).length() * 0.5).min(1.0).asin()
    }
}

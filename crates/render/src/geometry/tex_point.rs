//! Where a texture is looked up: the hit's texture coordinates and, for
//! textures that read a mesh's own attributes (`mesh_attribute`), the
//! triangle and the barycentric weights on it.

/// A texture lookup point. A bare `[f32; 2]` of texture coordinates
/// converts to one with triangle 0 at its first vertex.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct TexPoint {
    pub uv: [f32; 2],
    /// The triangle's index in its mesh (0 on other shapes).
    pub prim: u32,
    /// The weights of the triangle's second and third vertices (the
    /// first has 1 − b₁ − b₂); zero on other shapes.
    pub bary: [f32; 2],
}

impl From<[f32; 2]> for TexPoint {
    #[inline]
    fn from(uv: [f32; 2]) -> Self {
        Self {
            uv,
            prim: 0,
            bary: [0.0, 0.0],
        }
    }
}

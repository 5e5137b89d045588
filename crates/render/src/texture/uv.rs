//! Mitsuba's `to_uv`: an affine map of texture coordinates.

/// (u, v) ↦ (a·u + b·v + c, d·u + e·v + f), the upper 2×3 block of a 3×3
/// (or the x, y rows and translation of a 4×4) transform.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UvTransform(pub [f32; 6]);

impl Default for UvTransform {
    fn default() -> Self {
        UvTransform([1.0, 0.0, 0.0, 0.0, 1.0, 0.0])
    }
}

impl UvTransform {
    #[inline]
    pub fn apply(&self, [u, v]: [f32; 2]) -> [f32; 2] {
        let m = &self.0;
        [m[0] * u + m[1] * v + m[2], m[3] * u + m[4] * v + m[5]]
    }
}

//! Mitsuba 3's `checkerboard`: `color0` where the fractional parts of u and
//! v lie in the same half of [0, 1), `color1` elsewhere.

use super::{Texture, UvTransform};

#[derive(Debug, Clone, PartialEq)]
pub struct Checkerboard {
    pub color0: Texture,
    pub color1: Texture,
    pub to_uv: UvTransform,
}

impl Checkerboard {
    /// Whether `uv` falls on a `color0` square.
    #[inline]
    pub fn first_at(&self, uv: [f32; 2]) -> bool {
        same_halves(&self.to_uv, uv)
    }
}

/// Whether the fractional parts of the transformed u and v lie in the same
/// half of [0, 1): the squares of Mitsuba's checkerboard.
#[inline]
pub(crate) fn same_halves(to_uv: &UvTransform, uv: [f32; 2]) -> bool {
    let [u, v] = to_uv.apply(uv);
    (u - u.floor() > 0.5) == (v - v.floor() > 0.5)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn squares_alternate() {
        let c = Checkerboard {
            color0: Texture::constant(0.4),
            color1: Texture::constant(0.2),
            to_uv: UvTransform([4.0, 0.0, 0.0, 0.0, 4.0, 0.0]),
        };
        // Four squares per unit: (0.1, 0.1) → cell (0, 0), first colour.
        assert!(c.first_at([0.1, 0.1]));
        assert!(!c.first_at([0.2, 0.1]));
        assert!(!c.first_at([0.1, 0.2]));
        assert!(c.first_at([0.2, 0.2]));
        // Negative coordinates tile the same way.
        assert!(c.first_at([-0.9, -0.9]));
        assert!((Texture::Checkerboard(c.into()).mean() - 0.3).abs() < 1e-6);
    }
}

//! From X, Y, Z, V′ to receptor signals: the cone matrix (Hunt–Pointer–
//! Estévez), its inverse, and the opponent channels' share of the rods.

use scotopia_color::space::Cat;
use scotopia_color::{Mat3, RgbSpace};

/// XYZ → LMS (Hunt–Pointer–Estévez rows scaled so D65 gives 1, 1, 1), its
/// inverse, the cones' luminance, and the display cones a unit of rod
/// signal asks for.
pub(super) struct Matrices {
    pub(super) lms: [[f32; 3]; 3],
    pub(super) xyz: [[f32; 3]; 3],
    /// The Y row of LMS → XYZ: the achromatic channel A of the cones.
    pub(super) luminance: [f32; 3],
    /// Rods join the achromatic channel: A += R, C1 and C2 unchanged. Back
    /// through the inverse opponent transform that is the cone signals plus
    /// R times the inverse's first column (the cones of unit A and no
    /// chroma), so the opponent round trip itself is never evaluated.
    pub(super) rod_cones: [f32; 3],
}

impl Matrices {
    pub(super) fn new() -> Self {
        let hpe = Cat::VonKries.matrix();
        let white = hpe.apply(RgbSpace::Srgb.def().white_xyz());
        let lms = Mat3::diagonal(white.map(|w| 1.0 / w)) * hpe;
        let xyz = lms.inverse().expect("the cone matrix is invertible");
        // Opponent channels: A (the cones' luminance), C1 = L − M,
        // C2 = (L + M)/2 − S.
        let opponent = Mat3([xyz.0[1], [1.0, -1.0, 0.0], [0.5, 0.5, -1.0]]);
        let from_opponent = opponent
            .inverse()
            .expect("the opponent matrix is invertible");
        let f32s = |m: Mat3| m.0.map(|row| row.map(|v| v as f32));
        Self {
            lms: f32s(lms),
            xyz: f32s(xyz),
            luminance: xyz.0[1].map(|v| v as f32),
            rod_cones: from_opponent.apply([1.0, 0.0, 0.0]).map(|v| v as f32),
        }
    }
}

/// A pixel's receptor signals [L, M, S, R] through the cone matrix `lms`
/// (non-finite and negative values as 0; selects, so a row vectorises).
#[inline(always)]
pub(super) fn receptors_with(lms: &[[f32; 3]; 3], px: &[f32; 4]) -> [f32; 4] {
    let clean = px.map(|v| {
        let v = if v > 0.0 { v } else { 0.0 };
        if v < f32::INFINITY {
            v
        } else {
            0.0
        }
    });
    let [l, mm, s] = apply(lms, [clean[0], clean[1], clean[2]]);
    [l, mm, s, clean[3]]
}

#[inline(always)]
pub(super) fn apply(m: &[[f32; 3]; 3], v: [f32; 3]) -> [f32; 3] {
    m.map(|row| row[0] * v[0] + row[1] * v[1] + row[2] * v[2])
}

#[inline(always)]
pub(super) fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

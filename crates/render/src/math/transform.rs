//! Affine transforms as 4×4 matrices with their inverse, named
//! destination-from-source (`world_from_object`).

use super::Vec3;

/// A row-major 4×4 matrix.
pub type Mat4 = [[f64; 4]; 4];

/// An invertible affine (or projective) transform and its inverse.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Transform {
    m: Mat4,
    inv: Mat4,
}

const IDENTITY: Mat4 = [
    [1.0, 0.0, 0.0, 0.0],
    [0.0, 1.0, 0.0, 0.0],
    [0.0, 0.0, 1.0, 0.0],
    [0.0, 0.0, 0.0, 1.0],
];

fn mul(a: &Mat4, b: &Mat4) -> Mat4 {
    std::array::from_fn(|r| std::array::from_fn(|c| (0..4).map(|k| a[r][k] * b[k][c]).sum()))
}

/// Inverse by Gauss–Jordan elimination with partial pivoting; `None` when
/// singular (relative to the matrix's scale).
pub fn invert(m: &Mat4) -> Option<Mat4> {
    let max_abs = |v: &mut dyn Iterator<Item = f64>| v.fold(0.0f64, |s, v| s.max(v.abs()));
    if !max_abs(&mut m.iter().flatten().copied()).is_finite() {
        return None;
    }
    // Singular relative to the linear part's own scale (and the last
    // pivot to the bottom row's), not to the translation's: a scene
    // scaled by 10⁻¹² or placed at 10¹⁴ is not degenerate.
    let linear = max_abs(&mut m.iter().flat_map(|r| r[..3].iter().copied()));
    let bottom = max_abs(&mut m[3].iter().copied());
    if !(linear > 0.0 && bottom > 0.0) {
        return None;
    }
    let mut a = *m;
    let mut inv = IDENTITY;
    for col in 0..4 {
        let pivot = (col..4).max_by(|&i, &j| a[i][col].abs().total_cmp(&a[j][col].abs()))?;
        let scale = if col < 3 { linear } else { bottom };
        if a[pivot][col].abs() <= 1e-12 * scale {
            return None;
        }
        a.swap(col, pivot);
        inv.swap(col, pivot);
        let p = a[col][col];
        for k in 0..4 {
            a[col][k] /= p;
            inv[col][k] /= p;
        }
        for r in 0..4 {
            if r != col {
                let f = a[r][col];
                for k in 0..4 {
                    a[r][k] -= f * a[col][k];
                    inv[r][k] -= f * inv[col][k];
                }
            }
        }
    }
    Some(inv)
}

impl Default for Transform {
    fn default() -> Self {
        Self::IDENTITY
    }
}

impl Transform {
    pub const IDENTITY: Transform = Transform {
        m: IDENTITY,
        inv: IDENTITY,
    };

    /// The transform of matrix `m`; `None` when `m` is singular (a degenerate
    /// transform, such as a zero scale) or not finite.
    pub fn from_matrix(m: Mat4) -> Option<Self> {
        invert(&m).map(|inv| Self { m, inv })
    }

    pub fn matrix(&self) -> &Mat4 {
        &self.m
    }

    pub fn inverse(&self) -> Self {
        Self {
            m: self.inv,
            inv: self.m,
        }
    }

    pub fn translate(v: Vec3) -> Self {
        let (x, y, z) = (v.x as f64, v.y as f64, v.z as f64);
        let mut m = IDENTITY;
        let mut inv = IDENTITY;
        m[0][3] = x;
        m[1][3] = y;
        m[2][3] = z;
        inv[0][3] = -x;
        inv[1][3] = -y;
        inv[2][3] = -z;
        Self { m, inv }
    }

    /// Non-uniform scale; `None` if a factor is zero.
    pub fn scale(v: Vec3) -> Option<Self> {
        let mut m = IDENTITY;
        m[0][0] = v.x as f64;
        m[1][1] = v.y as f64;
        m[2][2] = v.z as f64;
        Self::from_matrix(m)
    }

    /// Rotation by `degrees` about `axis` (right-handed, as Mitsuba).
    pub fn rotate(axis: Vec3, degrees: f32) -> Option<Self> {
        let a = axis.normalize();
        if !a.is_finite() {
            return None;
        }
        let (s, c) = (degrees as f64).to_radians().sin_cos();
        let (x, y, z) = (a.x as f64, a.y as f64, a.z as f64);
        let t = 1.0 - c;
        let m = [
            [t * x * x + c, t * x * y - s * z, t * x * z + s * y, 0.0],
            [t * x * y + s * z, t * y * y + c, t * y * z - s * x, 0.0],
            [t * x * z - s * y, t * y * z + s * x, t * z * z + c, 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ];
        Self::from_matrix(m)
    }

    /// Camera-to-world for a camera at `origin` looking at `target` with
    /// `up` (Mitsuba's `lookat`: +z forward, +x left, +y up in camera space).
    pub fn look_at(origin: Vec3, target: Vec3, up: Vec3) -> Option<Self> {
        let dir = (target - origin).normalize();
        let left = up.normalize().cross(dir).normalize();
        let new_up = dir.cross(left);
        if !(dir.is_finite() && left.is_finite()) {
            return None;
        }
        let col = |v: Vec3| [v.x as f64, v.y as f64, v.z as f64];
        let (l, u, d, o) = (col(left), col(new_up), col(dir), col(origin));
        let m = [
            [l[0], u[0], d[0], o[0]],
            [l[1], u[1], d[1], o[1]],
            [l[2], u[2], d[2], o[2]],
            [0.0, 0.0, 0.0, 1.0],
        ];
        Self::from_matrix(m)
    }

    /// `self ∘ other`: apply `other` first.
    pub fn then_after(&self, other: &Transform) -> Self {
        Self {
            m: mul(&self.m, &other.m),
            inv: mul(&other.inv, &self.inv),
        }
    }

    #[inline]
    pub fn point(&self, p: Vec3) -> Vec3 {
        let m = &self.m;
        let (x, y, z) = (p.x as f64, p.y as f64, p.z as f64);
        let r = |i: usize| m[i][0] * x + m[i][1] * y + m[i][2] * z + m[i][3];
        // Affine (every placement): no divide. Compared element by element:
        // the array comparison is a call per point.
        if m[3][0] == 0.0 && m[3][1] == 0.0 && m[3][2] == 0.0 && m[3][3] == 1.0 {
            return Vec3::new(r(0) as f32, r(1) as f32, r(2) as f32);
        }
        let w = r(3);
        Vec3::new((r(0) / w) as f32, (r(1) / w) as f32, (r(2) / w) as f32)
    }

    #[inline]
    pub fn vector(&self, v: Vec3) -> Vec3 {
        let m = &self.m;
        let (x, y, z) = (v.x as f64, v.y as f64, v.z as f64);
        let r = |i: usize| (m[i][0] * x + m[i][1] * y + m[i][2] * z) as f32;
        Vec3::new(r(0), r(1), r(2))
    }

    /// Normals transform by the inverse transpose.
    #[inline]
    pub fn normal(&self, n: Vec3) -> Vec3 {
        let m = &self.inv;
        let (x, y, z) = (n.x as f64, n.y as f64, n.z as f64);
        let r = |i: usize| (m[0][i] * x + m[1][i] * y + m[2][i] * z) as f32;
        Vec3::new(r(0), r(1), r(2))
    }

    /// Whether the transform flips handedness (negative determinant).
    pub fn swaps_handedness(&self) -> bool {
        let m = &self.m;
        let det = m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0]);
        det < 0.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: Vec3, b: Vec3) -> bool {
        (a - b).length() < 1e-5
    }

    #[test]
    fn compose_invert_and_apply() {
        let t = Transform::translate(Vec3::new(1.0, 2.0, 3.0))
            .then_after(&Transform::rotate(Vec3::new(0.0, 0.0, 1.0), 90.0).unwrap())
            .then_after(&Transform::scale(Vec3::new(2.0, 2.0, 2.0)).unwrap());
        // Scale, then rotate 90° about z, then translate.
        assert!(close(
            t.point(Vec3::new(1.0, 0.0, 0.0)),
            Vec3::new(1.0, 4.0, 3.0)
        ));
        assert!(close(
            t.inverse().point(t.point(Vec3::new(0.3, -0.7, 2.0))),
            Vec3::new(0.3, -0.7, 2.0)
        ));
        assert!(close(
            t.vector(Vec3::new(1.0, 0.0, 0.0)),
            Vec3::new(0.0, 2.0, 0.0)
        ));
        // A normal stays perpendicular to a transformed tangent.
        let s = Transform::scale(Vec3::new(1.0, 4.0, 1.0)).unwrap();
        let (tangent, n) = (Vec3::new(1.0, 1.0, 0.0), Vec3::new(1.0, -1.0, 0.0));
        assert!(s.vector(tangent).dot(s.normal(n)).abs() < 1e-6);
        assert!(!t.swaps_handedness());
        assert!(Transform::scale(Vec3::new(-1.0, 1.0, 1.0))
            .unwrap()
            .swaps_handedness());
    }

    #[test]
    fn degenerate_transforms_are_refused() {
        assert!(Transform::scale(Vec3::new(1.0, 0.0, 1.0)).is_none());
        assert!(Transform::rotate(Vec3::ZERO, 30.0).is_none());
        let same = Vec3::new(1.0, 1.0, 1.0);
        assert!(Transform::look_at(same, same, Vec3::new(0.0, 1.0, 0.0)).is_none());
        assert!(Transform::look_at(
            Vec3::ZERO,
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0)
        )
        .is_none());
        assert!(Transform::from_matrix([[f64::NAN; 4]; 4]).is_none());
    }

    #[test]
    fn far_placements_and_tiny_scales_are_not_singular() {
        let far = Vec3::new(0.0, 0.0, 3e14);
        assert!(Transform::look_at(far, Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0)).is_some());
        assert!(Transform::scale(Vec3::new(1e-12, 1e-12, 1e-12)).is_some());
        assert!(Transform::scale(Vec3::new(1.0, 1.0, 0.0)).is_none());
    }

    #[test]
    fn look_at_is_mitsuba_s() {
        let t = Transform::look_at(
            Vec3::ZERO,
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(0.0, 1.0, 0.0),
        )
        .unwrap();
        // Camera +z is the view direction, +y is up, +x is left (−x of the view is right).
        assert!(close(
            t.vector(Vec3::new(0.0, 0.0, 1.0)),
            Vec3::new(0.0, 0.0, -1.0)
        ));
        assert!(close(
            t.vector(Vec3::new(0.0, 1.0, 0.0)),
            Vec3::new(0.0, 1.0, 0.0)
        ));
        assert!(close(
            t.vector(Vec3::new(1.0, 0.0, 0.0)),
            Vec3::new(-1.0, 0.0, 0.0)
        ));
    }
}

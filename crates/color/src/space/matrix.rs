//! 3×3 matrices for colour-space and adaptation transforms.

use std::ops::Mul;

/// A row-major 3×3 matrix of f64.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mat3(pub [[f64; 3]; 3]);

impl Mat3 {
    pub const IDENTITY: Mat3 = Mat3([[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]]);

    pub fn diagonal(d: [f64; 3]) -> Self {
        Mat3([[d[0], 0.0, 0.0], [0.0, d[1], 0.0], [0.0, 0.0, d[2]]])
    }

    /// The matrix whose columns are `c`.
    pub fn from_columns(c: [[f64; 3]; 3]) -> Self {
        Mat3(std::array::from_fn(|r| std::array::from_fn(|k| c[k][r])))
    }

    pub fn determinant(&self) -> f64 {
        let m = &self.0;
        m[0][0] * (m[1][1] * m[2][2] - m[1][2] * m[2][1])
            - m[0][1] * (m[1][0] * m[2][2] - m[1][2] * m[2][0])
            + m[0][2] * (m[1][0] * m[2][1] - m[1][1] * m[2][0])
    }

    /// The inverse by cofactors; `None` when singular.
    pub fn inverse(&self) -> Option<Self> {
        let det = self.determinant();
        if det.abs() < 1e-300 {
            return None;
        }
        let m = &self.0;
        let cof = |r0: usize, r1: usize, c0: usize, c1: usize| {
            m[r0][c0] * m[r1][c1] - m[r0][c1] * m[r1][c0]
        };
        Some(Mat3([
            [
                cof(1, 2, 1, 2) / det,
                -cof(0, 2, 1, 2) / det,
                cof(0, 1, 1, 2) / det,
            ],
            [
                -cof(1, 2, 0, 2) / det,
                cof(0, 2, 0, 2) / det,
                -cof(0, 1, 0, 2) / det,
            ],
            [
                cof(1, 2, 0, 1) / det,
                -cof(0, 2, 0, 1) / det,
                cof(0, 1, 0, 1) / det,
            ],
        ]))
    }

    #[inline]
    pub fn apply(&self, v: [f64; 3]) -> [f64; 3] {
        let m = &self.0;
        std::array::from_fn(|r| m[r][0] * v[0] + m[r][1] * v[1] + m[r][2] * v[2])
    }
}

impl Mul for Mat3 {
    type Output = Mat3;
    fn mul(self, rhs: Mat3) -> Mat3 {
        Mat3(std::array::from_fn(|r| {
            std::array::from_fn(|c| (0..3).map(|k| self.0[r][k] * rhs.0[k][c]).sum())
        }))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn inverse_round_trips() {
        let m = Mat3([[2.0, 1.0, 0.5], [0.1, 3.0, -1.0], [0.0, 0.2, 1.5]]);
        let p = m * m.inverse().unwrap();
        for r in 0..3 {
            for c in 0..3 {
                let e = if r == c { 1.0 } else { 0.0 };
                assert!((p.0[r][c] - e).abs() < 1e-12);
            }
        }
        assert!(Mat3([[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]])
            .inverse()
            .is_none());
    }
}

//! Orthonormal frames around a normal, for BSDF-local directions (z = n).

use super::Vec3;

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Frame {
    pub s: Vec3,
    pub t: Vec3,
    pub n: Vec3,
}

impl Frame {
    /// A frame with `n` (unit) as z: Duff et al. 2017, "Building an
    /// Orthonormal Basis, Revisited" (JCGT 6(1)), listing 3 — branchless and
    /// continuous except at the sign flip of n.z.
    #[inline]
    pub fn from_normal(n: Vec3) -> Self {
        let sign = 1.0f32.copysign(n.z);
        let a = -1.0 / (sign + n.z);
        let b = n.x * n.y * a;
        Self {
            s: Vec3::new(1.0 + sign * n.x * n.x * a, sign * b, -sign * n.x),
            t: Vec3::new(b, sign + n.y * n.y * a, -n.y),
            n,
        }
    }

    /// A frame with `n` (unit) as z and its x axis along `tangent`'s part
    /// perpendicular to `n` (Gram–Schmidt, as Mitsuba orients a shading
    /// frame by ∂p/∂u); [`Frame::from_normal`] when that part vanishes.
    #[inline]
    pub fn from_normal_tangent(n: Vec3, tangent: Vec3) -> Self {
        let s = tangent - n * n.dot(tangent);
        let len2 = s.length_squared();
        if !(len2 > 1e-12 * tangent.length_squared() && len2.is_finite()) {
            return Self::from_normal(n);
        }
        let s = s / len2.sqrt();
        Self {
            s,
            t: n.cross(s),
            n,
        }
    }

    #[inline]
    pub fn to_local(&self, v: Vec3) -> Vec3 {
        Vec3::new(v.dot(self.s), v.dot(self.t), v.dot(self.n))
    }

    #[inline]
    pub fn to_world(&self, v: Vec3) -> Vec3 {
        self.s * v.x + self.t * v.y + self.n * v.z
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn orthonormal_for_all_normals() {
        for n in [
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.0, 0.0, -1.0),
            Vec3::new(0.3, -0.4, 0.866).normalize(),
            Vec3::new(1.0, 0.0, -1e-8).normalize(),
        ] {
            let f = Frame::from_normal(n);
            assert!(
                f.s.dot(f.t).abs() < 1e-6 && f.s.dot(n).abs() < 1e-6 && f.t.dot(n).abs() < 1e-6
            );
            assert!((f.s.length() - 1.0).abs() < 1e-6 && (f.t.length() - 1.0).abs() < 1e-6);
            assert!((f.s.cross(f.t) - n).length() < 1e-5, "right-handed");
            let v = Vec3::new(0.2, 0.5, -0.3);
            assert!((f.to_world(f.to_local(v)) - v).length() < 1e-6);
        }
    }

    #[test]
    fn a_tangent_orients_the_frame() {
        let n = Vec3::new(0.3, -0.4, 0.866).normalize();
        let tangent = Vec3::new(2.0, 0.5, 0.0);
        let f = Frame::from_normal_tangent(n, tangent);
        assert!(f.s.dot(n).abs() < 1e-6 && (f.s.length() - 1.0).abs() < 1e-6);
        assert!((f.s.cross(f.t) - n).length() < 1e-5, "right-handed");
        // s is the tangent with its normal part removed, in its direction.
        let want = (tangent - n * n.dot(tangent)).normalize();
        assert!((f.s - want).length() < 1e-6);
        // A tangent along the normal (or zero) falls back to any frame.
        assert_eq!(
            Frame::from_normal_tangent(n, n * 3.0),
            Frame::from_normal(n)
        );
        assert_eq!(
            Frame::from_normal_tangent(n, Vec3::ZERO),
            Frame::from_normal(n)
        );
    }
}

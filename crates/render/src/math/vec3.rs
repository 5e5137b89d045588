//! Three-component f32 vectors for points, directions and normals.

use std::ops::{Add, AddAssign, Div, Index, Mul, MulAssign, Neg, Sub, SubAssign};

/// A 3-vector. Points, directions and normals share the type; transforms
/// name which they apply (`Transform::point`, `vector`, `normal`).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Vec3 {
    pub x: f32,
    pub y: f32,
    pub z: f32,
}

impl Vec3 {
    pub const ZERO: Vec3 = Vec3::new(0.0, 0.0, 0.0);

    #[inline]
    pub const fn new(x: f32, y: f32, z: f32) -> Self {
        Self { x, y, z }
    }

    #[inline]
    pub const fn splat(v: f32) -> Self {
        Self::new(v, v, v)
    }

    #[inline]
    pub fn dot(self, o: Self) -> f32 {
        self.x * o.x + self.y * o.y + self.z * o.z
    }

    #[inline]
    pub fn cross(self, o: Self) -> Self {
        Self::new(
            self.y * o.z - self.z * o.y,
            self.z * o.x - self.x * o.z,
            self.x * o.y - self.y * o.x,
        )
    }

    #[inline]
    pub fn length_squared(self) -> f32 {
        self.dot(self)
    }

    /// The length, without overflow or underflow of its square: a vector
    /// of components beyond ~1.8·10¹⁹ (or below ~10⁻¹⁹, as a cross
    /// product of a scene's edges is at scales beyond 10¹⁰ or below 10⁻¹⁰)
    /// is rescaled by its largest component first.
    #[inline]
    pub fn length(self) -> f32 {
        let l2 = self.length_squared();
        if l2.is_finite() && l2 >= f32::MIN_POSITIVE {
            l2.sqrt()
        } else {
            self.length_rescaled()
        }
    }

    #[cold]
    fn length_rescaled(self) -> f32 {
        let m = self.abs().max_component();
        if m == 0.0 || !m.is_finite() {
            return self.length_squared().sqrt();
        }
        m * (self / m).length_squared().sqrt()
    }

    /// The unit vector in this direction (NaN for the zero vector).
    #[inline]
    pub fn normalize(self) -> Self {
        self / self.length()
    }

    #[inline]
    pub fn abs(self) -> Self {
        Self::new(self.x.abs(), self.y.abs(), self.z.abs())
    }

    #[inline]
    pub fn min(self, o: Self) -> Self {
        Self::new(self.x.min(o.x), self.y.min(o.y), self.z.min(o.z))
    }

    #[inline]
    pub fn max(self, o: Self) -> Self {
        Self::new(self.x.max(o.x), self.y.max(o.y), self.z.max(o.z))
    }

    #[inline]
    pub fn max_component(self) -> f32 {
        self.x.max(self.y).max(self.z)
    }

    /// Index of the largest component.
    #[inline]
    pub fn max_dimension(self) -> usize {
        if self.x > self.y {
            if self.x > self.z {
                0
            } else {
                2
            }
        } else if self.y > self.z {
            1
        } else {
            2
        }
    }

    /// Component-wise product.
    #[inline]
    pub fn mul_elem(self, o: Self) -> Self {
        Self::new(self.x * o.x, self.y * o.y, self.z * o.z)
    }

    #[inline]
    pub fn is_finite(self) -> bool {
        self.x.is_finite() && self.y.is_finite() && self.z.is_finite()
    }

    #[inline]
    pub fn to_array(self) -> [f32; 3] {
        [self.x, self.y, self.z]
    }
}

impl From<[f32; 3]> for Vec3 {
    #[inline]
    fn from(a: [f32; 3]) -> Self {
        Self::new(a[0], a[1], a[2])
    }
}

impl Index<usize> for Vec3 {
    type Output = f32;
    #[inline]
    fn index(&self, i: usize) -> &f32 {
        match i {
            0 => &self.x,
            1 => &self.y,
            _ => &self.z,
        }
    }
}

impl Neg for Vec3 {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        Self::new(-self.x, -self.y, -self.z)
    }
}

impl Add for Vec3 {
    type Output = Self;
    #[inline]
    fn add(self, o: Self) -> Self {
        Self::new(self.x + o.x, self.y + o.y, self.z + o.z)
    }
}

impl AddAssign for Vec3 {
    #[inline]
    fn add_assign(&mut self, o: Self) {
        *self = *self + o;
    }
}

impl Sub for Vec3 {
    type Output = Self;
    #[inline]
    fn sub(self, o: Self) -> Self {
        Self::new(self.x - o.x, self.y - o.y, self.z - o.z)
    }
}

impl SubAssign for Vec3 {
    #[inline]
    fn sub_assign(&mut self, o: Self) {
        *self = *self - o;
    }
}

impl Mul<f32> for Vec3 {
    type Output = Self;
    #[inline]
    fn mul(self, s: f32) -> Self {
        Self::new(self.x * s, self.y * s, self.z * s)
    }
}

impl Mul<Vec3> for f32 {
    type Output = Vec3;
    #[inline]
    fn mul(self, v: Vec3) -> Vec3 {
        v * self
    }
}

impl MulAssign<f32> for Vec3 {
    #[inline]
    fn mul_assign(&mut self, s: f32) {
        *self = *self * s;
    }
}

impl Div<f32> for Vec3 {
    type Output = Self;
    #[inline]
    fn div(self, s: f32) -> Self {
        self * (1.0 / s)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn length_neither_overflows_nor_underflows() {
        for s in [1e-30f32, 1e-20, 1.0, 1e20, 1e30] {
            let v = Vec3::new(3.0 * s, 4.0 * s, 0.0);
            assert!(
                (v.length() / (5.0 * s) - 1.0).abs() < 1e-6,
                "{s:e}: {}",
                v.length()
            );
            assert!((v.normalize().length() - 1.0).abs() < 1e-6, "{s:e}");
        }
        assert_eq!(Vec3::ZERO.length(), 0.0);
        assert!(Vec3::new(f32::INFINITY, 0.0, 0.0).length().is_infinite());
    }

    #[test]
    fn products() {
        let (a, b) = (Vec3::new(1.0, 2.0, 3.0), Vec3::new(-2.0, 0.5, 4.0));
        assert_eq!(a.dot(b), 11.0);
        let c = a.cross(b);
        assert!(c.dot(a).abs() < 1e-6 && c.dot(b).abs() < 1e-6);
        assert_eq!(Vec3::new(0.1, -5.0, 2.0).abs().max_dimension(), 1);
        assert!((a.normalize().length() - 1.0).abs() < 1e-6);
    }
}

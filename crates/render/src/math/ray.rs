//! Rays, and moving a ray's origin off the surface it leaves.

use super::Vec3;

/// A ray o + t·d for t in (0, t_max).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ray {
    pub o: Vec3,
    pub d: Vec3,
    pub t_max: f32,
}

impl Ray {
    #[inline]
    pub fn new(o: Vec3, d: Vec3) -> Self {
        Self {
            o,
            d,
            t_max: f32::INFINITY,
        }
    }

    #[inline]
    pub fn at(&self, t: f32) -> Vec3 {
        self.o + self.d * t
    }
}

/// Moves a surface point `p` off its surface along the geometric normal `n`
/// (pointing to the side the new ray leaves on), far enough that the ray
/// cannot hit the surface it starts on: Wächter & Binder 2019, "A Fast and
/// Robust Method for Avoiding Self-Intersection" (Ray Tracing Gems, ch. 6).
/// The offset is a fixed number of ULPs of p, so it scales with p's
/// magnitude, with an absolute offset near the origin where ULPs vanish.
/// Their constants are for a scene of unit size; `unit` (the scene's size,
/// at most 1: [`crate::accel::Aggregate::offset_unit`]) scales the
/// absolute offset and the region it applies in, so a scene of 10⁻⁶ m is
/// not offset by more than its own size.
#[inline]
pub fn offset_ray_origin(p: Vec3, n: Vec3, unit: f32) -> Vec3 {
    // Constants of Wächter & Binder 2019, listing 6-1.
    let origin = unit / 32.0;
    let float_scale = unit / 65536.0;
    const INT_SCALE: f32 = 256.0;
    let offset = |p: f32, n: f32| {
        let of_i = (INT_SCALE * n) as i32;
        let bits = p.to_bits() as i32;
        let moved = f32::from_bits((if p < 0.0 { bits - of_i } else { bits + of_i }) as u32);
        if p.abs() < origin {
            p + float_scale * n
        } else {
            moved
        }
    };
    Vec3::new(offset(p.x, n.x), offset(p.y, n.y), offset(p.z, n.z))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn offset_moves_to_the_normal_side() {
        for p in [
            Vec3::new(1000.0, -3.0, 0.001),
            Vec3::new(-0.5, 1e5, 7.0),
            Vec3::ZERO,
        ] {
            let n = Vec3::new(0.3, -0.8, 0.52).normalize();
            let q = offset_ray_origin(p, n, 1.0);
            assert!((q - p).dot(n) > 0.0, "{p:?} → {q:?}");
            assert!((q - p).length() < 1e-3 * p.length().max(1.0));
        }
    }
}

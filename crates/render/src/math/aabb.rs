//! Axis-aligned bounding boxes.

use super::{Ray, Vec3};

/// γ₃ = 3u/(1 − 3u), u the unit roundoff (pbrt-v4 §6.8.1): the relative
/// error bound of the slab distances.
pub(crate) const GAMMA3: f32 = 3.0 * (f32::EPSILON * 0.5) / (1.0 - 3.0 * (f32::EPSILON * 0.5));

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Aabb {
    pub min: Vec3,
    pub max: Vec3,
}

impl Aabb {
    /// The empty box (union identity).
    pub const EMPTY: Aabb = Aabb {
        min: Vec3::splat(f32::INFINITY),
        max: Vec3::splat(f32::NEG_INFINITY),
    };

    #[inline]
    pub fn from_points(points: &[Vec3]) -> Self {
        points.iter().fold(Self::EMPTY, |b, &p| b.grow(p))
    }

    #[inline]
    pub fn grow(self, p: Vec3) -> Self {
        Self {
            min: self.min.min(p),
            max: self.max.max(p),
        }
    }

    #[inline]
    pub fn union(self, o: Self) -> Self {
        Self {
            min: self.min.min(o.min),
            max: self.max.max(o.max),
        }
    }

    #[inline]
    pub fn is_empty(&self) -> bool {
        !(self.min.x <= self.max.x && self.min.y <= self.max.y && self.min.z <= self.max.z)
    }

    #[inline]
    pub fn centroid(&self) -> Vec3 {
        (self.min + self.max) * 0.5
    }

    #[inline]
    pub fn extent(&self) -> Vec3 {
        self.max - self.min
    }

    /// Surface area; 0 for an empty box.
    #[inline]
    pub fn area(&self) -> f32 {
        if self.is_empty() {
            return 0.0;
        }
        let e = self.extent();
        2.0 * (e.x * e.y + e.y * e.z + e.z * e.x)
    }

    /// Slab test: whether the ray meets the box within (0, t_max). `inv_d`
    /// is 1/d per component. Robust to ±∞ in `inv_d` and scaled by
    /// 1 + 2γ₃ so grazing hits are not lost to rounding (pbrt-v4 §6.1.2).
    /// The near plane of each slab is chosen by the direction's sign, not
    /// by comparing distances, so the test is branch-free (the BVH's
    /// node tests are the same, per lane). A NaN distance (0·∞, when
    /// the origin lies on a slab plane) leaves the bound as it was.
    #[inline]
    pub fn hit(&self, ray: &Ray, inv_d: Vec3, t_max: f32) -> bool {
        let neg = [inv_d.x < 0.0, inv_d.y < 0.0, inv_d.z < 0.0];
        let o = ray.o;
        let pick = |a: usize, far: bool| {
            if neg[a] != far {
                self.max[a]
            } else {
                self.min[a]
            }
        };
        let near = |a: usize| (pick(a, false) - o[a]) * inv_d[a];
        let far = |a: usize| (pick(a, true) - o[a]) * inv_d[a] * (1.0 + 2.0 * GAMMA3);
        // Return b when a is NaN (and compile to one maxss/minss, unlike
        // f32::max, which also checks b).
        let max = |a: f32, b: f32| if a > b { a } else { b };
        let min = |a: f32, b: f32| if a < b { a } else { b };
        let t0 = max(near(0), max(near(1), max(near(2), 0.0)));
        let t1 = min(far(0), min(far(1), min(far(2), t_max)));
        t0 <= t1
    }
}

//! A leaf's triangles, and its planar shapes, in structure-of-arrays form:
//! each coordinate of the leaf's n primitives in an array of n floats, the
//! arrays one after the other, with no padding. A wide test loads a
//! register of lanes from each array; lanes past n read the next array
//! (or the padding at the end of all leaves) and are masked off. A leaf
//! of up to 16 triangles is one step at AVX-512, two at AVX2.
//!
//! The wide test is a filter: it finds the lanes the scalar test could
//! accept, computing every value the scalar test computes with the same
//! f32 operations in the same order (no fused multiply-adds), so it never
//! rejects a lane the scalar test accepts; lanes where the scalar test
//! would leave f32 (an edge function of exactly 0, a scaled distance
//! beyond f32's normal range) are always kept. The scalar test then runs
//! on the kept lanes in order, which makes the closest hit (t and
//! primitive) exactly the scalar traversal's.

use crate::geometry::{intersect_triangle, PlaneTest, RayShear};
use crate::math::{Ray, Vec3};
use crate::simd::Wide;

/// Most primitives a leaf holds (outside brute-force leaves).
pub(super) const BLOCK: usize = 16;

/// Floats after the last leaf, so a register loaded at any leaf's last
/// lane stays in bounds.
pub(super) const PAD: usize = 16;

/// Bits of lanes 0 … n − 1 (all 32 from n = 32 on).
#[inline(always)]
pub(super) fn lanes(n: usize) -> u32 {
    if n >= 32 {
        u32::MAX
    } else {
        (1u32 << n) - 1
    }
}

/// Floats per triangle: 3 vertices × 3 axes.
pub(super) const TRI_FLOATS: usize = 9;

/// Appends the arrays of a leaf's triangles to `data`.
pub(super) fn push_triangles(data: &mut Vec<f32>, tris: &[[Vec3; 3]]) {
    for v in 0..3 {
        for axis in 0..3 {
            data.extend(tris.iter().map(|t| t[v][axis]));
        }
    }
}

/// A leaf's triangles: the 9 arrays of `n` floats from the start of
/// `data` (which runs on past them by at least [`PAD`]).
#[derive(Clone, Copy)]
pub(super) struct Triangles<'a> {
    pub data: &'a [f32],
    pub n: usize,
}

impl Triangles<'_> {
    #[inline(always)]
    fn vertex(&self, v: usize, lane: usize) -> Vec3 {
        let a = |axis: usize| self.data[(v * 3 + axis) * self.n + lane];
        Vec3::new(a(0), a(1), a(2))
    }

    /// The scalar test of lane `lane`: t and barycentrics (b1, b2).
    #[inline(always)]
    pub fn hit_lane(
        &self,
        lane: usize,
        ray: &Ray,
        shear: &RayShear,
        t_max: f32,
    ) -> Option<(f32, [f32; 2])> {
        let (a, b, c) = (
            self.vertex(0, lane),
            self.vertex(1, lane),
            self.vertex(2, lane),
        );
        intersect_triangle(ray, shear, a, b, c, t_max).map(|h| (h.t, [h.b[1], h.b[2]]))
    }

    /// Lanes `base … base + LANES` of array (v, axis).
    #[inline(always)]
    fn load<W: Wide>(&self, v: usize, axis: usize, base: usize) -> W::f32s {
        let at = (v * 3 + axis) * self.n + base;
        W::as_simd_f32s(&self.data[at..at + W::LANES]).0[0]
    }

    /// Vertex `v` of lanes `base …`, relative to the origin and sheared
    /// as the scalar test does: (x, y, z).
    #[inline(always)]
    fn sheared<W: Wide>(
        &self,
        s: W,
        r: &WideRay<W>,
        v: usize,
        base: usize,
    ) -> (W::f32s, W::f32s, W::f32s) {
        let [kx, ky, kz] = r.axes;
        let x = s.sub_f32s(self.load::<W>(v, kx, base), r.o[kx]);
        let y = s.sub_f32s(self.load::<W>(v, ky, base), r.o[ky]);
        let z = s.sub_f32s(self.load::<W>(v, kz, base), r.o[kz]);
        (
            s.sub_f32s(x, s.mul_f32s(r.shear[0], z)),
            s.sub_f32s(y, s.mul_f32s(r.shear[1], z)),
            s.mul_f32s(r.shear[2], z),
        )
    }

    /// Of lanes `base … base + LANES`, those the scalar test could accept,
    /// as bits from bit 0 (the caller masks lanes past n).
    #[inline(always)]
    pub fn candidates<W: Wide>(&self, s: W, r: &WideRay<W>, t_max: f32, base: usize) -> u32 {
        let (ax, ay, az) = self.sheared(s, r, 0, base);
        let (bx, by, bz) = self.sheared(s, r, 1, base);
        let (cx, cy, cz) = self.sheared(s, r, 2, base);
        let u = s.sub_f32s(s.mul_f32s(cx, by), s.mul_f32s(cy, bx));
        let v = s.sub_f32s(s.mul_f32s(ax, cy), s.mul_f32s(ay, cx));
        let w = s.sub_f32s(s.mul_f32s(bx, ay), s.mul_f32s(by, ax));
        let zero = s.splat_f32s(0.0);
        let has_zero = or3(
            s,
            s.equal_f32s(u, zero),
            s.equal_f32s(v, zero),
            s.equal_f32s(w, zero),
        );
        let mixed_signs = s.and_m32s(
            or3(
                s,
                s.less_than_f32s(u, zero),
                s.less_than_f32s(v, zero),
                s.less_than_f32s(w, zero),
            ),
            or3(
                s,
                s.greater_than_f32s(u, zero),
                s.greater_than_f32s(v, zero),
                s.greater_than_f32s(w, zero),
            ),
        );
        let det = s.add_f32s(s.add_f32s(u, v), w);
        let t_scaled = s.add_f32s(
            s.add_f32s(s.mul_f32s(u, az), s.mul_f32s(v, bz)),
            s.mul_f32s(w, cz),
        );
        // Where the scalar test leaves f32: always kept.
        let unsure = s.or_m32s(
            has_zero,
            s.not_m32s(s.and_m32s(is_normal(s, t_scaled), is_normal(s, det))),
        );
        let limit = s.mul_f32s(s.splat_f32s(t_max), det);
        let outside_neg = s.and_m32s(
            s.less_than_f32s(det, zero),
            s.or_m32s(
                s.greater_than_or_equal_f32s(t_scaled, zero),
                s.less_than_f32s(t_scaled, limit),
            ),
        );
        let outside_pos = s.and_m32s(
            s.greater_than_f32s(det, zero),
            s.or_m32s(
                s.less_than_or_equal_f32s(t_scaled, zero),
                s.greater_than_f32s(t_scaled, limit),
            ),
        );
        let rejected = s.or_m32s(
            s.or_m32s(mixed_signs, s.equal_f32s(det, zero)),
            s.or_m32s(outside_neg, outside_pos),
        );
        s.mask_bits(s.or_m32s(unsure, s.not_m32s(rejected)))
    }
}

#[inline(always)]
fn or3<W: Wide>(s: W, a: W::m32s, b: W::m32s, c: W::m32s) -> W::m32s {
    s.or_m32s(s.or_m32s(a, b), c)
}

/// `x.is_normal()` per lane.
#[inline(always)]
fn is_normal<W: Wide>(s: W, x: W::f32s) -> W::m32s {
    let a = s.abs_f32s(x);
    s.and_m32s(
        s.greater_than_or_equal_f32s(a, s.splat_f32s(f32::MIN_POSITIVE)),
        s.less_than_f32s(a, s.splat_f32s(f32::INFINITY)),
    )
}

/// Floats per planar shape: its 3 × 4 rows, and 1 for a disk, 0 for a
/// rectangle.
pub(super) const PLANE_FLOATS: usize = 13;

/// Appends the arrays of a leaf's planar shapes to `data`.
pub(super) fn push_planes(data: &mut Vec<f32>, tests: &[PlaneTest]) {
    for i in 0..3 {
        for j in 0..4 {
            data.extend(tests.iter().map(|t| t.parts().0[i][j]));
        }
    }
    data.extend(tests.iter().map(|t| if t.parts().1 { 1.0 } else { 0.0 }));
}

/// A leaf's planar shapes: the 13 arrays of `n` floats from the start of
/// `data` (which runs on past them by at least [`PAD`]).
#[derive(Clone, Copy)]
pub(super) struct Planes<'a> {
    pub data: &'a [f32],
    pub n: usize,
}

impl Planes<'_> {
    /// Lanes `base … base + LANES` of array `k` (row k / 4, column k % 4;
    /// 12: the disk flags).
    #[inline(always)]
    fn load<W: Wide>(&self, k: usize, base: usize) -> W::f32s {
        let at = k * self.n + base;
        W::as_simd_f32s(&self.data[at..at + W::LANES]).0[0]
    }

    /// Row `i` applied to the point `p` (with the translation) or the
    /// vector `p`, in `PlaneTest::intersect`'s order.
    #[inline(always)]
    fn apply<W: Wide>(
        &self,
        s: W,
        i: usize,
        p: &[W::f32s; 3],
        point: bool,
        base: usize,
    ) -> W::f32s {
        let v = s.add_f32s(
            s.add_f32s(
                s.mul_f32s(self.load::<W>(4 * i, base), p[0]),
                s.mul_f32s(self.load::<W>(4 * i + 1, base), p[1]),
            ),
            s.mul_f32s(self.load::<W>(4 * i + 2, base), p[2]),
        );
        if point {
            s.add_f32s(v, self.load::<W>(4 * i + 3, base))
        } else {
            v
        }
    }

    /// Of lanes `base … base + LANES`, those `PlaneTest::intersect`
    /// accepts, as bits from bit 0. Every value is the scalar test's, so
    /// no lane is in doubt.
    #[inline(always)]
    pub fn candidates<W: Wide>(&self, s: W, r: &WideRay<W>, t_max: f32, base: usize) -> u32 {
        let t = s.div_f32s(
            s.neg_f32s(self.apply(s, 2, &r.o, true, base)),
            self.apply(s, 2, &r.d, false, base),
        );
        let in_range = s.and_m32s(
            s.greater_than_f32s(t, s.splat_f32s(0.0)),
            s.less_than_f32s(t, s.splat_f32s(t_max)),
        );
        let x = s.add_f32s(
            self.apply(s, 0, &r.o, true, base),
            s.mul_f32s(t, self.apply(s, 0, &r.d, false, base)),
        );
        let y = s.add_f32s(
            self.apply(s, 1, &r.o, true, base),
            s.mul_f32s(t, self.apply(s, 1, &r.d, false, base)),
        );
        let one = s.splat_f32s(1.0);
        let in_disk =
            s.less_than_or_equal_f32s(s.add_f32s(s.mul_f32s(x, x), s.mul_f32s(y, y)), one);
        let in_square = s.and_m32s(
            s.less_than_or_equal_f32s(s.abs_f32s(x), one),
            s.less_than_or_equal_f32s(s.abs_f32s(y), one),
        );
        let disk = s.equal_f32s(self.load::<W>(12, base), one);
        let inside = s.or_m32s(
            s.and_m32s(disk, in_disk),
            s.and_m32s(s.not_m32s(disk), in_square),
        );
        s.mask_bits(s.and_m32s(in_range, inside))
    }
}

/// What the wide tests need of a ray, in registers.
pub(super) struct WideRay<W: Wide> {
    o: [W::f32s; 3],
    d: [W::f32s; 3],
    axes: [usize; 3],
    shear: [W::f32s; 3],
}

impl<W: Wide> WideRay<W> {
    #[inline(always)]
    pub fn new(s: W, ray: &Ray, shear: &RayShear) -> Self {
        let sh = shear.shear();
        Self {
            o: [ray.o.x, ray.o.y, ray.o.z].map(|v| s.splat_f32s(v)),
            d: [ray.d.x, ray.d.y, ray.d.z].map(|v| s.splat_f32s(v)),
            axes: shear.axes().map(|k| k.min(2)),
            shear: sh.map(|v| s.splat_f32s(v)),
        }
    }
}

//! The BVH's wide nodes: 4 or 8 child boxes in structure-of-arrays form,
//! and their slab tests. The 4-wide test is plain code the compiler
//! vectorises; the 8-wide one runs on [`Lanes8`] (one AVX register, two
//! SSE halves or a scalar loop), every level computing the same f32
//! values in the same order, so every level visits the same children.

use crate::math::GAMMA3;
use crate::math::{Ray, Vec3};
use crate::simd::{Lanes8, Scalar8, Wide};

/// Far distances are scaled up by this so that rounding never loses a
/// box the ray grazes (pbrt-v4 §6.1.2, as `Aabb::hit`).
const FAR_SCALE: f32 = 1.0 + 2.0 * GAMMA3;

/// The per-ray values every box test needs, plain and in lanes.
pub(crate) struct Query<L: Lanes8> {
    o: Vec3,
    inv_d: Vec3,
    /// Per axis, the index of the near and the far plane in a node's
    /// `bounds` (0–2: min, 3–5: max).
    near: [usize; 3],
    far: [usize; 3],
    lo: [L::F; 3],
    li: [L::F; 3],
}

impl<L: Lanes8> Query<L> {
    #[inline(always)]
    pub fn new(l: L, ray: &Ray) -> Self {
        let inv_d = Vec3::new(1.0 / ray.d.x, 1.0 / ray.d.y, 1.0 / ray.d.z);
        // A negative direction enters through the max plane.
        let neg = [
            (inv_d.x < 0.0) as usize,
            (inv_d.y < 0.0) as usize,
            (inv_d.z < 0.0) as usize,
        ];
        Self {
            o: ray.o,
            inv_d,
            near: [3 * neg[0], 1 + 3 * neg[1], 2 + 3 * neg[2]],
            far: [3 - 3 * neg[0], 4 - 3 * neg[1], 5 - 3 * neg[2]],
            lo: [l.splat(ray.o.x), l.splat(ray.o.y), l.splat(ray.o.z)],
            li: [l.splat(inv_d.x), l.splat(inv_d.y), l.splat(inv_d.z)],
        }
    }
}

/// A node of `N` children: their boxes (min x, min y, min z, max x,
/// max y, max z, each one array of N lanes) and what each child is.
/// Unused slots hold an empty box, which no ray of finite coordinates
/// meets (`Bvh::traverse` walks no other). 128 bytes at N = 4, 256 at
/// N = 8.
#[derive(Debug, Clone, Copy)]
#[repr(C, align(64))]
pub(crate) struct Node<const N: usize> {
    pub bounds: [[f32; N]; 6],
    /// Interior child: its node index; leaf: its leaf number (or what
    /// `Bvh::relabel_leaves` put there).
    pub child: [u32; N],
    /// Primitives of a leaf child; 0 for an interior child.
    pub count: [u16; N],
}

impl<const N: usize> Node<N> {
    pub const EMPTY: Node<N> = Node {
        bounds: [
            [f32::INFINITY; N],
            [f32::INFINITY; N],
            [f32::INFINITY; N],
            [f32::NEG_INFINITY; N],
            [f32::NEG_INFINITY; N],
            [f32::NEG_INFINITY; N],
        ],
        child: [0; N],
        count: [0; N],
    };
}

/// What the traversal needs of a node, at either width.
pub(super) trait WideNode {
    /// The slab test of `Aabb::hit` on every child: bit c of the mask is
    /// set when the ray meets child c's box within (0, t_max), and the
    /// array holds the distance at which it enters (lanes past N, and
    /// lanes off the mask, are unspecified).
    fn hit<L: NodeLanes>(&self, l: L, q: &Query<L>, t_max: f32) -> (u32, [f32; 8]);
    fn child(&self, c: usize) -> u32;
    fn count(&self, c: usize) -> u16;
}

#[inline(always)]
fn max(a: f32, b: f32) -> f32 {
    if a > b {
        a
    } else {
        b
    }
}

#[inline(always)]
fn min(a: f32, b: f32) -> f32 {
    if a < b {
        a
    } else {
        b
    }
}

impl WideNode for Node<4> {
    /// Plain code, vectorised by the compiler at every level.
    #[inline(always)]
    fn hit<L: NodeLanes>(&self, _: L, q: &Query<L>, t_max: f32) -> (u32, [f32; 8]) {
        slabs_by_lane(&self.bounds, q, t_max)
    }
    #[inline(always)]
    fn child(&self, c: usize) -> u32 {
        self.child[c]
    }
    #[inline(always)]
    fn count(&self, c: usize) -> u16 {
        self.count[c]
    }
}

impl WideNode for Node<8> {
    #[inline(always)]
    fn hit<L: NodeLanes>(&self, l: L, q: &Query<L>, t_max: f32) -> (u32, [f32; 8]) {
        l.hit8(self, q, t_max)
    }
    #[inline(always)]
    fn child(&self, c: usize) -> u32 {
        self.child[c]
    }
    #[inline(always)]
    fn count(&self, c: usize) -> u16 {
        self.count[c]
    }
}

/// The 8-wide node test on the lanes `Self`: the 4-wide test's
/// operations, in its order, in registers; lane by lane at the scalar
/// level, where eight-lane arrays taken operation by operation cost 1,112
/// and 1,944 instructions per primary and incoherent ray on a million
/// triangles against 838 and 1,445 (the same values either way).
pub(crate) trait NodeLanes: Lanes8 {
    #[inline(always)]
    fn hit8(self, node: &Node<8>, q: &Query<Self>, t_max: f32) -> (u32, [f32; 8]) {
        let (l, b) = (self, &node.bounds);
        let scale = l.splat(FAR_SCALE);
        let t0 = l.max(
            slab(l, q, &b[q.near[0]], 0),
            l.max(
                slab(l, q, &b[q.near[1]], 1),
                l.max(slab(l, q, &b[q.near[2]], 2), l.splat(0.0)),
            ),
        );
        let t1 = l.min(
            l.mul(slab(l, q, &b[q.far[0]], 0), scale),
            l.min(
                l.mul(slab(l, q, &b[q.far[1]], 1), scale),
                l.min(l.mul(slab(l, q, &b[q.far[2]], 2), scale), l.splat(t_max)),
            ),
        );
        (l.le_bits(t0, t1), l.store(t0))
    }
}

impl<W: Wide> NodeLanes for W {}

impl NodeLanes for Scalar8 {
    #[inline(always)]
    fn hit8(self, node: &Node<8>, q: &Query<Self>, t_max: f32) -> (u32, [f32; 8]) {
        slabs_by_lane(&node.bounds, q, t_max)
    }
}

/// The slab test lane by lane (the plain form the compiler vectorises).
#[inline(always)]
fn slabs_by_lane<const N: usize, L: Lanes8>(
    b: &[[f32; N]; 6],
    q: &Query<L>,
    t_max: f32,
) -> (u32, [f32; 8]) {
    let (nx, fx) = (&b[q.near[0]], &b[q.far[0]]);
    let (ny, fy) = (&b[q.near[1]], &b[q.far[1]]);
    let (nz, fz) = (&b[q.near[2]], &b[q.far[2]]);
    let mut out = [0.0; 8];
    let mut mask = 0;
    for c in 0..N {
        let t0 = max(
            (nx[c] - q.o.x) * q.inv_d.x,
            max(
                (ny[c] - q.o.y) * q.inv_d.y,
                max((nz[c] - q.o.z) * q.inv_d.z, 0.0),
            ),
        );
        let t1 = min(
            (fx[c] - q.o.x) * q.inv_d.x * FAR_SCALE,
            min(
                (fy[c] - q.o.y) * q.inv_d.y * FAR_SCALE,
                min((fz[c] - q.o.z) * q.inv_d.z * FAR_SCALE, t_max),
            ),
        );
        out[c] = t0;
        mask |= ((t0 <= t1) as u32) << c;
    }
    (mask, out)
}

/// (plane − o) · (1/d) on eight lanes: where the ray crosses `plane`
/// along `axis`.
#[inline(always)]
fn slab<L: Lanes8>(l: L, q: &Query<L>, plane: &[f32; 8], axis: usize) -> L::F {
    l.mul(l.sub(l.load(plane), q.lo[axis]), q.li[axis])
}

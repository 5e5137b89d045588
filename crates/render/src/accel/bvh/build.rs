//! Building the binary tree: binned surface-area heuristic (Wald 2007),
//! subtrees built in parallel.

use crate::accel::block::BLOCK;
use crate::math::{Aabb, Vec3};

/// Bins per split axis.
const BINS: usize = 16;
/// Cost of a traversal step relative to a primitive test (pbrt-v4 uses ½).
const TRAVERSAL_COST: f32 = 0.5;

/// The leaves a BVH is built for: how their tests cost, for the SAH.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LeafCost {
    /// Most primitives a leaf may hold.
    pub max: usize,
    /// Primitives one test step covers: 1 for scalar tests, the SIMD lanes
    /// for block tests.
    pub lanes: usize,
    /// Cost of a step relative to one scalar primitive test.
    pub step: f32,
    /// Scenes of at most this many primitives are one leaf (no tree):
    /// tested by brute force in a few wide steps.
    pub brute_force: usize,
}

impl LeafCost {
    /// Leaves for scalar tests: at most 8, each primitive a step (leaves
    /// of 4 or 2 measured slower, docs/performance.md). Small scenes are
    /// built so, whatever the SIMD level (one tree for every level keeps
    /// their images identical); large ones get [`LeafCost::wide`] leaves
    /// (`accel::WIDE_LEAVES_FROM`), safe at any scene scale since the
    /// triangle test bounds its distance's error (pbrt-v4 §6.8.4).
    pub const SCALAR: LeafCost = LeafCost {
        max: 8,
        lanes: 1,
        step: 1.0,
        brute_force: 0,
    };

    /// Leaves costed by the wide test's steps of `lanes` primitives, up to
    /// 16.
    pub fn wide(lanes: usize) -> LeafCost {
        LeafCost {
            max: BLOCK,
            lanes: lanes.max(1),
            step: WIDE_STEP_COST,
            brute_force: 0,
        }
    }

    /// The SAH cost of a leaf of `n` primitives, in primitive tests.
    #[inline]
    fn of(&self, n: usize) -> f32 {
        n.div_ceil(self.lanes) as f32 * self.step
    }
}

/// Cost of one wide step of a block test (up to 16 lanes) relative to one
/// scalar primitive test: about 60 vector instructions against the
/// scalar test's 30–40, which often exits early.
const WIDE_STEP_COST: f32 = 2.0;
/// Subtrees larger than this are built in parallel.
const PARALLEL_MIN: usize = 4096;

#[derive(Clone, Copy)]
pub(super) struct Item {
    pub(super) bounds: Aabb,
    pub(super) centroid: Vec3,
    pub(super) index: u32,
}

/// The binary tree as built, before it is collapsed.
pub(super) enum BuildNode {
    Leaf {
        bounds: Aabb,
        start: usize,
        count: usize,
    },
    Interior {
        bounds: Aabb,
        children: Box<[BuildNode; 2]>,
    },
}

/// The tree over `items` (which it reorders into leaf order), the first
/// of them at `start` in the whole.
pub(super) fn build(items: &mut [Item], start: usize, cost: &LeafCost) -> BuildNode {
    let bounds = items.iter().fold(Aabb::EMPTY, |b, it| b.union(it.bounds));
    let n = items.len();
    let leaf = BuildNode::Leaf {
        bounds,
        start,
        count: n,
    };
    if n <= 1 {
        return leaf;
    }
    let centroid_bounds = items.iter().fold(Aabb::EMPTY, |b, it| b.grow(it.centroid));
    let axis = centroid_bounds.extent().max_dimension();
    let (lo, hi) = (centroid_bounds.min[axis], centroid_bounds.max[axis]);

    // All centroids coincide: no plane separates them; split by count.
    let mid = if hi.partial_cmp(&lo) != Some(std::cmp::Ordering::Greater) {
        if n <= cost.max {
            return leaf;
        }
        n / 2
    } else {
        // Bin the centroids and sweep for the cheapest of the BINS − 1 planes.
        let scale = BINS as f32 / (hi - lo);
        let bin_of = |c: Vec3| (((c[axis] - lo) * scale) as usize).min(BINS - 1);
        let mut counts = [0usize; BINS];
        let mut boxes = [Aabb::EMPTY; BINS];
        for it in items.iter() {
            let b = bin_of(it.centroid);
            counts[b] += 1;
            boxes[b] = boxes[b].union(it.bounds);
        }
        let mut right_area = [0.0f32; BINS];
        let mut right_count = [0usize; BINS];
        let (mut acc_b, mut acc_n) = (Aabb::EMPTY, 0);
        for i in (1..BINS).rev() {
            acc_b = acc_b.union(boxes[i]);
            acc_n += counts[i];
            right_area[i] = acc_b.area();
            right_count[i] = acc_n;
        }
        let (mut best, mut best_cost) = (0, f32::INFINITY);
        let (mut acc_b, mut acc_n) = (Aabb::EMPTY, 0);
        for i in 0..BINS - 1 {
            acc_b = acc_b.union(boxes[i]);
            acc_n += counts[i];
            let cost =
                acc_b.area() * cost.of(acc_n) + right_area[i + 1] * cost.of(right_count[i + 1]);
            if cost < best_cost {
                best_cost = cost;
                best = i;
            }
        }
        let split_cost = TRAVERSAL_COST + best_cost / bounds.area().max(f32::MIN_POSITIVE);
        if n <= cost.max && split_cost >= cost.of(n) {
            return leaf;
        }
        // Partition in place by the chosen plane.
        let mut left = 0;
        for i in 0..n {
            if bin_of(items[i].centroid) <= best {
                items.swap(i, left);
                left += 1;
            }
        }
        if left == 0 || left == n {
            n / 2
        } else {
            left
        }
    };

    let (l, r) = items.split_at_mut(mid);
    let (a, b) = if n > PARALLEL_MIN {
        rayon::join(|| build(l, start, cost), || build(r, start + mid, cost))
    } else {
        (build(l, start, cost), build(r, start + mid, cost))
    };
    BuildNode::Interior {
        bounds,
        children: Box::new([a, b]),
    }
}

impl BuildNode {
    pub(super) fn bounds(&self) -> Aabb {
        match self {
            BuildNode::Leaf { bounds, .. } | BuildNode::Interior { bounds, .. } => *bounds,
        }
    }
}

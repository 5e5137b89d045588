//! A bounding volume hierarchy built with the binned surface-area heuristic
//! (Wald 2007, "On fast Construction of SAH-based Bounding Volume
//! Hierarchies"), in parallel, then collapsed into a 4- or 8-wide tree for
//! traversal (as Embree's BVH4 and BVH8, Wald et al. 2014): each node
//! tests its child boxes at once (`node.rs`).

use rayon::prelude::*;

use super::node::{Node, NodeLanes, Query, WideNode};
use super::Aabb;
use crate::math::{Ray, Vec3};

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
            max: super::block::BLOCK,
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

/// Children per node of the traversal tree. The tree depends on it and
/// the primitives only, never on the SIMD level.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Width {
    Four,
    Eight,
}

/// The tree's nodes, at its width.
#[derive(Debug, Clone)]
enum Nodes {
    Four(Vec<Node<4>>),
    Eight(Vec<Node<8>>),
}

/// A BVH over primitives given by their bounds.
#[derive(Debug, Clone)]
pub struct Bvh {
    nodes: Nodes,
    bounds: Aabb,
    /// Primitive indices in leaf order.
    order: Vec<u32>,
    /// Each leaf's first position in `order` and primitive count, by the
    /// leaf numbers `traverse` reports.
    leaves: Vec<(u32, u32)>,
}

#[derive(Clone, Copy)]
struct Item {
    bounds: Aabb,
    centroid: Vec3,
    index: u32,
}

enum BuildNode {
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

fn build(items: &mut [Item], start: usize, cost: &LeafCost) -> BuildNode {
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

impl Bvh {
    /// Builds over primitives with the given bounds (empty bounds are left
    /// out: such primitives can never be hit).
    pub fn build(bounds: &[Aabb]) -> Self {
        Self::build_for(bounds, &LeafCost::SCALAR, Width::Eight)
    }

    /// Builds with leaves costed by `cost`, into nodes of `width`.
    pub fn build_for(bounds: &[Aabb], cost: &LeafCost, width: Width) -> Self {
        let mut items: Vec<Item> = bounds
            .par_iter()
            .enumerate()
            .filter(|(_, b)| !b.is_empty() && b.min.is_finite() && b.max.is_finite())
            .map(|(i, b)| Item {
                bounds: *b,
                centroid: b.centroid(),
                index: i as u32,
            })
            .collect();
        if items.is_empty() {
            return Self {
                nodes: Nodes::Four(Vec::new()),
                bounds: Aabb::EMPTY,
                order: Vec::new(),
                leaves: Vec::new(),
            };
        }
        // Leaves hold at most u16::MAX primitives; the count split guarantees
        // far fewer (cost.max, or one degenerate cluster halved until small).
        let root = if items.len() <= cost.brute_force.min(u16::MAX as usize) {
            BuildNode::Leaf {
                bounds: items.iter().fold(Aabb::EMPTY, |b, it| b.union(it.bounds)),
                start: 0,
                count: items.len(),
            }
        } else {
            build(&mut items, 0, cost)
        };
        let mut leaves = Vec::new();
        let nodes = match width {
            Width::Four => Nodes::Four(collapse(&root, &mut leaves)),
            Width::Eight => Nodes::Eight(collapse(&root, &mut leaves)),
        };
        Self {
            nodes,
            bounds: root.bounds(),
            order: items.iter().map(|it| it.index).collect(),
            leaves,
        }
    }

    /// Primitive indices in leaf order.
    pub fn order(&self) -> &[u32] {
        &self.order
    }

    /// Each leaf's first position in `order()` and primitive count, by the
    /// leaf numbers `traverse` reports.
    pub fn leaves(&self) -> &[(u32, u32)] {
        &self.leaves
    }

    /// The leaf order and the leaves, handed over once the caller has laid
    /// its primitives out by them (they are not needed to traverse).
    pub(super) fn take_layout(&mut self) -> (Vec<u32>, Vec<(u32, u32)>) {
        (
            std::mem::take(&mut self.order),
            std::mem::take(&mut self.leaves),
        )
    }

    /// Rewrites each leaf's words in its node: `f(leaf number)` gives the
    /// (child, count) that `traverse` will hand to `Visit::leaf` (count
    /// must not be 0, which marks interior children). Lets the caller find
    /// a leaf's primitives without a table lookup.
    pub fn relabel_leaves(&mut self, f: impl Fn(u32) -> (u32, u16)) {
        match &mut self.nodes {
            Nodes::Four(nodes) => relabel(nodes, f),
            Nodes::Eight(nodes) => relabel(nodes, f),
        }
    }

    /// Children per node.
    pub fn width(&self) -> Width {
        match self.nodes {
            Nodes::Four(_) => Width::Four,
            Nodes::Eight(_) => Width::Eight,
        }
    }

    /// Nodes of the wide tree.
    pub fn node_count(&self) -> usize {
        match &self.nodes {
            Nodes::Four(n) => n.len(),
            Nodes::Eight(n) => n.len(),
        }
    }

    /// Bytes of the nodes.
    pub fn node_bytes(&self) -> usize {
        match &self.nodes {
            Nodes::Four(n) => std::mem::size_of_val(&n[..]),
            Nodes::Eight(n) => std::mem::size_of_val(&n[..]),
        }
    }

    /// Bounds of everything.
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    /// Visits the leaves whose boxes the ray meets within (0, t_max),
    /// nearest box first, by their number in `leaves()`, testing 8-wide
    /// nodes on the lanes `l`.
    /// `hit(leaf, t_max)` returns a new, closer t_max when one of the
    /// leaf's primitives is hit; returning `Some` with `stop` true ends the
    /// traversal (any-hit queries). `NEAREST_FIRST` orders each node's
    /// children by distance: closest-hit queries need it to shrink t_max
    /// early; any-hit queries skip the sort.
    #[inline(always)]
    pub(crate) fn traverse<const NEAREST_FIRST: bool, L: NodeLanes>(
        &self,
        l: L,
        ray: &Ray,
        t_max: f32,
        mut hit: impl Visit,
    ) -> f32 {
        let query = Query::new(l, ray);
        match &self.nodes {
            Nodes::Four(n) if !n.is_empty() => {
                Walk { nodes: n, l }
                    .walk::<NEAREST_FIRST>(&query, 0, t_max, &mut hit)
                    .0
            }
            Nodes::Eight(n) if !n.is_empty() => {
                Walk { nodes: n, l }
                    .walk::<NEAREST_FIRST>(&query, 0, t_max, &mut hit)
                    .0
            }
            _ => t_max,
        }
    }
}

/// Rewrites each leaf child's words by `f`.
fn relabel<const N: usize>(nodes: &mut [Node<N>], f: impl Fn(u32) -> (u32, u16)) {
    for node in nodes {
        for c in 0..N {
            if node.count[c] != 0 {
                let (child, count) = f(node.child[c]);
                assert!(count != 0, "a leaf's count must not be 0");
                (node.child[c], node.count[c]) = (child, count);
            }
        }
    }
}

/// A traversal of nodes `T` whose 8-wide tests run on lanes `L`.
struct Walk<'a, T, L> {
    nodes: &'a [T],
    l: L,
}

/// Bits of a stack entry's low word that hold the child slot (the node
/// index is above them).
const SLOT_BITS: u32 = 3;

impl<T: WideNode, L: NodeLanes> Walk<'_, T, L> {
    /// Traverses the subtree under node `root` with a fixed stack of
    /// (entry distance, node, child slot) words; a subtree that would
    /// overflow it (only in pathologically deep trees) is walked by
    /// recursion instead. Returns (t_max, stopped).
    #[inline(always)]
    fn walk<const NEAREST_FIRST: bool>(
        &self,
        q: &Query<L>,
        root: u32,
        mut t_max: f32,
        hit: &mut impl Visit,
    ) -> (f32, bool) {
        let mut stack = [0u64; STACK];
        let mut sp = 0;
        let mut current = root;
        loop {
            let node = &self.nodes[current as usize];
            let (mut mask, t_near) = node.hit(self.l, q, t_max);
            // The hit children, sorted farthest first (insertion into at
            // most eight), so the nearest is pushed last and pops first.
            let mut hits = [(0.0f32, 0u32); 8];
            let mut n = 0;
            while mask != 0 {
                let c = mask.trailing_zeros() as usize;
                mask &= mask - 1;
                let t = t_near[c];
                let mut j = n;
                while NEAREST_FIRST && j > 0 && hits[j - 1].0 < t {
                    hits[j] = hits[j - 1];
                    j -= 1;
                }
                hits[j] = (t, c as u32);
                n += 1;
            }
            // Descend straight into the nearest child when it is interior;
            // the others wait on the stack.
            if n > 0 && node.count(hits[n - 1].1 as usize) == 0 {
                n -= 1;
                for &(t, c) in &hits[..n] {
                    let (t, stop) = self
                        .push::<NEAREST_FIRST>(&mut stack, &mut sp, q, current, c, t, t_max, hit);
                    t_max = t;
                    if stop {
                        return (t_max, true);
                    }
                }
                current = node.child(hits[n].1 as usize);
                continue;
            }
            for &(t, c) in &hits[..n] {
                let (t, stop) =
                    self.push::<NEAREST_FIRST>(&mut stack, &mut sp, q, current, c, t, t_max, hit);
                t_max = t;
                if stop {
                    return (t_max, true);
                }
            }
            // Pop until an interior child to descend into.
            loop {
                if sp == 0 {
                    return (t_max, false);
                }
                sp -= 1;
                let e = stack[sp];
                // A box entered beyond the closest hit holds nothing nearer.
                if f32::from_bits((e >> 32) as u32) > t_max {
                    continue;
                }
                let (index, slot) = (
                    (e as u32) >> SLOT_BITS,
                    (e as u32 & ((1 << SLOT_BITS) - 1)) as usize,
                );
                let node = &self.nodes[index as usize];
                if node.count(slot) == 0 {
                    current = node.child(slot);
                    break;
                }
                let (t, stop) = self.visit::<NEAREST_FIRST>(q, node, slot, t_max, hit);
                t_max = t;
                if stop {
                    return (t_max, true);
                }
            }
        }
    }

    /// Puts child `slot` of node `index`, entered at `t`, on the stack;
    /// when the stack is full, visits it at once instead.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn push<const NEAREST_FIRST: bool>(
        &self,
        stack: &mut [u64; STACK],
        sp: &mut usize,
        q: &Query<L>,
        index: u32,
        slot: u32,
        t: f32,
        t_max: f32,
        hit: &mut impl Visit,
    ) -> (f32, bool) {
        if *sp < STACK {
            stack[*sp] = (t.to_bits() as u64) << 32 | (index << SLOT_BITS | slot) as u64;
            *sp += 1;
            return (t_max, false);
        }
        self.visit::<NEAREST_FIRST>(q, &self.nodes[index as usize], slot as usize, t_max, hit)
    }

    /// Child `slot` of `node`: a leaf, or (when the stack is full) an
    /// interior subtree by recursion.
    #[inline(always)]
    fn visit<const NEAREST_FIRST: bool>(
        &self,
        q: &Query<L>,
        node: &T,
        slot: usize,
        t_max: f32,
        hit: &mut impl Visit,
    ) -> (f32, bool) {
        let child = node.child(slot);
        if node.count(slot) == 0 {
            return self.walk_deep::<NEAREST_FIRST>(q, child, t_max, hit);
        }
        match hit.leaf(child, node.count(slot), t_max) {
            Some((t, stop)) => (t, stop),
            None => (t_max, false),
        }
    }

    /// `walk` where the stack overflowed: not inlined, which ends the
    /// recursion's inlining.
    #[inline(never)]
    fn walk_deep<const NEAREST_FIRST: bool>(
        &self,
        q: &Query<L>,
        root: u32,
        t_max: f32,
        hit: &mut impl Visit,
    ) -> (f32, bool) {
        self.walk::<NEAREST_FIRST>(q, root, t_max, hit)
    }
}

/// What a traversal does at a leaf: `leaf(child, count, t_max)` (the
/// leaf's words in its node: its number and primitive count as built, or
/// what [`Bvh::relabel_leaves`] put there) returns a new, closer t_max
/// when a primitive is hit, with whether to stop. A trait rather than a
/// closure so the call can be `#[inline(always)]`, which keeps it inside a
/// SIMD kernel's target features.
pub trait Visit {
    fn leaf(&mut self, child: u32, count: u16, t_max: f32) -> Option<(f32, bool)>;
}

impl<F: FnMut(u32, f32) -> Option<(f32, bool)>> Visit for F {
    #[inline(always)]
    fn leaf(&mut self, child: u32, _: u16, t_max: f32) -> Option<(f32, bool)> {
        self(child, t_max)
    }
}

/// Entries on the traversal stack.
const STACK: usize = 32;

impl BuildNode {
    fn bounds(&self) -> Aabb {
        match self {
            BuildNode::Leaf { bounds, .. } | BuildNode::Interior { bounds, .. } => *bounds,
        }
    }
}

/// Collapses the binary tree into N-wide nodes: each node takes its
/// children's children, opening the largest interior child first, until
/// it has N. Node 0 is the root.
fn collapse<const N: usize>(root: &BuildNode, leaves: &mut Vec<(u32, u32)>) -> Vec<Node<N>> {
    let mut nodes = vec![Node::EMPTY];
    let top: Vec<&BuildNode> = match root {
        // A lone leaf still needs a node above it.
        BuildNode::Leaf { .. } => vec![root],
        BuildNode::Interior { children, .. } => vec![&children[0], &children[1]],
    };
    fill(0, top, &mut nodes, leaves);
    nodes
}

fn fill<const N: usize>(
    at: usize,
    mut kids: Vec<&BuildNode>,
    nodes: &mut Vec<Node<N>>,
    leaves: &mut Vec<(u32, u32)>,
) {
    while kids.len() < N {
        let widest = kids
            .iter()
            .enumerate()
            .filter(|(_, k)| matches!(k, BuildNode::Interior { .. }))
            .max_by(|a, b| a.1.bounds().area().total_cmp(&b.1.bounds().area()))
            .map(|(i, _)| i);
        let Some(i) = widest else { break };
        let BuildNode::Interior { children, .. } = kids.swap_remove(i) else {
            unreachable!("filtered to interior nodes")
        };
        kids.push(&children[0]);
        kids.push(&children[1]);
    }
    for (c, kid) in kids.into_iter().enumerate() {
        let b = kid.bounds();
        let corners = [b.min.x, b.min.y, b.min.z, b.max.x, b.max.y, b.max.z];
        for (k, v) in corners.into_iter().enumerate() {
            nodes[at].bounds[k][c] = v;
        }
        match kid {
            BuildNode::Leaf { start, count, .. } => {
                nodes[at].child[c] = leaves.len() as u32;
                nodes[at].count[c] = (*count).clamp(1, u16::MAX as usize) as u16;
                leaves.push((*start as u32, *count as u32));
            }
            BuildNode::Interior { children, .. } => {
                let index = nodes.len();
                nodes.push(Node::EMPTY);
                nodes[at].child[c] = index as u32;
                fill(index, vec![&children[0], &children[1]], nodes, leaves);
            }
        }
    }
}

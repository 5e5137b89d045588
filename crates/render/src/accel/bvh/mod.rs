//! A bounding volume hierarchy: a binary tree built with the binned
//! surface-area heuristic (`build`: Wald 2007, "On fast Construction of
//! SAH-based Bounding Volume Hierarchies"), in parallel, then collapsed
//! into a 4- or 8-wide tree (`collapse`, as Embree's BVH4 and BVH8, Wald
//! et al. 2014) that a ray walks testing each node's child boxes at once
//! (`traverse`, `node.rs`).

mod build;
mod collapse;
mod traverse;

use rayon::prelude::*;

pub use build::LeafCost;
pub use traverse::Visit;

use super::node::{Node, NodeLanes, Query};
use super::Aabb;
use crate::math::Ray;
use build::{build, BuildNode, Item};
use collapse::collapse;
use traverse::Walk;

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
    /// early; any-hit queries skip the sort. A ray with a NaN or infinite
    /// coordinate meets nothing ([`meets_boxes`]).
    #[inline(always)]
    pub(crate) fn traverse<const NEAREST_FIRST: bool, L: NodeLanes>(
        &self,
        l: L,
        ray: &Ray,
        t_max: f32,
        mut hit: impl Visit,
    ) -> f32 {
        if !meets_boxes(ray) {
            return t_max;
        }
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

/// Whether `ray` can be walked through the tree: its origin and direction
/// are finite. A NaN coordinate (or an infinite one, through ∞ − ∞ or
/// 0 · ∞) makes slab distances NaN, which the tests' min/max chains pass
/// over, so a box can test as hit — an unused slot's empty box too, whose
/// child word (0, interior) is the root: the walk would go back to the
/// root without end, and once its stack filled, recurse until the
/// thread's stack overflowed.
#[inline(always)]
fn meets_boxes(ray: &Ray) -> bool {
    ray.o.is_finite() && ray.d.is_finite()
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

//! A bounding volume hierarchy built with the binned surface-area heuristic
//! (Wald 2007, "On fast Construction of SAH-based Bounding Volume
//! Hierarchies"), in parallel, then flattened depth-first for traversal.

use rayon::prelude::*;

use super::Aabb;
use crate::math::{Ray, Vec3};

/// Bins per split axis.
const BINS: usize = 16;
/// Most primitives a leaf may hold.
const MAX_LEAF: usize = 8;
/// Cost of a traversal step relative to a primitive test (pbrt-v4 uses ½).
const TRAVERSAL_COST: f32 = 0.5;
/// Subtrees larger than this are built in parallel.
const PARALLEL_MIN: usize = 4096;

/// One node of the flattened tree: 32 bytes.
#[derive(Debug, Clone, Copy)]
struct Node {
    bounds: Aabb,
    /// Leaf: first index into `order`; interior: index of the second child
    /// (the first child follows the node).
    offset: u32,
    /// Primitives in a leaf; 0 for an interior node.
    count: u16,
    /// Split axis of an interior node.
    axis: u16,
}

/// A BVH over primitives given by their bounds.
#[derive(Debug, Clone)]
pub struct Bvh {
    nodes: Vec<Node>,
    /// Primitive indices in leaf order.
    order: Vec<u32>,
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
        axis: usize,
        children: Box<[BuildNode; 2]>,
        size: usize,
    },
}

impl BuildNode {
    fn node_count(&self) -> usize {
        match self {
            BuildNode::Leaf { .. } => 1,
            BuildNode::Interior { size, .. } => *size,
        }
    }
}

fn build(items: &mut [Item], start: usize) -> BuildNode {
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
        if n <= MAX_LEAF {
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
            let cost = acc_b.area() * acc_n as f32 + right_area[i + 1] * right_count[i + 1] as f32;
            if cost < best_cost {
                best_cost = cost;
                best = i;
            }
        }
        let split_cost = TRAVERSAL_COST + best_cost / bounds.area().max(f32::MIN_POSITIVE);
        if n <= MAX_LEAF && split_cost >= n as f32 {
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
        rayon::join(|| build(l, start), || build(r, start + mid))
    } else {
        (build(l, start), build(r, start + mid))
    };
    let size = 1 + a.node_count() + b.node_count();
    BuildNode::Interior {
        bounds,
        axis,
        children: Box::new([a, b]),
        size,
    }
}

fn flatten(node: &BuildNode, nodes: &mut Vec<Node>) {
    match node {
        BuildNode::Leaf {
            bounds,
            start,
            count,
        } => nodes.push(Node {
            bounds: *bounds,
            offset: *start as u32,
            count: *count as u16,
            axis: 0,
        }),
        BuildNode::Interior {
            bounds,
            axis,
            children,
            ..
        } => {
            let here = nodes.len();
            nodes.push(Node {
                bounds: *bounds,
                offset: 0,
                count: 0,
                axis: *axis as u16,
            });
            flatten(&children[0], nodes);
            nodes[here].offset = nodes.len() as u32;
            flatten(&children[1], nodes);
        }
    }
}

impl Bvh {
    /// Builds over primitives with the given bounds (empty bounds are left
    /// out: such primitives can never be hit).
    pub fn build(bounds: &[Aabb]) -> Self {
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
                nodes: Vec::new(),
                order: Vec::new(),
            };
        }
        // Leaves hold at most u16::MAX primitives; the count split guarantees
        // far fewer (MAX_LEAF, or one degenerate cluster halved until small).
        let root = build(&mut items, 0);
        let mut nodes = Vec::with_capacity(root.node_count());
        flatten(&root, &mut nodes);
        Self {
            nodes,
            order: items.iter().map(|it| it.index).collect(),
        }
    }

    pub fn node_count(&self) -> usize {
        self.nodes.len()
    }

    /// Bounds of everything.
    pub fn bounds(&self) -> Aabb {
        self.nodes.first().map_or(Aabb::EMPTY, |n| n.bounds)
    }

    /// Visits the primitives whose boxes the ray meets within (0, t_max),
    /// nearest subtree first. `hit(prim, t_max)` returns a new, closer t_max
    /// when the primitive is hit; returning `Some` with `stop` true ends the
    /// traversal (any-hit queries).
    #[inline]
    pub fn traverse(
        &self,
        ray: &Ray,
        mut t_max: f32,
        mut hit: impl FnMut(u32, f32) -> Option<(f32, bool)>,
    ) -> f32 {
        if self.nodes.is_empty() {
            return t_max;
        }
        let inv_d = Vec3::new(1.0 / ray.d.x, 1.0 / ray.d.y, 1.0 / ray.d.z);
        let neg = [inv_d.x < 0.0, inv_d.y < 0.0, inv_d.z < 0.0];
        let mut stack = [0u32; 64];
        let mut sp = 0;
        let mut current = 0usize;
        loop {
            let node = &self.nodes[current];
            if node.bounds.hit(ray, inv_d, t_max) {
                if node.count > 0 {
                    let start = node.offset as usize;
                    for &prim in &self.order[start..start + node.count as usize] {
                        if let Some((t, stop)) = hit(prim, t_max) {
                            t_max = t;
                            if stop {
                                return t_max;
                            }
                        }
                    }
                } else {
                    // Visit the near child first; push the far one.
                    let (near, far) = if neg[node.axis as usize] {
                        (node.offset as usize, current + 1)
                    } else {
                        (current + 1, node.offset as usize)
                    };
                    if sp < stack.len() {
                        stack[sp] = far as u32;
                        sp += 1;
                        current = near;
                        continue;
                    }
                    // Deeper than 64 (pathological input): visit both, near
                    // first, by recursing on the far side.
                    t_max = self.traverse_from(far, ray, t_max, &mut hit);
                    current = near;
                    continue;
                }
            }
            if sp == 0 {
                return t_max;
            }
            sp -= 1;
            current = stack[sp] as usize;
        }
    }

    fn traverse_from(
        &self,
        start: usize,
        ray: &Ray,
        t_max: f32,
        hit: &mut impl FnMut(u32, f32) -> Option<(f32, bool)>,
    ) -> f32 {
        // A plain recursive walk, for the rare stack overflow case.
        let node = &self.nodes[start];
        let inv_d = Vec3::new(1.0 / ray.d.x, 1.0 / ray.d.y, 1.0 / ray.d.z);
        if !node.bounds.hit(ray, inv_d, t_max) {
            return t_max;
        }
        let mut t_max = t_max;
        if node.count > 0 {
            let s = node.offset as usize;
            for &prim in &self.order[s..s + node.count as usize] {
                if let Some((t, _)) = hit(prim, t_max) {
                    t_max = t;
                }
            }
            t_max
        } else {
            t_max = self.traverse_from(start + 1, ray, t_max, hit);
            self.traverse_from(node.offset as usize, ray, t_max, hit)
        }
    }
}

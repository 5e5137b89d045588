//! Where the guide's directional densities hold: a binary tree over the
//! scene's box, each node halved across its longest side (Müller et al.
//! 2017, which alternates the axes; the longest side keeps the cells
//! of a 300 m street from becoming slivers), each leaf a cell with its own
//! density of directions.

use crate::math::Vec3;

#[derive(Debug, Clone, Copy, PartialEq)]
struct Node {
    /// The axis it is halved across.
    axis: u8,
    /// Its first child (the second follows); 0 for a cell.
    child: u32,
    /// A cell's index among the cells.
    cell: u32,
}

/// The tree of cells.
#[derive(Debug, Clone, PartialEq)]
pub struct SpatialTree {
    lo: Vec3,
    hi: Vec3,
    nodes: Vec<Node>,
}

impl SpatialTree {
    /// One cell covering the box `lo`..`hi`.
    pub fn new(lo: Vec3, hi: Vec3) -> Self {
        Self {
            lo,
            hi,
            nodes: vec![Node {
                axis: 0,
                child: 0,
                cell: 0,
            }],
        }
    }

    /// How many cells it has.
    pub fn cells(&self) -> usize {
        self.nodes.iter().filter(|n| n.child == 0).count()
    }

    /// The cell holding `p` (points outside the box: the nearest cell).
    pub fn cell(&self, p: Vec3) -> u32 {
        self.locate(p).0
    }

    /// The size of the cell holding `p`.
    pub fn size_at(&self, p: Vec3) -> Vec3 {
        let (_, lo, hi) = self.locate(p);
        Vec3::new(hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2])
    }

    /// The cell holding `p` and its box.
    fn locate(&self, p: Vec3) -> (u32, [f32; 3], [f32; 3]) {
        let p = p.to_array();
        let (mut lo, mut hi) = (self.lo.to_array(), self.hi.to_array());
        let mut node = self.nodes[0];
        while node.child != 0 {
            let a = node.axis as usize;
            let mid = 0.5 * (lo[a] + hi[a]);
            node = if p[a] < mid {
                hi[a] = mid;
                self.nodes[node.child as usize]
            } else {
                lo[a] = mid;
                self.nodes[node.child as usize + 1]
            };
        }
        (node.cell, lo, hi)
    }

    /// Each cell's box, by cell.
    pub fn boxes(&self) -> Vec<(Vec3, Vec3)> {
        let mut out = vec![(self.lo, self.hi); self.cells()];
        let mut stack = vec![(0usize, self.lo.to_array(), self.hi.to_array())];
        while let Some((i, lo, hi)) = stack.pop() {
            let n = self.nodes[i];
            if n.child == 0 {
                out[n.cell as usize] = (Vec3::from(lo), Vec3::from(hi));
                continue;
            }
            let a = n.axis as usize;
            let mid = 0.5 * (lo[a] + hi[a]);
            let (mut hi0, mut lo1) = (hi, lo);
            hi0[a] = mid;
            lo1[a] = mid;
            stack.push((n.child as usize, lo, hi0));
            stack.push((n.child as usize + 1, lo1, hi));
        }
        out
    }

    /// `p` moved into the tree's box.
    pub fn clamp(&self, p: Vec3) -> Vec3 {
        p.max(self.lo).min(self.hi)
    }

    /// The tree with every cell `c` for which `times(c)` is k > 0 halved k
    /// times over (each half again, across the longest side each time).
    /// Cells are renumbered in the order of the tree's nodes; returns the
    /// new tree and, for each new cell, the old cell it lies in.
    pub fn split(&self, times: impl Fn(u32) -> u32) -> (Self, Vec<u32>) {
        let mut out = Self {
            lo: self.lo,
            hi: self.hi,
            nodes: Vec::with_capacity(self.nodes.len()),
        };
        let mut origin = Vec::new();
        out.nodes.push(self.nodes[0]);
        let (lo, hi) = (self.lo.to_array(), self.hi.to_array());
        self.copy_node(0, 0, lo, hi, &times, &mut out.nodes, &mut origin);
        (out, origin)
    }

    #[allow(clippy::too_many_arguments)] // a recursion's running state
    fn copy_node(
        &self,
        from: usize,
        to: usize,
        lo: [f32; 3],
        hi: [f32; 3],
        times: &impl Fn(u32) -> u32,
        nodes: &mut Vec<Node>,
        origin: &mut Vec<u32>,
    ) {
        let n = self.nodes[from];
        if n.child == 0 {
            Self::grow(to, lo, hi, times(n.cell), n.cell, nodes, origin);
            return;
        }
        let first = nodes.len();
        nodes.push(self.nodes[n.child as usize]);
        nodes.push(self.nodes[n.child as usize + 1]);
        nodes[to] = Node {
            axis: n.axis,
            child: first as u32,
            cell: 0,
        };
        let a = n.axis as usize;
        let mid = 0.5 * (lo[a] + hi[a]);
        let (mut hi0, mut lo1) = (hi, lo);
        hi0[a] = mid;
        lo1[a] = mid;
        self.copy_node(n.child as usize, first, lo, hi0, times, nodes, origin);
        self.copy_node(
            n.child as usize + 1,
            first + 1,
            lo1,
            hi,
            times,
            nodes,
            origin,
        );
    }

    /// Makes node `at` (box `lo`..`hi`) a cell of old cell `old`, halved
    /// `k` times.
    fn grow(
        at: usize,
        lo: [f32; 3],
        hi: [f32; 3],
        k: u32,
        old: u32,
        nodes: &mut Vec<Node>,
        origin: &mut Vec<u32>,
    ) {
        if k == 0 {
            nodes[at] = Node {
                axis: 0,
                child: 0,
                cell: origin.len() as u32,
            };
            origin.push(old);
            return;
        }
        let size = [hi[0] - lo[0], hi[1] - lo[1], hi[2] - lo[2]];
        let a = if size[0] >= size[1] && size[0] >= size[2] {
            0
        } else if size[1] >= size[2] {
            1
        } else {
            2
        };
        let first = nodes.len();
        let leaf = Node {
            axis: 0,
            child: 0,
            cell: 0,
        };
        nodes.push(leaf);
        nodes.push(leaf);
        nodes[at] = Node {
            axis: a as u8,
            child: first as u32,
            cell: 0,
        };
        let mid = 0.5 * (lo[a] + hi[a]);
        let (mut hi0, mut lo1) = (hi, lo);
        hi0[a] = mid;
        lo1[a] = mid;
        Self::grow(first, lo, hi0, k - 1, old, nodes, origin);
        Self::grow(first + 1, lo1, hi, k - 1, old, nodes, origin);
    }
}

//! Walking the wide tree: each node tests its child boxes at once
//! (`node.rs`); the hit children go on a fixed stack, nearest popped first.

use crate::accel::node::{NodeLanes, Query, WideNode};

/// A traversal of nodes `T` whose 8-wide tests run on lanes `L`.
pub(super) struct Walk<'a, T, L> {
    pub(super) nodes: &'a [T],
    pub(super) l: L,
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
    pub(super) fn walk<const NEAREST_FIRST: bool>(
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

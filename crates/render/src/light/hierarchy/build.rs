//! Building the tree: a binary BVH over the lights' bounds, split by the
//! surface area orientation heuristic (SAOH) of Conty Estevez & Kulla 2018
//! (§4.3), binned as pbrt-v4 bins it (§12.6.3). Deterministic: the same
//! lights in the same order give the same tree.

use super::bounds::LightBounds;
use crate::math::Aabb;

/// Bins per axis for the split search.
const BUCKETS: usize = 12;

/// Levels a path from the root may have: a light's path is kept as bits
/// in a u64.
pub(super) const MAX_DEPTH: u32 = 63;

/// A node of the tree, stored depth first: an interior node's first child
/// follows it, `index` is its second child; a leaf's `index` is its light.
#[derive(Debug, Clone, Copy, PartialEq)]
pub(super) struct BuildNode {
    pub bounds: LightBounds,
    pub index: u32,
    pub leaf: bool,
}

/// The tree's nodes and, per light in it, (light, path bits, depth): bit
/// k set when the path turns to the second child at depth k.
pub(super) struct Built {
    pub nodes: Vec<BuildNode>,
    pub paths: Vec<(usize, u64, u32)>,
}

/// Lights (index, bounds) to place in a subtree.
type Items = Vec<(usize, LightBounds)>;

/// The tree over `items` (light index, bounds); empty for none.
pub(super) fn build(items: Items) -> Built {
    let mut built = Built {
        nodes: Vec::with_capacity(2 * items.len()),
        paths: Vec::with_capacity(items.len()),
    };
    if !items.is_empty() {
        split(items, 0, 0, &mut built);
    }
    built
}

/// ⌈log₂ n⌉.
fn ceil_log2(n: usize) -> u32 {
    usize::BITS - (n.max(1) - 1).leading_zeros()
}

/// The box measure of the cost: the surface area plus the squared
/// diagonal, so that flat and line-like clusters (coplanar panels, point
/// lights along a street), whose area is 0, still prefer compact splits.
fn box_measure(b: &Aabb) -> f32 {
    if b.is_empty() {
        return 0.0;
    }
    b.area() + b.extent().length_squared()
}

/// Adds the subtree over `items` (≥ 1) at `depth`, reached by `bits`;
/// returns its root's index.
fn split(items: Items, depth: u32, bits: u64, out: &mut Built) -> usize {
    let at = out.nodes.len();
    if items.len() == 1 {
        let (light, bounds) = items[0];
        out.nodes.push(BuildNode {
            bounds,
            index: light as u32,
            leaf: true,
        });
        out.paths.push((light, bits, depth));
        return at;
    }
    let bounds = items[1..].iter().fold(items[0].1, |b, (_, x)| b.union(x));
    out.nodes.push(BuildNode {
        bounds,
        index: 0,
        leaf: false,
    });
    let (first, second) = partition(items, &bounds, depth);
    split(first, depth + 1, bits, out);
    let right = split(second, depth + 1, bits | (1u64 << depth), out);
    out.nodes[at].index = right as u32;
    at
}

/// Splits `items` (≥ 2) in two non-empty parts: by the least SAOH cost
/// over the binned planes of the three axes; at the median along the
/// widest axis of the centroids where no plane separates them, or where
/// the depth left must be kept for a balanced split.
fn partition(mut items: Items, bounds: &LightBounds, depth: u32) -> (Items, Items) {
    let centroids = items
        .iter()
        .fold(Aabb::EMPTY, |b, (_, x)| b.grow(x.aabb.centroid()));
    let extent = centroids.extent();
    let balanced_only = depth + ceil_log2(items.len()) >= MAX_DEPTH;
    if !balanced_only {
        if let Some((axis, plane)) = best_plane(&items, bounds, &centroids) {
            let bucket = |b: &LightBounds| bucket_of(b, &centroids, axis);
            let (first, second): (Vec<_>, Vec<_>) =
                items.into_iter().partition(|(_, b)| bucket(b) <= plane);
            return (first, second);
        }
    }
    // Median by centroid along the widest axis, ties by light index.
    let axis = extent.max_dimension();
    items.sort_by(|(i, a), (j, b)| {
        a.aabb.centroid()[axis]
            .total_cmp(&b.aabb.centroid()[axis])
            .then(i.cmp(j))
    });
    let second = items.split_off(items.len() / 2);
    (items, second)
}

fn bucket_of(b: &LightBounds, centroids: &Aabb, axis: usize) -> usize {
    let lo = centroids.min[axis];
    let width = centroids.max[axis] - lo;
    let t = (b.aabb.centroid()[axis] - lo) / width;
    ((t * BUCKETS as f32) as usize).min(BUCKETS - 1)
}

/// The axis and the last bucket of the first part of the cheapest split:
/// cost φ · M_Ω · M_A · K_r per side (Conty Estevez & Kulla 2018, §4.3: the
/// SAOH, with K_r = the node's widest extent over its extent along the
/// axis, against thin slices). `None` when no plane separates the items.
fn best_plane(
    items: &[(usize, LightBounds)],
    node: &LightBounds,
    centroids: &Aabb,
) -> Option<(usize, usize)> {
    let extent = node.aabb.extent();
    let widest = extent.max_component();
    let mut best: Option<(f32, usize, usize)> = None;
    for axis in 0..3 {
        if centroids.max[axis] <= centroids.min[axis] || extent[axis].is_nan() {
            continue;
        }
        let mut buckets: [Option<LightBounds>; BUCKETS] = [None; BUCKETS];
        for (_, b) in items {
            let k = bucket_of(b, centroids, axis);
            buckets[k] = Some(match buckets[k] {
                None => *b,
                Some(x) => x.union(b),
            });
        }
        let kr = if extent[axis] > 0.0 {
            widest / extent[axis]
        } else {
            1.0
        };
        let cost = |b: &Option<LightBounds>| {
            b.map_or(0.0, |b| {
                b.phi as f64 * b.orientation_measure() as f64 * box_measure(&b.aabb) as f64
            })
        };
        // Costs of the parts below and above each plane.
        let fold = |range: &mut dyn Iterator<Item = usize>| {
            let mut acc: Option<LightBounds> = None;
            let mut out = [0.0f64; BUCKETS];
            for k in range {
                if let Some(b) = &buckets[k] {
                    acc = Some(match acc {
                        None => *b,
                        Some(a) => a.union(b),
                    });
                }
                out[k] = cost(&acc);
            }
            out
        };
        let below = fold(&mut (0..BUCKETS));
        let above = fold(&mut (0..BUCKETS).rev());
        let occupied_below = |k: usize| buckets[..=k].iter().any(Option::is_some);
        let occupied_above = |k: usize| buckets[k + 1..].iter().any(Option::is_some);
        for k in 0..BUCKETS - 1 {
            if !(occupied_below(k) && occupied_above(k)) {
                continue;
            }
            let c = (kr as f64 * (below[k] + above[k + 1])) as f32;
            // Strictly less: the first of equal costs, in axis then plane
            // order, for a deterministic tree.
            if best.is_none_or(|(b, _, _)| c < b) {
                best = Some((c, axis, k));
            }
        }
    }
    best.map(|(_, axis, k)| (axis, k))
}

#[cfg(test)]
mod tests {
    use super::super::bounds::Cone;
    use super::*;
    use crate::math::Vec3;

    fn at(x: f32) -> LightBounds {
        LightBounds {
            aabb: Aabb {
                min: Vec3::new(x, 0.0, 0.0),
                max: Vec3::new(x, 0.0, 0.0),
            },
            phi: 1.0,
            normals: Cone::ALL,
            theta_e: std::f32::consts::FRAC_PI_2,
        }
    }

    /// Every light's path bits lead from the root to its own leaf.
    fn check(items: Vec<(usize, LightBounds)>) -> u32 {
        let n = items.len();
        let built = build(items);
        assert_eq!(built.paths.len(), n);
        assert_eq!(built.nodes.len(), 2 * n - 1);
        let mut deepest = 0;
        for &(light, bits, depth) in &built.paths {
            assert!(depth <= MAX_DEPTH);
            let mut node = 0;
            for level in 0..depth {
                assert!(!built.nodes[node].leaf);
                node = if bits >> level & 1 == 0 {
                    node + 1
                } else {
                    built.nodes[node].index as usize
                };
            }
            assert!(built.nodes[node].leaf);
            assert_eq!(built.nodes[node].index as usize, light);
            deepest = deepest.max(depth);
        }
        deepest
    }

    #[test]
    fn paths_lead_to_their_leaves_even_in_lopsided_sets() {
        // Spacing growing geometrically: each SAOH split peels off the
        // farthest few, so the depth limit must step in.
        let lopsided = check((0..400).map(|i| (i, at(1.25f32.powi(i as i32)))).collect());
        assert!(lopsided <= MAX_DEPTH);
        // All at one place: median splits, a balanced tree.
        assert_eq!(check((0..1000).map(|i| (i, at(1.0))).collect()), 10);
        assert_eq!(check(vec![(3, at(0.0))]), 0);
    }
}

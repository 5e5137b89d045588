//! A density of directions on the sphere: a quadtree over the unit square
//! of the equal-area cylindrical map, u = (cos θ + 1)/2, v = φ/2π
//! (Müller, Gross & Novák 2017, "Practical Path Guiding", the directional quadtree). Each
//! node holds the energy of its four quadrants; a quadrant is a leaf or
//! the root of a subtree. The map's Jacobian is the constant 4π, so a
//! leaf's density in solid angle is its share of the energy over its
//! area, over 4π.

use std::f32::consts::{PI, TAU};

use super::SHARE;
use crate::math::Vec3;

/// Midpoints per side of a leaf in [`DTree::gain`]'s integrals.
const GAIN_POINTS: usize = 4;

/// A quadrant holding more than this share of the tree's energy is
/// subdivided for the next iteration, one holding less is merged
/// (Müller et al. 2017, the quadtree's subdivision: ρ = 0.01).
pub const RHO: f64 = 0.01;

/// Deepest level a quadrant is subdivided to (Müller et al. 2017's limit).
pub const MAX_DEPTH: u32 = 20;

/// Records that found light a quadrant must have had to be subdivided:
/// where light was found by few paths, the density stays coarse, so that
/// it spreads over the directions near theirs instead of pointing at
/// theirs alone (a rule of ours: Müller et al. subdivide by energy alone,
/// with millions of records).
pub const MIN_SPLIT_LIT: u32 = 8;

/// One node: its four quadrants, numbered `ix + 2·iy` (ix: the u half,
/// iy: the v half).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
struct Node {
    /// The node holding each quadrant's subtree; 0 where it is a leaf
    /// (the root, node 0, is no one's child).
    child: [u32; 4],
    /// Each quadrant's share of the node's energy (kept as shares, so
    /// that a density is a product along the walk, without divisions).
    share: [f32; 4],
}

/// A quadtree of directions: the topology, and the energy that makes it
/// a density.
#[derive(Debug, Clone, PartialEq)]
pub struct DTree {
    nodes: Vec<Node>,
    /// The energy of the whole tree (0: not a density yet).
    energy: f32,
    /// Per node, each quadrant's records that found light (what
    /// [`Self::refined`] may subdivide; empty where not learned).
    lit: Vec<[u32; 4]>,
    /// Per node, each leaf quadrant's squared energy over the tree's
    /// squared energy, less what the records' noise adds to it (S² − Σe²
    /// for records e summing to S: the square of the mean, unbiased up to
    /// a factor (N − 1)/N); empty where not learned ([`Self::gain`]).
    square: Vec<[f32; 4]>,
}

impl Default for DTree {
    /// The root alone: four leaves, no energy.
    fn default() -> Self {
        Self {
            nodes: vec![Node::default()],
            energy: 0.0,
            lit: Vec::new(),
            square: Vec::new(),
        }
    }
}

/// The point of the unit square that `d` (unit, world) maps to.
pub fn to_square(d: Vec3) -> [f32; 2] {
    let u = ((d.z + 1.0) * 0.5).clamp(0.0, 1.0);
    let phi = d.y.atan2(d.x);
    let v = if phi < 0.0 { phi + TAU } else { phi } / TAU;
    [u, v.clamp(0.0, 1.0)]
}

/// The unit direction at point `s` of the unit square.
pub fn from_square(s: [f32; 2]) -> Vec3 {
    let z = 2.0 * s[0] - 1.0;
    let r = (1.0 - z * z).max(0.0).sqrt();
    let (sin, cos) = (TAU * s[1]).sin_cos();
    Vec3::new(r * cos, r * sin, z)
}

/// The quadrant of `s` in a node, and `s` within it.
#[inline]
fn quadrant(s: [f32; 2]) -> (usize, [f32; 2]) {
    let ix = (s[0] >= 0.5) as usize;
    let iy = (s[1] >= 0.5) as usize;
    let inner = [
        (2.0 * s[0] - ix as f32).clamp(0.0, 1.0),
        (2.0 * s[1] - iy as f32).clamp(0.0, 1.0),
    ];
    (ix + 2 * iy, inner)
}

/// Picks one of two with weights `a` and `b` by `u`, and `u` rescaled to
/// [0, 1) within the pick.
#[inline]
fn pick(a: f32, b: f32, u: f32) -> (usize, f32) {
    let p = a / (a + b);
    if u < p {
        (0, (u / p).min(1.0 - f32::EPSILON))
    } else {
        (1, ((u - p) / (1.0 - p)).clamp(0.0, 1.0 - f32::EPSILON))
    }
}

impl DTree {
    /// How many leaf slots it has: four per node (inner quadrants' slots
    /// stay unused), the size of its statistics.
    pub fn slots(&self) -> usize {
        4 * self.nodes.len()
    }

    /// The total energy.
    pub fn energy(&self) -> f32 {
        self.energy
    }

    /// The slot of the leaf quadrant holding direction `d`.
    pub fn slot(&self, d: Vec3) -> u32 {
        let mut s = to_square(d);
        let mut node = 0;
        loop {
            let (q, inner) = quadrant(s);
            let child = self.nodes[node].child[q];
            if child == 0 {
                return (4 * node + q) as u32;
            }
            node = child as usize;
            s = inner;
        }
    }

    /// The density in solid angle of [`Self::sample`] drawing `d`; 0 with
    /// no energy.
    pub fn pdf(&self, d: Vec3) -> f32 {
        if self.energy <= 0.0 {
            return 0.0;
        }
        let mut s = to_square(d);
        let mut node = 0;
        let mut p = 1.0 / (4.0 * PI);
        loop {
            let n = &self.nodes[node];
            let (q, inner) = quadrant(s);
            p *= 4.0 * n.share[q];
            if n.child[q] == 0 || p == 0.0 {
                return p;
            }
            node = n.child[q] as usize;
            s = inner;
        }
    }

    /// A direction drawn in proportion to the energy, with `u`, and its
    /// density in solid angle; `None` with no energy.
    pub fn sample(&self, u: [f32; 2]) -> Option<(Vec3, f32)> {
        if self.energy <= 0.0 {
            return None;
        }
        let [mut u0, mut u1] = u;
        let (mut lo, mut size) = ([0.0f32, 0.0f32], 1.0f32);
        let mut node = 0;
        let mut p = 1.0 / (4.0 * PI);
        loop {
            let n = &self.nodes[node];
            // The u half by its marginal, then the v half within it.
            let s = &n.share;
            let (ix, r0) = pick(s[0] + s[2], s[1] + s[3], u0);
            let (iy, r1) = pick(s[ix], s[ix + 2], u1);
            let q = ix + 2 * iy;
            (u0, u1) = (r0, r1);
            p *= 4.0 * s[q];
            size *= 0.5;
            lo = [lo[0] + size * ix as f32, lo[1] + size * iy as f32];
            if n.child[q] == 0 {
                let d = from_square([lo[0] + size * u0, lo[1] + size * u1]);
                return (p > 0.0 && p.is_finite()).then_some((d, p));
            }
            node = n.child[q] as usize;
        }
    }

    /// The same tree with each leaf's energy from `stats`, the sum of its
    /// records' squares from `square` and its records that found light
    /// from `lit` (all indexed by [`Self::slot`]), and each inner
    /// quadrant's the sums below it.
    pub fn with_energy(&self, stats: &[f64], square: &[f64], lit: &[u64]) -> Self {
        let mut nodes = self.nodes.clone();
        // Each node's quadrants' energy; children come after their
        // parents, so fill from the last node back.
        let mut sums = vec![[0.0f64; 4]; nodes.len()];
        let mut found = vec![[0u32; 4]; nodes.len()];
        for i in (0..nodes.len()).rev() {
            for q in 0..4 {
                let c = nodes[i].child[q] as usize;
                (sums[i][q], found[i][q]) = if c == 0 {
                    let l = lit.get(4 * i + q).copied().unwrap_or(0);
                    let e = stats.get(4 * i + q).copied().unwrap_or(0.0).max(0.0);
                    (e, l.min(u64::from(u32::MAX)) as u32)
                } else {
                    let l = found[c].iter().fold(0u32, |a, &b| a.saturating_add(b));
                    (sums[c].iter().sum(), l)
                };
            }
        }
        for (n, s) in nodes.iter_mut().zip(&sums) {
            let total: f64 = s.iter().sum();
            n.share = if total > 0.0 {
                s.map(|e| (e / total) as f32)
            } else {
                [0.0; 4]
            };
        }
        let total: f64 = sums[0].iter().sum();
        let squares = (0..nodes.len())
            .map(|i| {
                std::array::from_fn(|q| {
                    let e = sums[i][q];
                    let e2 = square.get(4 * i + q).copied().unwrap_or(0.0);
                    if nodes[i].child[q] == 0 && total > 0.0 {
                        ((e * e - e2).max(0.0) / (total * total)) as f32
                    } else {
                        0.0
                    }
                })
            })
            .collect();
        let energy = total as f32;
        Self {
            nodes,
            energy: if energy.is_finite() { energy } else { 0.0 },
            lit: found,
            square: squares,
        }
    }

    /// The topology for the next iteration, without energy: quadrants
    /// holding more than [`RHO`] of the energy are subdivided, the others
    /// are leaves; a leaf subdivided goes on as deep as its energy, spread
    /// evenly over its quarters, stays above [`RHO`] (Müller et al. 2017,
    /// the quadtree's subdivision).
    pub fn refined(&self) -> Self {
        let mut out = vec![Node::default()];
        if self.energy > 0.0 {
            self.refine_into(Some(0), 0, 1, 1.0, &mut out);
        }
        Self {
            nodes: out,
            energy: 0.0,
            lit: Vec::new(),
            square: Vec::new(),
        }
    }

    /// Refines node `from` (`None`: a leaf of this tree, its energy spread
    /// evenly), holding share `of` of the energy, into `to`.
    fn refine_into(
        &self,
        from: Option<usize>,
        to: usize,
        depth: u32,
        of: f64,
        out: &mut Vec<Node>,
    ) {
        for q in 0..4 {
            let (share, child, lit) = match from {
                Some(f) => {
                    let n = &self.nodes[f];
                    let c = n.child[q] as usize;
                    let lit = self.lit.get(f).map_or(u32::MAX, |l| l[q]);
                    (of * f64::from(n.share[q]), (c != 0).then_some(c), lit)
                }
                None => (of * 0.25, None, u32::MAX),
            };
            if depth >= MAX_DEPTH || share <= RHO || lit < MIN_SPLIT_LIT {
                continue;
            }
            let at = out.len();
            out.push(Node::default());
            out[to].child[q] = at as u32;
            self.refine_into(child, at, depth + 1, share, out);
        }
    }

    /// The largest density in solid angle over its leaves (0 with no
    /// energy).
    pub fn peak(&self) -> f32 {
        if self.energy <= 0.0 {
            return 0.0;
        }
        let mut peak = 0.0f32;
        let mut stack = vec![(0usize, 1.0 / (4.0 * PI))];
        while let Some((i, p)) = stack.pop() {
            let n = &self.nodes[i];
            for q in 0..4 {
                let pq = p * 4.0 * n.share[q];
                match n.child[q] {
                    0 => peak = peak.max(pq),
                    c => stack.push((c as usize, pq)),
                }
            }
        }
        peak
    }

    /// What guiding is predicted to leave of a diffuse bounce's variance
    /// at a surface facing `side` (`super::side`): the second moment of
    /// the estimate of ∫L·cos/π dω when the bounce is drawn from the
    /// mixture (1 − [`SHARE`])·cos/π + SHARE·guide, over its second moment
    /// under cosine sampling alone. L² is each leaf's squared energy less
    /// its records' noise (`square`): squared as learned, a density from a
    /// few records looks peaked where the light is flat (on the Cornell
    /// box's walls it predicted a gain of 0.63 where 0.96 was measured).
    /// The normal is the side's axis, and each leaf is integrated by its
    /// [`GAIN_POINTS`]² midpoints. 1 or more where guiding would not
    /// lower the variance; `None` with no energy, for media, or before
    /// the tree learned its squares.
    pub fn gain(&self, side: usize) -> Option<f32> {
        // The last side is media's.
        if self.energy <= 0.0 || side >= super::SIDES - 1 || self.square.len() != self.nodes.len() {
            return None;
        }
        let (axis, sign) = (side / 2, if side.is_multiple_of(2) { 1.0 } else { -1.0 });
        let (mut cosine, mut mixture) = (0.0f64, 0.0f64);
        let mut stack = vec![(0usize, [0.0f32, 0.0f32], 1.0f32, 1.0f32)];
        let n = GAIN_POINTS as f32;
        while let Some((i, lo, size, share)) = stack.pop() {
            let half = 0.5 * size;
            let node = &self.nodes[i];
            for q in 0..4 {
                let lo = [
                    lo[0] + half * (q & 1) as f32,
                    lo[1] + half * (q >> 1) as f32,
                ];
                let sq = share * node.share[q];
                if node.child[q] != 0 {
                    stack.push((node.child[q] as usize, lo, half, sq));
                    continue;
                }
                // The leaf's solid angle, the guide's density there, the
                // light's debiased square, and each point's solid angle.
                let area = half * half * 4.0 * PI;
                let g = sq / area;
                let l2 = self.square[i][q] / (area * area);
                if l2 <= 0.0 {
                    continue;
                }
                let dw = area / (n * n);
                for a in 0..GAIN_POINTS {
                    for b in 0..GAIN_POINTS {
                        let d = from_square([
                            lo[0] + half * (a as f32 + 0.5) / n,
                            lo[1] + half * (b as f32 + 0.5) / n,
                        ]);
                        let cos = sign * d.to_array()[axis];
                        if cos <= 0.0 {
                            continue;
                        }
                        let f2 = l2 * cos * cos;
                        cosine += f64::from(f2 / (cos / PI) * dw);
                        mixture += f64::from(f2 / ((1.0 - SHARE) * cos / PI + SHARE * g) * dw);
                    }
                }
            }
        }
        (cosine > 0.0).then(|| (mixture / cosine) as f32)
    }

    /// Quadrants in the tree (leaves), for reports and tests.
    pub fn leaves(&self) -> usize {
        self.nodes
            .iter()
            .map(|n| n.child.iter().filter(|&&c| c == 0).count())
            .sum()
    }

    /// Every leaf quadrant: its corner, side and probability.
    #[cfg(test)]
    pub(super) fn leaf_squares(&self) -> Vec<([f64; 2], f64, f64)> {
        let mut out = Vec::new();
        self.leaves_below(0, [0.0, 0.0], 1.0, 1.0, &mut out);
        out
    }

    #[cfg(test)]
    fn leaves_below(
        &self,
        node: usize,
        lo: [f64; 2],
        size: f64,
        p: f64,
        out: &mut Vec<([f64; 2], f64, f64)>,
    ) {
        let n = &self.nodes[node];
        let half = 0.5 * size;
        for q in 0..4 {
            let lo = [
                lo[0] + half * (q & 1) as f64,
                lo[1] + half * (q >> 1) as f64,
            ];
            let pq = p * f64::from(n.share[q]);
            match n.child[q] {
                0 => out.push((lo, half, pq)),
                c => self.leaves_below(c as usize, lo, half, pq, out),
            }
        }
    }
}

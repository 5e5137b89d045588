//! Many-light sampling by a light hierarchy (issue 40): a binary BVH over
//! the lights with a place, each node bounding its lights' positions,
//! power and directions of emission, traversed per shading point with
//! one random number, each step choosing a child in proportion to its
//! importance at the point (Conty Estevez & Kulla 2018, "Importance
//! Sampling of Many Lights with Adaptive Tree Splitting", §4; pbrt-v4's
//! `BVHLightSampler`, §12.6.3 — without the adaptive splitting).
//!
//! Lights at infinity (directional, constant, environment map — the
//! directional light too, which `Light::is_infinite` leaves out as rays
//! never meet it, but which has no place to bound) stay out of the tree.
//! Each has the weight Φ/R² (its power over the scene's squared radius:
//! the irradiance it gives the scene, up to a constant), the tree the
//! importance of its root at the point, and one of them is chosen in
//! proportion. pbrt-v4 gives each light at infinity and the tree equal
//! shares instead; at night that spends half the samples on a sky a
//! hundred-thousandth as bright as the lamps. Where no light can be
//! chosen, `sample` returns `None` and `pmf` 0. Lights with zero or
//! non-finite power are never chosen.
//!
//! `sample` and `pmf` walk the same nodes with the same arithmetic (`pmf`
//! follows the light's path from the root, kept as bits), so the
//! probability `pmf` reports is bit for bit the one `sample` returned: MIS
//! weights are exact. Neither allocates.

mod bounds;
mod build;

use bounds::{light_bounds, NodeBounds};

use super::Light;
use crate::geometry::Shape;
use crate::math::Vec3;

/// The largest f32 below 1: rescaled random numbers stay in [0, 1).
const ONE_MINUS_EPSILON: f32 = 1.0 - f32::EPSILON / 2.0;

/// A node: an interior node's first child follows it and `index` is its
/// second child; a leaf's `index` is its light.
#[derive(Debug, Clone, Copy, PartialEq)]
struct Node {
    bounds: NodeBounds,
    index: u32,
    leaf: bool,
}

/// Where a light is in the choice.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Place {
    /// Never chosen (no power, or an area light without a shape).
    Out,
    /// At infinity: one of the fixed shares.
    Infinite,
    /// In the tree: the turns from the root (bit k: the second child at
    /// depth k) and the depth of its leaf.
    Tree { bits: u64, depth: u32 },
}

/// The scene's light hierarchy.
#[derive(Debug, Clone, PartialEq)]
pub struct LightHierarchy {
    nodes: Vec<Node>,
    /// The lights at infinity with power, in scene order, with their
    /// weights Φ/R², and the sum of the weights.
    infinite: Vec<(u32, f32)>,
    infinite_weight: f32,
    /// Per light of the scene.
    places: Vec<Place>,
}

impl LightHierarchy {
    /// The hierarchy over `lights` (area lights' shapes in `shapes`);
    /// `power[i]`: light i's radiant power in W (as `LightChoice::new`
    /// gets it; a missing power counts as 0); `scene_radius`: the radius
    /// of the scene's bounding sphere.
    pub fn new(lights: &[Light], shapes: &[Shape], power: &[f32], scene_radius: f32) -> Self {
        let r2 = (scene_radius * scene_radius).max(f32::MIN_POSITIVE);
        let mut places = vec![Place::Out; lights.len()];
        let mut infinite = Vec::new();
        let mut items = Vec::new();
        for (i, light) in lights.iter().enumerate() {
            let w = power.get(i).copied().unwrap_or(0.0);
            if !(w > 0.0 && w.is_finite()) {
                continue;
            }
            match light {
                Light::Directional(_) | Light::Constant(_) | Light::EnvMap(_) => {
                    places[i] = Place::Infinite;
                    infinite.push((i as u32, (w / r2).min(f32::MAX)));
                }
                _ => {
                    if let Some(b) = light_bounds(light, shapes, w) {
                        items.push((i, b));
                    }
                }
            }
        }
        let built = build::build(items);
        for &(light, bits, depth) in &built.paths {
            places[light] = Place::Tree { bits, depth };
        }
        Self {
            nodes: built
                .nodes
                .iter()
                .map(|n| Node {
                    bounds: n.bounds.compact(),
                    index: n.index,
                    leaf: n.leaf,
                })
                .collect(),
            infinite_weight: infinite.iter().map(|&(_, w)| w).sum::<f32>().min(f32::MAX),
            infinite,
            places,
        }
    }

    /// Whether no light can ever be chosen.
    pub fn is_empty(&self) -> bool {
        self.nodes.is_empty() && self.infinite.is_empty()
    }

    /// Number of lights in the tree.
    pub fn tree_len(&self) -> usize {
        self.places
            .iter()
            .filter(|p| matches!(p, Place::Tree { .. }))
            .count()
    }

    /// The normal the importance reads: unit, or none.
    #[inline]
    fn clean_normal(n: Option<Vec3>) -> Option<Vec3> {
        n.map(Vec3::normalize).filter(|n| n.is_finite())
    }

    /// The tree's weight at `p` (its root's importance; 0 without a
    /// tree) and the sum of all weights.
    #[inline]
    fn shares(&self, p: Vec3, n: Option<Vec3>) -> (f32, f32) {
        let tree = self
            .nodes
            .first()
            .map_or(0.0, |root| root.bounds.importance(p, n));
        (tree, (tree + self.infinite_weight).min(f32::MAX))
    }

    /// The probabilities of interior node `at`'s two children at `p`, and
    /// the second child's index.
    ///
    /// When neither child has importance, by their power: a node's bounds
    /// are looser than its children's (its box fills a wider cone from
    /// `p`), so it may pass the cone test where both fail. Such a step
    /// ends at a light that cannot reach `p` — a wasted sample, as `None`
    /// would be — but keeps the probabilities summing to 1.
    #[inline]
    fn children(&self, at: usize, p: Vec3, n: Option<Vec3>) -> (f32, f32, usize) {
        let second = self.nodes[at].index as usize;
        let (first, second_node) = (&self.nodes[at + 1].bounds, &self.nodes[second].bounds);
        let (mut a, mut b) = (first.importance(p, n), second_node.importance(p, n));
        if !(a > 0.0 || b > 0.0) {
            (a, b) = (first.phi, second_node.phi);
        }
        // a/(a + b) without overflow: exactly 1 and 0 when one is 0.
        (1.0 / (1.0 + b / a), 1.0 / (1.0 + a / b), second)
    }

    /// A light for next-event estimation at `p` with `u` ∈ [0, 1): its
    /// index in the scene's lights and the probability it was chosen with.
    /// `None` when no light can be chosen. `n`: the shading point's normal
    /// (any length, either orientation: the cosine bound takes |cos θ|, so
    /// light from behind keeps its share for transmission); `None` in a
    /// medium.
    pub fn sample(&self, p: Vec3, n: Option<Vec3>, u: f32) -> Option<(usize, f32)> {
        if !p.is_finite() {
            return None;
        }
        let n = Self::clean_normal(n);
        let (tree, total) = self.shares(p, n);
        if total <= 0.0 {
            return None;
        }
        // The lights at infinity first, then the tree.
        let mut x = u.clamp(0.0, ONE_MINUS_EPSILON) * total;
        for (k, &(i, w)) in self.infinite.iter().enumerate() {
            let last = k + 1 == self.infinite.len() && tree <= 0.0;
            if x < w || last {
                return Some((i as usize, w / total));
            }
            x -= w;
        }
        let mut u = (x / tree).clamp(0.0, ONE_MINUS_EPSILON);
        let share = tree / total;
        let mut pmf = share;
        let mut at = 0;
        loop {
            let node = &self.nodes[at];
            if node.leaf {
                return Some((node.index as usize, pmf));
            }
            let (first, second, second_at) = self.children(at, p, n);
            if u < first {
                u = (u / first).min(ONE_MINUS_EPSILON);
                pmf *= first;
                at += 1;
            } else {
                u = ((u - first) / second).min(ONE_MINUS_EPSILON);
                pmf *= second;
                at = second_at;
            }
        }
    }

    /// The probability that [`Self::sample`] at `p` (normal `n`) chooses
    /// `light`: bit for bit the one it returns with it.
    pub fn pmf(&self, p: Vec3, n: Option<Vec3>, light: usize) -> f32 {
        let Some(&place) = self.places.get(light) else {
            return 0.0;
        };
        if place == Place::Out || !p.is_finite() {
            return 0.0;
        }
        let n = Self::clean_normal(n);
        let (tree, total) = self.shares(p, n);
        if total <= 0.0 {
            return 0.0;
        }
        let Place::Tree { bits, depth } = place else {
            let w = self.infinite.iter().find(|&&(i, _)| i as usize == light);
            return w.map_or(0.0, |&(_, w)| w / total);
        };
        if tree <= 0.0 {
            return 0.0;
        }
        let share = tree / total;
        let mut pmf = share;
        let mut at = 0;
        for level in 0..depth {
            if self.nodes[at].leaf {
                break;
            }
            let (first, second, second_at) = self.children(at, p, n);
            if bits >> level & 1 == 0 {
                pmf *= first;
                at += 1;
            } else {
                pmf *= second;
                at = second_at;
            }
        }
        debug_assert!(self.nodes[at].leaf && self.nodes[at].index as usize == light);
        pmf
    }
}

#[cfg(test)]
mod tests;

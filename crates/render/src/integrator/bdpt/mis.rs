//! Multiple importance sampling weights of the strategies that build one
//! path, by the power heuristic (β = 2), with Veach's ratio recurrence
//! (1997, §10.2.1): the density of the strategy with one more light
//! vertex is the current one times p_light(x)/p_camera(x) at the vertex
//! that changes sides, so every strategy's relative density follows from
//! the stored `pdf_fwd`/`pdf_rev` in one pass over the path, without
//! re-evaluating any BSDF. Delta vertices cannot be connected: strategies
//! that would connect at one count nothing, and their densities (stored
//! as 0) count as 1 in the ratios.

use super::vertex::Vertex;

/// The densities that change at a connection (Veach's p← at the two
/// endpoints and their predecessors), and the endpoints that replace the
/// subpaths' own (a light point or lens point sampled for the connection).
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Connection {
    pub light_last_rev: f32,
    pub light_prev_rev: f32,
    pub camera_last_rev: f32,
    pub camera_prev_rev: f32,
    /// A light point sampled for s = 1: its origin density.
    pub light_origin: Option<f32>,
    /// The light is a delta (position or direction): s = 0 is impossible.
    pub delta_light: bool,
    /// The light is at infinity: s = 1, t = 1 is not a strategy here.
    pub light_at_infinity: bool,
}

#[inline]
fn remap(p: f32) -> f32 {
    if p != 0.0 {
        p
    } else {
        1.0
    }
}

/// The weight of strategy (s, t) for the path its subpaths make with
/// connection `c`. Strategies with fewer than `min_s` light vertices
/// cannot build the path (a re-emission on the light subpath) and are
/// left out.
///
/// `share`: the light subpaths' origin density of the path's light over
/// next-event estimation's, where s = 1 chooses its light at the vertex
/// next to it by the light hierarchy and the light subpaths by the
/// cluster (1 where both choose alike). The densities stored on the
/// vertices are those of the strategy at hand, so the ratio to a strategy
/// on the other side of s = 1 ↔ s = 2 takes `share` once: ×share from
/// s ≤ 1 to s ≥ 2, ÷share to s = 1 alone from s ≥ 2 (s = 0 depends on no
/// light choice, and the two factors cancel on the way there).
pub(super) fn weight<const K: usize>(
    light: &[Vertex<K>],
    camera: &[Vertex<K>],
    s: usize,
    t: usize,
    c: &Connection,
    min_s: usize,
    share: f32,
) -> f32 {
    let camera_rev = |i: usize| {
        if i + 1 == t {
            c.camera_last_rev
        } else if i + 2 == t {
            c.camera_prev_rev
        } else {
            camera[i].pdf_rev
        }
    };
    let camera_delta = |i: usize| i + 1 != t && camera[i].delta;
    let light_rev = |i: usize| {
        if i + 1 == s {
            c.light_last_rev
        } else if i + 2 == s {
            c.light_prev_rev
        } else {
            light[i].pdf_rev
        }
    };
    let light_fwd = |i: usize| match (i, c.light_origin) {
        (0, Some(p)) => p,
        _ => light[i].pdf_fwd,
    };
    let light_delta = |i: usize| i + 1 != s && light[i].delta;

    let mut sum = 0.0f32;
    // More light vertices: camera vertices move to the light subpath.
    let mut r = 1.0f32;
    for i in (1..t).rev() {
        r *= remap(camera_rev(i)) / remap(camera[i].pdf_fwd);
        // (1, 1) from a light at infinity is not a strategy here.
        let excluded = s + t == 2 && i == 1 && c.light_at_infinity;
        // Strategy s + t − i: past s = 1 its light comes from a subpath.
        let k = s + t - i;
        let rk = if s <= 1 && k >= 2 { r * share } else { r };
        if !camera_delta(i) && !camera_delta(i - 1) && !excluded {
            sum += rk * rk;
        }
    }
    // Fewer light vertices: light vertices move to the camera subpath.
    let mut r = 1.0f32;
    for i in (0..s).rev() {
        if i < min_s {
            break;
        }
        r *= remap(light_rev(i)) / remap(light_fwd(i));
        let before_delta = if i > 0 {
            light_delta(i - 1)
        } else {
            c.delta_light
        };
        // Strategy i: s = 1 chose its light by next-event estimation.
        let ri = if s >= 2 && i == 1 { r / share } else { r };
        if !light_delta(i) && !before_delta {
            sum += ri * ri;
        }
    }
    1.0 / (1.0 + sum)
}

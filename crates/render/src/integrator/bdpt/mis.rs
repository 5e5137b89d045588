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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::integrator::bdpt::vertex::Kind;
    use crate::math::Vec3;
    use crate::test_rng::Rng;
    use scotopia_color::SampledSpectrum;

    /// One path x₀ (on the light) … x₄ (the lens) with made-up densities:
    /// `from_light[i]` of x_i drawn from the light's side (for x₀ the
    /// light subpaths' origin density), `from_camera[i]` from the
    /// camera's side (for x₀ the density of the camera path hitting it),
    /// and `nee` the origin density of next-event estimation's choice.
    /// The weight of each strategy, with the densities its subpaths would
    /// store and its connection's, must be p_s²/Σ_k p_k² with p_k the
    /// product of the densities strategy k draws the path with.
    #[test]
    fn the_weights_are_the_power_heuristic_of_the_strategies_true_densities() {
        let n = 5;
        let mut rng = Rng(3);
        for _ in 0..200 {
            let mut draw = || 0.05 + 2.0 * rng.next();
            let from_light: Vec<f32> = (0..n).map(|_| draw()).collect();
            let from_camera: Vec<f32> = (0..n).map(|_| draw()).collect();
            let nee = draw();
            let share = from_light[0] / nee;
            // Strategy k: light vertices x₀…x_{k−1}, camera vertices the rest;
            // s = 1 draws x₀ by next-event estimation.
            let density = |k: usize| -> f64 {
                (0..n)
                    .map(|i| {
                        let p = if i >= k {
                            from_camera[i]
                        } else if i == 0 && k == 1 {
                            nee
                        } else {
                            from_light[i]
                        };
                        p as f64
                    })
                    .product()
            };
            let total: f64 = (0..n).map(|k| density(k).powi(2)).sum();
            let vertex = |fwd: f32, rev: f32| {
                let mut v =
                    Vertex::<1>::new(Kind::Surface, Vec3::ZERO, SampledSpectrum::splat(1.0));
                v.pdf_fwd = fwd;
                v.pdf_rev = rev;
                v
            };
            let mut sum = 0.0;
            for s in 0..n {
                let t = n - s;
                let light: Vec<_> = (0..s)
                    .map(|i| vertex(from_light[i], from_camera[i]))
                    .collect();
                let camera: Vec<_> = (0..t)
                    .map(|j| vertex(from_camera[n - 1 - j], from_light[n - 1 - j]))
                    .collect();
                let mut c = Connection::default();
                if s >= 1 {
                    c.light_last_rev = from_camera[s - 1];
                }
                if s >= 2 {
                    c.light_prev_rev = from_camera[s - 2];
                }
                // The camera vertex that meets the light side, and the one
                // before it; for s = 0 x₀ is the light the camera path hit,
                // whose density for s = 1 is next-event estimation's.
                c.camera_last_rev = if s == 0 { nee } else { from_light[s] };
                c.camera_prev_rev = from_light.get(s + 1).copied().unwrap_or(0.0);
                if s == 1 {
                    c.light_origin = Some(nee);
                }
                let w = weight(&light, &camera, s, t, &c, 0, share) as f64;
                let expected = density(s).powi(2) / total;
                assert!(
                    (w - expected).abs() < 1e-4,
                    "s = {s}: {w} against {expected}"
                );
                sum += w;
            }
            assert!((sum - 1.0).abs() < 1e-4, "Σ w = {sum}");
        }
    }
}

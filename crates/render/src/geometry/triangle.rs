//! The watertight ray–triangle test of Woop, Benthin & Wald 2013,
//! "Watertight Ray/Triangle Intersection" (JCGT 2(1)): no ray passes between
//! two triangles that share an edge.

use crate::math::{Ray, Vec3};

/// Per-ray precomputation: the axis permutation and shear that make the ray
/// run along +z (Woop et al. 2013, §3).
#[derive(Debug, Clone, Copy)]
pub struct RayShear {
    kx: usize,
    ky: usize,
    kz: usize,
    sx: f32,
    sy: f32,
    sz: f32,
}

impl RayShear {
    #[inline]
    pub fn new(ray: &Ray) -> Self {
        let kz = ray.d.abs().max_dimension();
        let mut kx = (kz + 1) % 3;
        let mut ky = (kx + 1) % 3;
        // Keep the winding: swap when the ray points down the chosen axis.
        if ray.d[kz] < 0.0 {
            std::mem::swap(&mut kx, &mut ky);
        }
        Self {
            kx,
            ky,
            kz,
            sx: ray.d[kx] / ray.d[kz],
            sy: ray.d[ky] / ray.d[kz],
            sz: 1.0 / ray.d[kz],
        }
    }

    /// The permuted axes (kx, ky, kz), for wide forms of the test.
    #[inline]
    pub fn axes(&self) -> [usize; 3] {
        [self.kx, self.ky, self.kz]
    }

    /// The shear (sx, sy, sz), for wide forms of the test.
    #[inline]
    pub fn shear(&self) -> [f32; 3] {
        [self.sx, self.sy, self.sz]
    }
}

/// A hit on a triangle: distance and barycentric weights of (p0, p1, p2).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TriangleHit {
    pub t: f32,
    pub b: [f32; 3],
}

/// Intersects the triangle (p0, p1, p2) with `ray` in (0, t_max).
#[inline]
pub fn intersect_triangle(
    ray: &Ray,
    s: &RayShear,
    p0: Vec3,
    p1: Vec3,
    p2: Vec3,
    t_max: f32,
) -> Option<TriangleHit> {
    // Vertices relative to the origin, sheared so the ray is the +z axis.
    // As 4-arrays indexed by `k & 3`: a plain index, where `Vec3[k]` is a
    // branch per component (nine per test).
    let rel = |p: Vec3| {
        let d = p - ray.o;
        [d.x, d.y, d.z, 0.0]
    };
    let (a, b, c) = (rel(p0), rel(p1), rel(p2));
    let (kx, ky, kz) = (s.kx & 3, s.ky & 3, s.kz & 3);
    let ax = a[kx] - s.sx * a[kz];
    let ay = a[ky] - s.sy * a[kz];
    let bx = b[kx] - s.sx * b[kz];
    let by = b[ky] - s.sy * b[kz];
    let cx = c[kx] - s.sx * c[kz];
    let cy = c[ky] - s.sy * c[kz];
    let sheared = [ax, ay, bx, by, cx, cy];

    // Scaled barycentrics: 2D edge functions, in f64 when one is exactly 0
    // (an edge through the ray), so the shared edge decides consistently.
    let mut u = cx * by - cy * bx;
    let mut v = ax * cy - ay * cx;
    let mut w = bx * ay - by * ax;
    if u == 0.0 || v == 0.0 || w == 0.0 {
        let (ax, ay, bx, by, cx, cy) = (
            ax as f64, ay as f64, bx as f64, by as f64, cx as f64, cy as f64,
        );
        u = (cx * by - cy * bx) as f32;
        v = (ax * cy - ay * cx) as f32;
        w = (bx * ay - by * ax) as f32;
    }
    if (u < 0.0 || v < 0.0 || w < 0.0) && (u > 0.0 || v > 0.0 || w > 0.0) {
        return None;
    }
    let det = u + v + w;
    if det == 0.0 {
        return None;
    }

    // Scaled distance, compared without dividing (Woop et al. 2013, §3).
    let az = s.sz * a[kz];
    let bz = s.sz * b[kz];
    let cz = s.sz * c[kz];
    let t_scaled = u * az + v * bz + w * cz;
    // The edge functions grow as length², the scaled distance as length³:
    // beyond ~10¹² it overflows f32 (and below ~10⁻¹² it underflows), so
    // such a scene's test is finished in f64.
    if !(t_scaled.is_normal() && det.is_normal()) {
        return finish_f64(sheared, [u, v, w], [az, bz, cz], t_max);
    }
    if (det < 0.0 && (t_scaled >= 0.0 || t_scaled < t_max * det))
        || (det > 0.0 && (t_scaled <= 0.0 || t_scaled > t_max * det))
    {
        return None;
    }
    let inv = 1.0 / det;
    let t = t_scaled * inv;
    if !(t > 0.0 && t < t_max)
        || t as f64 <= t_error_bound(sheared, [az, bz, cz], [u, v, w], inv as f64)
    {
        return None;
    }
    Some(TriangleHit {
        t,
        b: [u * inv, v * inv, w * inv],
    })
}

/// γₙ = nε / (1 − nε), ε = 2⁻²⁴: the bound on the relative error of n
/// f32 operations (Pharr, Jakob & Humphreys, *Physically Based Rendering*,
/// 4th ed., §6.8.1, eq. 6.41; Higham 2002).
fn gamma(n: f64) -> f64 {
    let e = f32::EPSILON as f64 * 0.5;
    n * e / (1.0 - n * e)
}

/// A conservative bound on the error of the test's distance t: a hit
/// closer than this may be on the wrong side of the origin (a ray leaving
/// the surface it starts on finds that surface again). Pharr, Jakob &
/// Humphreys, PBR 4th ed., §6.8.4 ("Conservative Ray–Triangle
/// Intersection"): the sheared coordinates carry γ₅ (x, y) and γ₃ (z)
/// errors, the edge functions δe, the scaled distance γ₃ maxE maxZ +
/// δe maxZ + δz maxE, and 1/det a factor 3. Evaluated in f64 (the f32
/// products overflow at scales where the test itself finishes in f64).
/// `xy`: (ax, ay, bx, by, cx, cy); `z`: the scaled z's; `e`: the edge
/// functions; `inv`: 1/det.
#[cold]
fn t_error_bound(xy: [f32; 6], z: [f32; 3], e: [f32; 3], inv: f64) -> f64 {
    let max3 = |a: f32, b: f32, c: f32| a.abs().max(b.abs()).max(c.abs()) as f64;
    let max_x = max3(xy[0], xy[2], xy[4]);
    let max_y = max3(xy[1], xy[3], xy[5]);
    let max_z = max3(z[0], z[1], z[2]);
    let max_e = max3(e[0], e[1], e[2]);
    let delta_x = gamma(5.0) * (max_x + max_z);
    let delta_y = gamma(5.0) * (max_y + max_z);
    let delta_z = gamma(3.0) * max_z;
    let delta_e = 2.0 * (gamma(2.0) * max_x * max_y + delta_y * max_x + delta_x * max_y);
    3.0 * (gamma(3.0) * max_e * max_z + delta_e * max_z + delta_z * max_e) * inv.abs()
}

/// The end of [`intersect_triangle`] in f64, for edge functions and
/// distances beyond f32's range.
#[cold]
fn finish_f64(xy: [f32; 6], uvw: [f32; 3], z: [f32; 3], t_max: f32) -> Option<TriangleHit> {
    let [u, v, w] = uvw.map(f64::from);
    let det = u + v + w;
    let t = (u * z[0] as f64 + v * z[1] as f64 + w * z[2] as f64) / det;
    if !(t > 0.0 && t < t_max as f64) || t <= t_error_bound(xy, z, uvw, 1.0 / det) {
        return None;
    }
    let b = [u / det, v / det, w / det].map(|x| x as f32);
    Some(TriangleHit { t: t as f32, b })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn tri() -> (Vec3, Vec3, Vec3) {
        (
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        )
    }

    #[test]
    fn hits_at_scales_beyond_f32_cubes() {
        // At 10¹⁴ the scaled distance (length³) overflows f32, at 10⁻¹⁴
        // it underflows: the f64 finish gives the same t and barycentrics.
        for s in [1e-14f32, 1e14] {
            let (p0, p1, p2) = tri();
            let ray = Ray::new(Vec3::new(0.25, 0.5, 2.0) * s, Vec3::new(0.0, 0.0, -1.0));
            let h = intersect_triangle(
                &ray,
                &RayShear::new(&ray),
                p0 * s,
                p1 * s,
                p2 * s,
                f32::INFINITY,
            )
            .unwrap_or_else(|| panic!("scale {s:e}: missed"));
            assert!((h.t / (2.0 * s) - 1.0).abs() < 1e-5, "{s:e}: {h:?}");
            assert!(
                (h.b[1] - 0.25).abs() < 1e-5 && (h.b[2] - 0.5).abs() < 1e-5,
                "{h:?}"
            );
        }
    }

    #[test]
    fn hits_with_barycentrics() {
        let (p0, p1, p2) = tri();
        let ray = Ray::new(Vec3::new(0.25, 0.5, 2.0), Vec3::new(0.0, 0.0, -1.0));
        let h = intersect_triangle(&ray, &RayShear::new(&ray), p0, p1, p2, f32::INFINITY).unwrap();
        assert!((h.t - 2.0).abs() < 1e-6);
        let p = p0 * h.b[0] + p1 * h.b[1] + p2 * h.b[2];
        assert!((p - ray.at(h.t)).length() < 1e-6, "{h:?}");
        // Behind the origin, beyond t_max, outside: misses.
        let back = Ray::new(Vec3::new(0.25, 0.5, -2.0), Vec3::new(0.0, 0.0, -1.0));
        assert!(
            intersect_triangle(&back, &RayShear::new(&back), p0, p1, p2, f32::INFINITY).is_none()
        );
        assert!(intersect_triangle(&ray, &RayShear::new(&ray), p0, p1, p2, 1.5).is_none());
        let out = Ray::new(Vec3::new(0.75, 0.75, 2.0), Vec3::new(0.0, 0.0, -1.0));
        assert!(
            intersect_triangle(&out, &RayShear::new(&out), p0, p1, p2, f32::INFINITY).is_none()
        );
    }

    #[test]
    fn a_ray_leaving_a_large_triangle_never_finds_it_again() {
        // Rays from points of a 4·10⁶-wide face (z = 0, origins offset by
        // Wächter & Binder's 1/65536 above it) towards a lamp 10⁶ above:
        // the relative coordinates' rounding (ulp 0.25 at 2·10⁶) exceeds
        // the offset, and without the conservative t bound 38 % of such
        // rays hit the face they leave (at t ~ 10⁻³–10⁻¹).
        let s = 1e6f32;
        let v = |x: f32, y: f32| Vec3::new(x * s, y * s, 0.0);
        let face = [
            (v(-2.0, -2.0), v(2.0, -2.0), v(2.0, 2.0)),
            (v(-2.0, -2.0), v(2.0, 2.0), v(-2.0, 2.0)),
        ];
        let mut r = crate::test_rng::uniforms(1);
        let mut found = 0;
        for _ in 0..20_000 {
            let p = v(r() * 4.0 - 2.0, r() * 4.0 - 2.0);
            let o = crate::math::offset_ray_origin(p, Vec3::new(0.0, 0.0, 1.0), 1.0);
            let lamp = Vec3::new((r() * 0.8 - 0.4) * s, (r() * 0.8 - 0.4) * s, s);
            let ray = Ray::new(o, (lamp - o).normalize());
            let sh = RayShear::new(&ray);
            found += face
                .iter()
                .filter(|t| intersect_triangle(&ray, &sh, t.0, t.1, t.2, f32::INFINITY).is_some())
                .count();
        }
        assert_eq!(found, 0, "rays found the face they leave");
    }

    #[test]
    fn shared_edge_is_watertight() {
        // Two triangles sharing the diagonal of the unit square: rays through
        // the diagonal hit exactly one of them.
        let (a, b, c, d) = (
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
        );
        let mut state = 12345u32;
        for _ in 0..10_000 {
            state = state.wrapping_mul(1_664_525).wrapping_add(1_013_904_223);
            let s = (state >> 8) as f32 / (1u32 << 24) as f32;
            let o = Vec3::new(s, s, 1.0) + Vec3::new(0.3, -0.2, 0.0) * 1e-3;
            let ray = Ray::new(o, (Vec3::new(s, s, 0.0) - o).normalize());
            let sh = RayShear::new(&ray);
            let hits = intersect_triangle(&ray, &sh, a, b, c, f32::INFINITY).is_some() as u32
                + intersect_triangle(&ray, &sh, a, c, d, f32::INFINITY).is_some() as u32;
            assert!(
                hits >= 1,
                "a ray through the shared edge fell through at {s}"
            );
        }
    }

    #[test]
    fn degenerate_triangles_never_hit() {
        let p = Vec3::new(0.5, 0.5, 0.0);
        let ray = Ray::new(Vec3::new(0.5, 0.5, 1.0), Vec3::new(0.0, 0.0, -1.0));
        let s = RayShear::new(&ray);
        assert!(intersect_triangle(&ray, &s, p, p, p, f32::INFINITY).is_none());
        let line = (
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(2.0, 2.0, 0.0),
        );
        assert!(intersect_triangle(&ray, &s, line.0, line.1, line.2, f32::INFINITY).is_none());
    }
}

//! Spheres, in world space, and sampling the part of one a point sees.

use super::SurfacePoint;
use crate::math::{Frame, Ray, Vec3};
use crate::sampling::warp::{square_to_uniform_cone, uniform_cone_pdf};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
    /// The object-space axes in world space (orthonormal; a mirror when
    /// `to_world` mirrors): texture coordinates are computed in object
    /// space, as Mitsuba computes them, so they turn with the sphere.
    pub frame: Frame,
    /// Normals point inwards (Mitsuba's `flip_normals`).
    pub flip: bool,
}

impl Sphere {
    /// A sphere whose object axes are the world's.
    pub fn new(center: Vec3, radius: f32) -> Self {
        let frame = Frame {
            s: Vec3::new(1.0, 0.0, 0.0),
            t: Vec3::new(0.0, 1.0, 0.0),
            n: Vec3::new(0.0, 0.0, 1.0),
        };
        Self::oriented(center, radius, frame)
    }

    /// A sphere whose object x, y, z axes are `frame`'s s, t, n.
    pub fn oriented(center: Vec3, radius: f32, frame: Frame) -> Self {
        Self {
            center,
            radius,
            frame,
            flip: false,
        }
    }

    /// The same sphere with its normals inwards when `flip`.
    pub fn with_flipped_normals(self, flip: bool) -> Self {
        Self { flip, ..self }
    }

    /// The normal at unit outward direction `n` from the centre.
    #[inline]
    pub fn normal(&self, n: Vec3) -> Vec3 {
        if self.flip {
            -n
        } else {
            n
        }
    }

    /// Mitsuba's texture coordinates at unit world direction `n` from the
    /// centre: (φ/2π, θ/π) of the direction in object space.
    pub fn uv(&self, n: Vec3) -> [f32; 2] {
        let local = self.frame.to_local(n);
        let phi = local
            .y
            .atan2(local.x)
            .rem_euclid(2.0 * std::f32::consts::PI);
        let u = phi / (2.0 * std::f32::consts::PI);
        let theta = local.z.clamp(-1.0, 1.0).acos();
        // rem_euclid can round up to 2π.
        [if u >= 1.0 { 0.0 } else { u }, theta / std::f32::consts::PI]
    }

    /// Nearest t in (0, t_max) where the ray meets the sphere. Solved in f64
    /// with the numerically stable quadratic (no cancellation in −b ± √Δ).
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        Self::intersect_ball(self.center, self.radius, ray, t_max)
    }

    /// [`Sphere::intersect`] for the ball of `center` and `radius`.
    #[inline]
    pub fn intersect_ball(center: Vec3, radius: f32, ray: &Ray, t_max: f32) -> Option<f32> {
        let o = ray.o - center;
        let (ox, oy, oz) = (o.x as f64, o.y as f64, o.z as f64);
        let (dx, dy, dz) = (ray.d.x as f64, ray.d.y as f64, ray.d.z as f64);
        let a = dx * dx + dy * dy + dz * dz;
        let b = 2.0 * (dx * ox + dy * oy + dz * oz);
        let r = radius as f64;
        // c = |o|² − r², via (|o| − r)(|o| + r) to keep precision near the surface.
        let len = (ox * ox + oy * oy + oz * oz).sqrt();
        let c = (len - r) * (len + r);
        let disc = b * b - 4.0 * a * c;
        if disc < 0.0 {
            return None;
        }
        let q = -0.5 * (b + b.signum() * disc.sqrt());
        let (mut t0, mut t1) = (q / a, c / q);
        if t0 > t1 {
            std::mem::swap(&mut t0, &mut t1);
        }
        let t_max = t_max as f64;
        [t0, t1]
            .into_iter()
            .find(|&t| t > 0.0 && t < t_max)
            .map(|t| t as f32)
            .filter(|&t| t > 0.0 && t < t_max as f32)
    }

    pub fn area(&self) -> f32 {
        4.0 * std::f32::consts::PI * self.radius * self.radius
    }

    /// The cone of directions the sphere fills seen from `p`: its axis,
    /// the distance to the centre, sin²θmax and 1 − cos θmax (the latter
    /// as sin²/(1 + cos), exact for small, distant spheres). `None` from
    /// inside or on the sphere.
    fn cone(&self, p: Vec3) -> Option<(Vec3, f64, f64, f64)> {
        let d = self.center - p;
        let dc = (d.length_squared() as f64).sqrt();
        let r = self.radius as f64;
        // NaN distances fail this too.
        if dc.is_nan() || dc <= r * (1.0 + 1e-4) {
            return None;
        }
        let sin2 = (r / dc) * (r / dc);
        let cos = (1.0 - sin2).max(0.0).sqrt();
        Some((d / dc as f32, dc, sin2, sin2 / (1.0 + cos)))
    }

    /// Density per steradian of [`Sphere::sample_seen`] from `p`:
    /// 1/(2π(1 − cos θmax)) on the cone; `None` from inside.
    pub fn seen_pdf(&self, p: Vec3) -> Option<f32> {
        let (_, _, _, one_minus_cos) = self.cone(p)?;
        Some(uniform_cone_pdf(one_minus_cos as f32))
    }

    /// A point on the near side of the sphere as seen from `p`, reached by
    /// a direction uniform in the cone the sphere subtends (pbrt-v4 §6.2.4
    /// samples spheres the same way): every sample is visible, where
    /// uniform area sampling wastes the far half and weighs the near one
    /// by cos θ / d². Returns the point and its density per steradian;
    /// `None` from inside (then sample by area).
    pub fn sample_seen(&self, p: Vec3, u: [f32; 2]) -> Option<(SurfacePoint, f32)> {
        let (axis, dc, sin2_max, one_minus_max) = self.cone(p)?;
        let w = Frame::from_normal(axis).to_world(square_to_uniform_cone(u, one_minus_max as f32));
        // The nearer root of |p + t·w − c| = r, with cos θ and sin²θ of the
        // sampled direction formed as the warp forms them.
        let one_minus = u[0] as f64 * one_minus_max;
        let sin2 = (one_minus * (2.0 - one_minus)).min(sin2_max);
        let r = self.radius as f64;
        let t = dc * (1.0 - one_minus) - (r * r - dc * dc * sin2).max(0.0).sqrt();
        // Back onto the surface (f32 rounding), the normal outwards.
        let n = (p + w * t as f32 - self.center).normalize();
        n.is_finite().then_some((
            SurfacePoint {
                p: self.center + n * self.radius,
                n: self.normal(n),
                uv: self.uv(n),
            },
            uniform_cone_pdf(one_minus_max as f32),
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::warp::{square_to_uniform_sphere, UNIFORM_SPHERE_PDF};
    use crate::test_rng::{mean_and_se, uniforms};

    #[test]
    fn samples_lie_on_the_near_side_with_the_cone_density() {
        let s = Sphere::new(Vec3::new(1.0, 2.0, -3.0), 0.5);
        let mut u = uniforms(1);
        for p in [
            Vec3::new(1.0, 2.0, -1.0),
            Vec3::new(4.0, 2.5, 0.0),
            Vec3::new(1.0, 2.0, -3.0 + 0.5001),
            Vec3::new(1000.0, 2.0, -3.0),
        ] {
            let pdf = s.seen_pdf(p).unwrap();
            for _ in 0..1000 {
                let (q, density) = s.sample_seen(p, [u(), u()]).unwrap();
                assert_eq!(density, pdf);
                let r = (q.p - s.center).length();
                assert!((r / s.radius - 1.0).abs() < 1e-4, "{p:?}: |q − c| = {r}");
                // Seen from p: the normal faces it.
                assert!((p - q.p).dot(q.n) > 0.0, "{p:?}: {q:?}");
            }
        }
        assert!(s.seen_pdf(s.center).is_none());
        assert!(s
            .sample_seen(Vec3::new(1.2, 2.0, -3.0), [0.5, 0.5])
            .is_none());
    }

    #[test]
    fn facing_the_sphere_the_estimate_is_exact() {
        // ∫ over the cone of cos θ dω = π sin²θmax; with cos θ uniform the
        // estimate is linear in u[0], so a midpoint grid gets it exactly.
        let s = Sphere::new(Vec3::new(0.0, 0.0, 10.0), 1.0);
        for p in [
            Vec3::ZERO,
            Vec3::new(0.0, 0.0, 7.0),
            Vec3::new(0.0, 0.0, -990.0),
        ] {
            let axis = (s.center - p).normalize();
            let n = 64;
            let mut sum = 0.0f64;
            for i in 0..n {
                for j in 0..n {
                    let u = [(i as f32 + 0.5) / n as f32, (j as f32 + 0.5) / n as f32];
                    let (q, pdf) = s.sample_seen(p, u).unwrap();
                    let w = (q.p - p).normalize();
                    sum += (w.dot(axis) / pdf) as f64;
                }
            }
            let e = sum / (n * n) as f64;
            let sin2 = 1.0 / ((s.center - p).length() as f64).powi(2);
            let want = std::f64::consts::PI * sin2;
            assert!((e / want - 1.0).abs() < 1e-3, "{p:?}: {e} vs {want}");
        }
    }

    #[test]
    fn cone_and_area_sampling_agree_and_the_cone_has_less_variance() {
        // Irradiance at a receiver tilted 60° away from a sphere 3 radii
        // off, by both strategies (fixed seeds, 4 standard errors).
        let s = Sphere::new(Vec3::new(0.0, 0.0, 3.0), 1.0);
        let p = Vec3::ZERO;
        let normal = Vec3::new(60f32.to_radians().sin(), 0.0, 60f32.to_radians().cos());
        let n = 40_000;
        let mut u = uniforms(7);
        let cone: Vec<f64> = (0..n)
            .map(|_| {
                let (q, pdf) = s.sample_seen(p, [u(), u()]).unwrap();
                let w = (q.p - p).normalize();
                (w.dot(normal).max(0.0) / pdf) as f64
            })
            .collect();
        let area: Vec<f64> = (0..n)
            .map(|_| {
                let m = square_to_uniform_sphere([u(), u()]);
                let q = s.center + m * s.radius;
                let d = q - p;
                let (dist2, w) = (d.length_squared(), d.normalize());
                let cos_l = -w.dot(m);
                if cos_l <= 0.0 {
                    return 0.0;
                }
                (w.dot(normal).max(0.0) * cos_l / dist2 / (UNIFORM_SPHERE_PDF / s.radius.powi(2)))
                    as f64
            })
            .collect();
        let ((mc, sc), (ma, sa)) = (mean_and_se(&cone), mean_and_se(&area));
        assert!(
            (mc - ma).abs() < 4.0 * (sc * sc + sa * sa).sqrt(),
            "cone {mc} ± {sc}, area {ma} ± {sa}"
        );
        assert!(sc < 0.5 * sa, "standard errors: cone {sc}, area {sa}");
    }
}

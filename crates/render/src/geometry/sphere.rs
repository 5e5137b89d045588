//! Spheres, in world space.

use crate::math::{Ray, Vec3};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    pub center: Vec3,
    pub radius: f32,
}

impl Sphere {
    /// Nearest t in (0, t_max) where the ray meets the sphere. Solved in f64
    /// with the numerically stable quadratic (no cancellation in −b ± √Δ).
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<f32> {
        let o = ray.o - self.center;
        let (ox, oy, oz) = (o.x as f64, o.y as f64, o.z as f64);
        let (dx, dy, dz) = (ray.d.x as f64, ray.d.y as f64, ray.d.z as f64);
        let a = dx * dx + dy * dy + dz * dz;
        let b = 2.0 * (dx * ox + dy * oy + dz * oz);
        let r = self.radius as f64;
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
}

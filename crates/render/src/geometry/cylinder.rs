//! Cylinders as Mitsuba defines them: an open tube (no caps) of radius
//! `radius` around the segment p0 → p1, placed by `to_world`. In object
//! space it is the unit tube x² + y² = 1, 0 ≤ z ≤ 1; its normals point
//! outwards (inwards when flipped) and its texture coordinates are
//! (φ/2π, z).

use super::{GeometryError, SurfacePoint};
use crate::math::{Aabb, Frame, Ray, Transform, Vec3};

#[derive(Debug, Clone, PartialEq)]
pub struct Cylinder {
    pub world_from_object: Transform,
    pub object_from_world: Transform,
    /// What the ray test needs, in f32.
    pub test: CylinderTest,
    flip: bool,
    area: f32,
}

/// The ray test of a cylinder: the first three rows of its
/// object-from-world matrix (affine). Small and `Copy`, so the
/// accelerator keeps it inline.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CylinderTest {
    rows: [[f32; 4]; 3],
}

impl CylinderTest {
    /// The nearer t in (0, t_max) where the ray meets the tube between its
    /// ends; the farther root when the nearer one misses the tube's length
    /// or lies behind the origin (a ray from inside). Solved in f64 in
    /// object space, with the numerically stable quadratic.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<(f32, [f32; 2])> {
        let [rx, ry, rz] = self.rows.map(|r| r.map(|v| v as f64));
        let (o, d) = (
            [ray.o.x as f64, ray.o.y as f64, ray.o.z as f64],
            [ray.d.x as f64, ray.d.y as f64, ray.d.z as f64],
        );
        let point = |r: &[f64; 4]| r[0] * o[0] + r[1] * o[1] + r[2] * o[2] + r[3];
        let vector = |r: &[f64; 4]| r[0] * d[0] + r[1] * d[1] + r[2] * d[2];
        let (ox, oy, oz) = (point(&rx), point(&ry), point(&rz));
        let (dx, dy, dz) = (vector(&rx), vector(&ry), vector(&rz));
        let a = dx * dx + dy * dy;
        if a == 0.0 || a.is_nan() {
            // Along the axis: the tube has no area there.
            return None;
        }
        let b = 2.0 * (dx * ox + dy * oy);
        // c = ρ² − 1 as (ρ − 1)(ρ + 1), precise near the surface.
        let rho = (ox * ox + oy * oy).sqrt();
        let c = (rho - 1.0) * (rho + 1.0);
        let disc = b * b - 4.0 * a * c;
        if disc < 0.0 || disc.is_nan() {
            return None;
        }
        let q = -0.5 * (b + b.signum() * disc.sqrt());
        let (mut t0, mut t1) = (q / a, if q != 0.0 { c / q } else { q / a });
        if t0 > t1 {
            std::mem::swap(&mut t0, &mut t1);
        }
        let t_max = t_max as f64;
        [t0, t1]
            .into_iter()
            .filter(|&t| t > 0.0 && t < t_max)
            .find(|&t| (0.0..=1.0).contains(&(oz + dz * t)))
            .map(|t| t as f32)
            .filter(|&t| t > 0.0 && (t as f64) < t_max)
            .map(|t| (t, [0.0, 0.0]))
    }
}

impl Cylinder {
    /// The tube of `radius` around p0 → p1 (object space of `to_world`).
    pub fn new(
        p0: Vec3,
        p1: Vec3,
        radius: f32,
        to_world: &Transform,
        flip: bool,
    ) -> Result<Self, GeometryError> {
        let d = p1 - p0;
        let length = d.length();
        if length.is_nan() || length <= 0.0 || length.is_infinite() {
            return Err(GeometryError::Invalid(format!(
                "the cylinder's p0 and p1 must differ, got {p0:?} and {p1:?}"
            )));
        }
        if radius.is_nan() || radius <= 0.0 || radius.is_infinite() {
            return Err(GeometryError::Invalid(format!(
                "radius must be positive, got {radius}"
            )));
        }
        // world ← to_world · translate(p0) · frame(d) · scale(r, r, length),
        // the frame's axes as Mitsuba's coordinate system around d.
        let f = Frame::from_normal(d / length);
        let col = |v: Vec3| [v.x as f64, v.y as f64, v.z as f64];
        let (s, t, n) = (col(f.s), col(f.t), col(f.n));
        let frame = Transform::from_matrix([
            [s[0], t[0], n[0], 0.0],
            [s[1], t[1], n[1], 0.0],
            [s[2], t[2], n[2], 0.0],
            [0.0, 0.0, 0.0, 1.0],
        ])
        .ok_or_else(|| GeometryError::Invalid("degenerate cylinder axis".into()))?;
        let scale = Transform::scale(Vec3::new(radius, radius, length))
            .ok_or_else(|| GeometryError::Invalid("degenerate cylinder".into()))?;
        let world_from_object = to_world
            .then_after(&Transform::translate(p0))
            .then_after(&frame)
            .then_after(&scale);
        let object_from_world = world_from_object.inverse();
        let m = object_from_world.matrix();
        let test = CylinderTest {
            rows: std::array::from_fn(|i| std::array::from_fn(|j| m[i][j] as f32)),
        };
        // Mitsuba's area: 2π · |x axis| · |z axis| in world space (exact
        // without shear or unequal scaling across the axis).
        let r = world_from_object.vector(Vec3::new(1.0, 0.0, 0.0)).length();
        let l = world_from_object.vector(Vec3::new(0.0, 0.0, 1.0)).length();
        let area = 2.0 * std::f32::consts::PI * r * l;
        if !area.is_finite() || area <= 0.0 {
            return Err(GeometryError::Invalid("degenerate cylinder".into()));
        }
        Ok(Self {
            world_from_object,
            object_from_world,
            test,
            flip,
            area,
        })
    }

    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<(f32, [f32; 2])> {
        self.test.intersect(ray, t_max)
    }

    pub fn area(&self) -> f32 {
        self.area
    }

    /// The two end circles' box (as Mitsuba bounds a cylinder).
    pub fn bounds(&self) -> Aabb {
        let m = &self.world_from_object;
        let (x1, x2) = (
            m.vector(Vec3::new(1.0, 0.0, 0.0)),
            m.vector(Vec3::new(0.0, 1.0, 0.0)),
        );
        let x = Vec3::new(x1.x.hypot(x2.x), x1.y.hypot(x2.y), x1.z.hypot(x2.z));
        let (p0, p1) = (m.point(Vec3::ZERO), m.point(Vec3::new(0.0, 0.0, 1.0)));
        // Widened by a few ULPs for the rounding of the transform.
        let pad =
            x * 1e-6 + Vec3::splat(1e-6 * p0.abs().max_component().max(p1.abs().max_component()));
        Aabb::from_points(&[p0 - x - pad, p0 + x + pad, p1 - x - pad, p1 + x + pad])
    }

    /// The world-space normal at object point (x, y) on the tube.
    fn normal_at(&self, x: f32, y: f32) -> Vec3 {
        let n = self
            .world_from_object
            .normal(Vec3::new(x, y, 0.0))
            .normalize();
        if self.flip {
            -n
        } else {
            n
        }
    }

    /// The surface at world point `p` (a hit): re-projected onto the tube,
    /// its normal and Mitsuba's (φ/2π, z).
    pub fn surface_at(&self, p: Vec3) -> (Vec3, Vec3, [f32; 2]) {
        let local = self.object_from_world.point(p);
        let rho = local.x.hypot(local.y);
        let (x, y) = if rho > 0.0 {
            (local.x / rho, local.y / rho)
        } else {
            (1.0, 0.0)
        };
        let z = local.z.clamp(0.0, 1.0);
        let p = self.world_from_object.point(Vec3::new(x, y, z));
        (p, self.normal_at(x, y), tube_uv(x, y, z))
    }

    /// A point uniform over the tube's area (density 1/area), as Mitsuba
    /// samples it: u[0] along the axis, u[1] around it.
    pub fn sample_area(&self, u: [f32; 2]) -> SurfacePoint {
        let (s, c) = (2.0 * std::f32::consts::PI * u[1]).sin_cos();
        SurfacePoint {
            p: self.world_from_object.point(Vec3::new(c, s, u[0])),
            n: self.normal_at(c, s),
            uv: tube_uv(c, s, u[0]),
        }
    }
}

/// Mitsuba's (φ/2π, z) at object point (x, y, z) of the unit tube.
#[inline]
fn tube_uv(x: f32, y: f32, z: f32) -> [f32; 2] {
    let phi = y.atan2(x).rem_euclid(2.0 * std::f32::consts::PI);
    let u = phi / (2.0 * std::f32::consts::PI);
    // rem_euclid can round up to 2π.
    [if u >= 1.0 { 0.0 } else { u }, z]
}

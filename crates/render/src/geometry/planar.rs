//! Planar shapes defined in object space on z = 0 and placed by a
//! transform, as Mitsuba defines them: the disk of radius 1 and the
//! rectangle [−1, 1]².

use crate::math::{Ray, Transform, Vec3};

/// Which planar shape.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum PlanarKind {
    /// x² + y² ≤ 1.
    Disk,
    /// |x| ≤ 1 and |y| ≤ 1.
    Rectangle,
}

#[derive(Debug, Clone, PartialEq)]
pub struct Planar {
    pub kind: PlanarKind,
    pub world_from_object: Transform,
    pub object_from_world: Transform,
    /// What the ray test needs, in f32.
    pub test: PlaneTest,
    /// The unit world-space normal.
    normal: Vec3,
}

/// The ray test of a planar shape: the first three rows of its
/// object-from-world matrix (affine: placements have no projection), and
/// its kind. Small and `Copy`, so the accelerator keeps it inline.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PlaneTest {
    rows: [[f32; 4]; 3],
    disk: bool,
}

impl PlaneTest {
    /// The object-from-world rows and whether the shape is the disk, for
    /// wide forms of the test.
    #[inline]
    pub fn parts(&self) -> (&[[f32; 4]; 3], bool) {
        (&self.rows, self.disk)
    }

    /// t in (0, t_max) and the object-space hit point (x, y). The hit
    /// point is rebuilt from (x, y) in f64, so t's f32 rounding only
    /// decides which surface is nearer.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<(f32, [f32; 2])> {
        // The distance t is the same in both spaces (the direction is
        // transformed unnormalised).
        let [rx, ry, rz] = &self.rows;
        let point = |r: &[f32; 4]| r[0] * ray.o.x + r[1] * ray.o.y + r[2] * ray.o.z + r[3];
        let vector = |r: &[f32; 4]| r[0] * ray.d.x + r[1] * ray.d.y + r[2] * ray.d.z;
        let dz = vector(rz);
        let t = -point(rz) / dz;
        if !(t > 0.0 && t < t_max) {
            return None;
        }
        let (x, y) = (point(rx) + t * vector(rx), point(ry) + t * vector(ry));
        let inside = if self.disk {
            x * x + y * y <= 1.0
        } else {
            x.abs() <= 1.0 && y.abs() <= 1.0
        };
        inside.then_some((t, [x, y]))
    }
}

impl Planar {
    pub fn new(kind: PlanarKind, world_from_object: Transform) -> Self {
        let object_from_world = world_from_object.inverse();
        let m = object_from_world.matrix();
        let test = PlaneTest {
            rows: std::array::from_fn(|i| std::array::from_fn(|j| m[i][j] as f32)),
            disk: kind == PlanarKind::Disk,
        };
        let normal = world_from_object
            .normal(Vec3::new(0.0, 0.0, 1.0))
            .normalize();
        Self {
            kind,
            object_from_world,
            world_from_object,
            test,
            normal,
        }
    }

    /// t in (0, t_max) and the object-space hit point (x, y).
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<(f32, [f32; 2])> {
        self.test.intersect(ray, t_max)
    }

    /// World-space normal: object +z transformed as a normal, as Mitsuba
    /// does (a mirroring `to_world` turns the shape over).
    #[inline]
    pub fn normal(&self) -> Vec3 {
        self.normal
    }

    /// Mitsuba's texture coordinates at object point (x, y): for the
    /// rectangle ((x + 1)/2, (y + 1)/2), for the disk (r, φ/2π).
    #[inline]
    pub fn uv_at(&self, x: f32, y: f32) -> [f32; 2] {
        match self.kind {
            PlanarKind::Rectangle => [0.5 * (x + 1.0), 0.5 * (y + 1.0)],
            PlanarKind::Disk => {
                let two_pi = 2.0 * std::f32::consts::PI;
                let phi = y.atan2(x).rem_euclid(two_pi);
                [(x * x + y * y).sqrt(), phi / two_pi]
            }
        }
    }

    /// World-space area (the object shape's area times the transform's
    /// area scale on the z = 0 plane).
    pub fn area(&self) -> f32 {
        let dx = self.world_from_object.vector(Vec3::new(1.0, 0.0, 0.0));
        let dy = self.world_from_object.vector(Vec3::new(0.0, 1.0, 0.0));
        let scale = dx.cross(dy).length();
        match self.kind {
            PlanarKind::Disk => std::f32::consts::PI * scale,
            PlanarKind::Rectangle => 4.0 * scale,
        }
    }
}

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
}

impl Planar {
    pub fn new(kind: PlanarKind, world_from_object: Transform) -> Self {
        Self {
            kind,
            object_from_world: world_from_object.inverse(),
            world_from_object,
        }
    }

    /// t in (0, t_max) and the object-space hit point (x, y).
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<(f32, [f32; 2])> {
        // The distance t is the same in both spaces (the direction is
        // transformed unnormalised).
        let o = self.object_from_world.point(ray.o);
        let d = self.object_from_world.vector(ray.d);
        if d.z == 0.0 {
            return None;
        }
        let t = -o.z / d.z;
        if !(t > 0.0 && t < t_max) {
            return None;
        }
        let (x, y) = (o.x + t * d.x, o.y + t * d.y);
        let inside = match self.kind {
            PlanarKind::Disk => x * x + y * y <= 1.0,
            PlanarKind::Rectangle => x.abs() <= 1.0 && y.abs() <= 1.0,
        };
        inside.then_some((t, [x, y]))
    }

    /// World-space normal: object +z transformed as a normal, as Mitsuba
    /// does (a mirroring `to_world` turns the shape over).
    pub fn normal(&self) -> Vec3 {
        self.world_from_object
            .normal(Vec3::new(0.0, 0.0, 1.0))
            .normalize()
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

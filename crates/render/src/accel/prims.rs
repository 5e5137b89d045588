//! The primitives in the BVH's leaf order, each with what its ray test
//! needs stored inline: a traversal step reads one entry instead of
//! following shape → mesh → index → position.

use crate::geometry::{intersect_triangle, CylinderTest, PlaneTest, RayShear, Shape, Sphere};
use crate::math::{Ray, Vec3};

#[derive(Debug, Clone, Copy)]
enum Test {
    Triangle([Vec3; 3]),
    Sphere(Vec3, f32),
    Plane(PlaneTest),
    Cylinder(CylinderTest),
    /// An instance of a shape group, by its number in the aggregate: the
    /// aggregate tests it (`Instance::intersect`).
    Instance(u32),
}

/// One primitive: its test, and which shape and primitive it is.
#[derive(Debug, Clone, Copy)]
pub(super) struct Prim {
    test: Test,
    pub shape: u32,
    pub index: u32,
}

impl Prim {
    pub fn new(shapes: &[Shape], shape: u32, index: u32) -> Self {
        let test = match &shapes[shape as usize] {
            Shape::Mesh(m) => {
                let (a, b, c) = m.vertices(index as usize);
                Test::Triangle([a, b, c])
            }
            Shape::Sphere(s) => Test::Sphere(s.center, s.radius),
            Shape::Planar(p) => Test::Plane(p.test),
            Shape::Cylinder(c) => Test::Cylinder(c.test),
        };
        Self { test, shape, index }
    }

    /// Instance `k` of the aggregate.
    pub fn of_instance(k: u32) -> Self {
        Self {
            test: Test::Instance(k),
            shape: u32::MAX,
            index: k,
        }
    }

    /// The instance this primitive is, if it is one.
    #[inline(always)]
    pub fn instance(&self) -> Option<u32> {
        match self.test {
            Test::Instance(k) => Some(k),
            _ => None,
        }
    }

    /// t in (0, t_max) and the hit's barycentrics or object (x, y).
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray, shear: &RayShear, t_max: f32) -> Option<(f32, [f32; 2])> {
        match &self.test {
            Test::Triangle([a, b, c]) => {
                intersect_triangle(ray, shear, *a, *b, *c, t_max).map(|h| (h.t, [h.b[1], h.b[2]]))
            }
            Test::Sphere(c, r) => {
                Sphere::intersect_ball(*c, *r, ray, t_max).map(|t| (t, [0.0, 0.0]))
            }
            Test::Plane(p) => p.intersect(ray, t_max),
            Test::Cylinder(c) => c.intersect(ray, t_max),
            // Tested by the aggregate, which holds the instances.
            Test::Instance(_) => None,
        }
    }
}

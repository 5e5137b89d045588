//! The primitives tested one at a time (triangles and planar shapes are
//! tested in blocks: `block.rs`), in the BVH's leaf order, each with what
//! its ray test needs stored inline.

use crate::geometry::{CylinderTest, Shape, Sphere};
use crate::math::{Ray, Vec3};

#[derive(Debug, Clone, Copy)]
enum Test {
    Sphere(Vec3, f32),
    Cylinder(CylinderTest),
    /// An instance of a shape group, by its number in the aggregate: the
    /// aggregate tests it (`Instance::intersect_at`).
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
    /// Primitive `index` of `shapes[shape]`, if it is a sphere or a
    /// cylinder (the other kinds go into blocks).
    pub fn new(shapes: &[Shape], shape: u32, index: u32) -> Option<Self> {
        let test = match &shapes[shape as usize] {
            Shape::Sphere(s) => Test::Sphere(s.center, s.radius),
            Shape::Cylinder(c) => Test::Cylinder(c.test),
            Shape::Mesh(_) | Shape::Planar(_) => return None,
        };
        Some(Self { test, shape, index })
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

    /// t in (0, t_max) and the hit's object (x, y) or (0, 0).
    #[inline(always)]
    pub fn intersect(&self, ray: &Ray, t_max: f32) -> Option<(f32, [f32; 2])> {
        match &self.test {
            Test::Sphere(c, r) => {
                Sphere::intersect_ball(*c, *r, ray, t_max).map(|t| (t, [0.0, 0.0]))
            }
            Test::Cylinder(c) => c.intersect(ray, t_max),
            // Tested by the aggregate, which holds the instances.
            Test::Instance(_) => None,
        }
    }
}

//! Acceleration: bounding boxes, the BVH, and the aggregate of all shapes
//! that answers a scene's ray queries.

mod aabb;
mod bvh;

pub use aabb::Aabb;
pub use bvh::Bvh;

use crate::geometry::{Hit, RayShear, Shape};
use crate::math::Ray;

/// All shapes of a scene under one BVH over their primitives.
#[derive(Debug, Clone)]
pub struct Aggregate {
    pub shapes: Vec<Shape>,
    /// (shape, primitive) of each BVH primitive.
    prims: Vec<(u32, u32)>,
    bvh: Bvh,
}

impl Aggregate {
    pub fn new(shapes: Vec<Shape>) -> Self {
        let prims: Vec<(u32, u32)> = shapes
            .iter()
            .enumerate()
            .flat_map(|(s, shape)| (0..shape.primitive_count()).map(move |p| (s as u32, p as u32)))
            .collect();
        let bounds: Vec<Aabb> = prims
            .iter()
            .map(|&(s, p)| shapes[s as usize].bounds(p as usize))
            .collect();
        let bvh = Bvh::build(&bounds);
        Self { shapes, prims, bvh }
    }

    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    /// The closest hit within (0, ray.t_max).
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let shear = RayShear::new(ray);
        let mut best: Option<Hit> = None;
        self.bvh.traverse(ray, ray.t_max, |i, t_max| {
            let (s, p) = self.prims[i as usize];
            let (t, uv) = self.shapes[s as usize].intersect(p as usize, ray, &shear, t_max)?;
            best = Some(Hit {
                t,
                shape: s,
                prim: p,
                uv,
            });
            Some((t, false))
        });
        best
    }

    /// Whether anything lies within (0, ray.t_max).
    pub fn occluded(&self, ray: &Ray) -> bool {
        let shear = RayShear::new(ray);
        let mut any = false;
        self.bvh.traverse(ray, ray.t_max, |i, t_max| {
            let (s, p) = self.prims[i as usize];
            let (t, _) = self.shapes[s as usize].intersect(p as usize, ray, &shear, t_max)?;
            any = true;
            Some((t, true))
        });
        any
    }
}

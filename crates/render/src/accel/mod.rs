//! Acceleration: bounding boxes, the BVH, and the aggregate of all shapes
//! that answers a scene's ray queries.

mod aabb;
mod bvh;
mod prims;

pub use aabb::Aabb;
pub use bvh::Bvh;

use crate::geometry::{Hit, RayShear, Shape};
use crate::math::Ray;
use prims::Prim;

/// All shapes of a scene under one BVH over their primitives.
#[derive(Debug, Clone)]
pub struct Aggregate {
    pub shapes: Vec<Shape>,
    /// The primitives in the BVH's leaf order.
    prims: Vec<Prim>,
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
        let prims = bvh
            .order()
            .iter()
            .map(|&i| {
                let (s, p) = prims[i as usize];
                Prim::new(&shapes, s, p)
            })
            .collect();
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
        self.bvh.traverse::<true>(ray, ray.t_max, |i, t_max| {
            let prim = &self.prims[i as usize];
            let (t, uv) = prim.intersect(ray, &shear, t_max)?;
            best = Some(Hit {
                t,
                shape: prim.shape,
                prim: prim.index,
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
        self.bvh.traverse::<false>(ray, ray.t_max, |i, t_max| {
            let (t, _) = self.prims[i as usize].intersect(ray, &shear, t_max)?;
            any = true;
            Some((t, true))
        });
        any
    }
}

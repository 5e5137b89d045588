//! Acceleration: bounding boxes, the BVH, the aggregate of all shapes that
//! answers a scene's ray queries, and instances of shape groups.

mod aabb;
mod bvh;
mod instance;
mod prims;

pub use aabb::Aabb;
pub use bvh::Bvh;
pub use instance::{Instance, ShapeGroup};

use crate::geometry::{Hit, RayShear, Shape, Surface};
use crate::math::Ray;
use prims::Prim;

/// All shapes of a scene, and the instances of shape groups, under one BVH
/// over their primitives (an instance is one primitive; its group has a
/// BVH of its own).
#[derive(Debug, Clone)]
pub struct Aggregate {
    /// The shapes outside groups, numbered from 0.
    pub shapes: Vec<Shape>,
    instances: Vec<Instance>,
    /// The primitives in the BVH's leaf order.
    prims: Vec<Prim>,
    bvh: Bvh,
}

impl Aggregate {
    pub fn new(shapes: Vec<Shape>) -> Self {
        Self::with_instances(shapes, Vec::new())
    }

    /// `shapes` and `instances` under one BVH. The groups' shapes are
    /// numbered after `shapes` (by each group's `first_shape`).
    pub fn with_instances(shapes: Vec<Shape>, instances: Vec<Instance>) -> Self {
        let mut prims: Vec<Prim> = shapes
            .iter()
            .enumerate()
            .flat_map(|(s, shape)| {
                let shapes = &shapes;
                (0..shape.primitive_count()).map(move |p| Prim::new(shapes, s as u32, p as u32))
            })
            .collect();
        let mut bounds: Vec<Aabb> = prims
            .iter()
            .map(|p| shapes[p.shape as usize].bounds(p.index as usize))
            .collect();
        for (k, instance) in instances.iter().enumerate() {
            prims.push(Prim::of_instance(k as u32));
            bounds.push(instance.bounds());
        }
        let bvh = Bvh::build(&bounds);
        let prims = bvh.order().iter().map(|&i| prims[i as usize]).collect();
        Self {
            shapes,
            instances,
            prims,
            bvh,
        }
    }

    pub fn bvh(&self) -> &Bvh {
        &self.bvh
    }

    pub fn bounds(&self) -> Aabb {
        self.bvh.bounds()
    }

    /// The scene's size for moving ray origins off surfaces
    /// ([`crate::math::offset_ray_origin`]): the largest coordinate of its
    /// bounds, at most 1 (larger scenes are covered by the offset's ULPs).
    #[inline]
    pub fn offset_unit(&self) -> f32 {
        let b = self.bvh.bounds();
        let size = b.min.abs().max_component().max(b.max.abs().max_component());
        if size > 0.0 && size.is_finite() {
            size.min(1.0)
        } else {
            1.0
        }
    }

    pub fn instances(&self) -> &[Instance] {
        &self.instances
    }

    /// The distinct shape groups the instances place, each once.
    pub fn groups(&self) -> Vec<&ShapeGroup> {
        let mut groups: Vec<&ShapeGroup> = self.instances.iter().map(|i| &**i.group()).collect();
        groups.sort_by_key(|g| *g as *const ShapeGroup);
        groups.dedup_by_key(|g| *g as *const ShapeGroup);
        groups
    }

    /// Triangles held in memory: the meshes outside groups and each
    /// group's meshes once, however many instances place it.
    pub fn stored_triangles(&self) -> usize {
        let count = |shapes: &[Shape]| -> usize {
            shapes
                .iter()
                .map(|s| match s {
                    Shape::Mesh(m) => m.triangle_count(),
                    _ => 0,
                })
                .sum()
        };
        count(&self.shapes)
            + self
                .groups()
                .iter()
                .map(|g| count(g.shapes()))
                .sum::<usize>()
    }

    /// The closest hit within (0, ray.t_max).
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        let shear = RayShear::new(ray);
        let mut best: Option<Hit> = None;
        self.bvh.traverse::<true>(ray, ray.t_max, |i, t_max| {
            let prim = &self.prims[i as usize];
            let hit = match prim.instance() {
                Some(k) => self.instances[k as usize].intersect(ray, t_max, k)?,
                None => {
                    let (t, uv) = prim.intersect(ray, &shear, t_max)?;
                    Hit {
                        t,
                        shape: prim.shape,
                        prim: prim.index,
                        uv,
                        instance: None,
                    }
                }
            };
            best = Some(hit);
            Some((hit.t, false))
        });
        best
    }

    /// Whether anything lies within (0, ray.t_max).
    pub fn occluded(&self, ray: &Ray) -> bool {
        let shear = RayShear::new(ray);
        let mut any = false;
        self.bvh.traverse::<false>(ray, ray.t_max, |i, t_max| {
            let prim = &self.prims[i as usize];
            let blocked = match prim.instance() {
                Some(k) => self.instances[k as usize].occluded(ray, t_max),
                None => prim.intersect(ray, &shear, t_max).is_some(),
            };
            any |= blocked;
            blocked.then_some((t_max, true))
        });
        any
    }

    /// The world-space surface at `hit` (from `intersect(ray)`).
    pub fn surface(&self, hit: &Hit, ray: &Ray) -> Surface {
        match hit.instance {
            Some(k) => self.instances[k as usize].surface(hit, ray),
            None => self.shapes[hit.shape as usize].surface(hit, ray),
        }
    }
}

//! Instancing (Mitsuba's `shapegroup` and `instance`): a group's shapes
//! live once, under their own BVH, and every instance that places them is
//! one primitive of the scene's BVH holding its world bound, its placement
//! and a shared reference to the group. A forest of 10 000 instanced trees
//! costs one tree plus 10 000 placements.
//!
//! A ray is taken into the group's space with its direction left
//! unnormalised, so a distance t means the same point in both spaces: the
//! group's hits compare directly with the rest of the scene's, and t_max
//! carries over unchanged. The surface found there is brought back to
//! world space: points and tangents by the placement, normals by its
//! inverse transpose.

use std::sync::Arc;

use super::{Aabb, Aggregate};
use crate::geometry::{Hit, Shape, Surface};
use crate::math::{Ray, Transform, Vec3};
use crate::simd::Level;

/// The shapes of one `shapegroup` under their own BVH. Its shapes are
/// numbered in the scene from `first_shape` on (their materials are
/// `Scene::shape_material[first_shape + k]`), once for all instances.
#[derive(Debug, Clone)]
pub struct ShapeGroup {
    geometry: Aggregate,
    first_shape: u32,
}

impl ShapeGroup {
    /// The group of `shapes`, numbered in the scene from `first_shape`.
    /// A group holds shapes only: groups do not nest.
    pub fn new(shapes: Vec<Shape>, first_shape: u32) -> Self {
        Self {
            geometry: Aggregate::new(shapes),
            first_shape,
        }
    }

    pub fn shapes(&self) -> &[Shape] {
        &self.geometry.shapes
    }

    /// The scene's number of the group's first shape.
    pub fn first_shape(&self) -> u32 {
        self.first_shape
    }

    /// Bounds in the group's own space.
    pub fn bounds(&self) -> Aabb {
        self.geometry.bounds()
    }

    /// The group's own aggregate (its shapes and their BVH).
    pub fn geometry(&self) -> &Aggregate {
        &self.geometry
    }
}

/// One placement of a shape group.
#[derive(Debug, Clone)]
pub struct Instance {
    /// The placement; it carries its inverse, which takes rays in.
    world_from_object: Transform,
    bounds: Aabb,
    group: Arc<ShapeGroup>,
}

impl Instance {
    pub fn new(group: Arc<ShapeGroup>, world_from_object: Transform) -> Self {
        let b = group.bounds();
        let bounds = if b.is_empty() {
            Aabb::EMPTY
        } else {
            let corners: [Vec3; 8] = std::array::from_fn(|i| {
                let pick = |bit: usize, a: usize| {
                    if i >> bit & 1 == 0 {
                        b.min[a]
                    } else {
                        b.max[a]
                    }
                };
                world_from_object.point(Vec3::new(pick(0, 0), pick(1, 1), pick(2, 2)))
            });
            let world = Aabb::from_points(&corners);
            // Widened by a few ULPs for the rounding of the transform (the
            // transform is applied in f64 and rounded once to f32).
            let pad = Vec3::splat(1e-6 * world.min.abs().max(world.max.abs()).max_component());
            Aabb {
                min: world.min - pad,
                max: world.max + pad,
            }
        };
        Self {
            world_from_object,
            bounds,
            group,
        }
    }

    /// World-space bounds.
    pub fn bounds(&self) -> Aabb {
        self.bounds
    }

    pub fn group(&self) -> &Arc<ShapeGroup> {
        &self.group
    }

    pub fn world_from_object(&self) -> &Transform {
        &self.world_from_object
    }

    /// `ray` in the group's space, limited to `t_max`; t is unchanged.
    #[inline]
    fn to_object(&self, ray: &Ray, t_max: f32) -> Ray {
        let object_from_world = self.world_from_object.inverse();
        Ray {
            o: object_from_world.point(ray.o),
            d: object_from_world.vector(ray.d),
            t_max,
        }
    }

    /// The closest hit of `ray` on the group within (0, t_max), as the
    /// scene numbers it: the group's shape (offset by `first_shape`), its
    /// primitive, and this instance's number `index`.
    #[inline]
    pub fn intersect(&self, ray: &Ray, t_max: f32, index: u32) -> Option<Hit> {
        self.intersect_at(Level::current(), ray, t_max, index)
    }

    /// [`Instance::intersect`] at SIMD level `level`.
    #[inline]
    pub fn intersect_at(&self, level: Level, ray: &Ray, t_max: f32, index: u32) -> Option<Hit> {
        let local = self.to_object(ray, t_max);
        let hit = self.group.geometry.intersect_at(level, &local)?;
        Some(Hit {
            shape: self.group.first_shape + hit.shape,
            instance: Some(index),
            ..hit
        })
    }

    /// Whether anything of the group lies along `ray` within (0, t_max).
    #[inline]
    pub fn occluded(&self, ray: &Ray, t_max: f32) -> bool {
        self.occluded_at(Level::current(), ray, t_max)
    }

    /// [`Instance::occluded`] at SIMD level `level`.
    #[inline]
    pub fn occluded_at(&self, level: Level, ray: &Ray, t_max: f32) -> bool {
        self.group
            .geometry
            .occluded_at(level, &self.to_object(ray, t_max))
    }

    /// The world-space surface at `hit` (a hit on this instance) of `ray`.
    pub fn surface(&self, hit: &Hit, ray: &Ray) -> Surface {
        let local_ray = self.to_object(ray, ray.t_max);
        let local_hit = Hit {
            shape: hit.shape - self.group.first_shape,
            instance: None,
            ..*hit
        };
        let s = self.group.shapes()[local_hit.shape as usize].surface(&local_hit, &local_ray);
        let m = &self.world_from_object;
        let n_shading = m.normal(s.n_shading).normalize();
        let n_geometric = m.normal(s.n_geometric).normalize();
        // The geometric normal follows the shading normal's side, as
        // `Shape::surface` decides in world space (a non-uniform scale can
        // tip two nearly perpendicular normals apart).
        let n_geometric = if n_geometric.dot(n_shading) < 0.0 {
            -n_geometric
        } else {
            n_geometric
        };
        Surface {
            p: m.point(s.p),
            n_geometric,
            n_shading,
            uv: s.uv,
            dpdu: m.vector(s.dpdu),
            dpdv: m.vector(s.dpdv),
        }
    }
}

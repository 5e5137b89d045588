//! Acceleration: the BVH, the aggregate of all shapes that
//! answers a scene's ray queries, and instances of shape groups.

mod block;
mod bvh;
mod instance;
mod node;
mod prims;
mod query;
#[cfg(test)]
mod tests;

/// The box lives in `math`, below the shapes that report theirs; kept
/// here too for the paths that name it `accel::Aabb`.
pub use crate::math::Aabb;
pub use bvh::{Bvh, LeafCost, Visit, Width};
pub use instance::{Instance, ShapeGroup};

use crate::geometry::{Hit, PlaneTest, Shape, Surface};
use crate::math::{Ray, Vec3};
use crate::simd::Level;
use block::{Planes, Triangles, PAD, PLANE_FLOATS, TRI_FLOATS};
use prims::Prim;

/// All shapes of a scene, and the instances of shape groups, under one BVH
/// over their primitives (an instance is one primitive; its group has a
/// BVH of its own). A leaf's triangles and planar shapes are kept in
/// blocks tested many at a time; spheres, cylinders and instances one at
/// a time.
#[derive(Debug, Clone)]
pub struct Aggregate {
    /// The shapes outside groups, numbered from 0.
    pub shapes: Vec<Shape>,
    instances: Vec<Instance>,
    bvh: Bvh,
    /// The BVH's leaves, by the numbers its traversal reports.
    leaves: Vec<Leaf>,
    /// The leaves' triangles: each leaf's coordinate arrays
    /// (`block::Triangles`), then [`PAD`] floats.
    tri_data: Vec<f32>,
    /// Each triangle's shape and primitive, in leaf order.
    tri_ids: Vec<(u32, u32)>,
    /// The leaves' planar shapes: each leaf's arrays (`block::Planes`),
    /// then [`PAD`] floats.
    plane_data: Vec<f32>,
    /// Each planar shape's test and shape, in leaf order.
    plane_tests: Vec<(PlaneTest, u32)>,
    /// The primitives tested one at a time, in leaf order.
    others: Vec<Prim>,
    /// [`Self::offset_unit`], fixed with the bounds (every ray spawned
    /// reads it).
    offset_unit: f32,
}

/// [`Aggregate::offset_unit`] of a scene within `b`.
fn unit_of(b: Aabb) -> f32 {
    let size = b.min.abs().max_component().max(b.max.abs().max_component());
    if size > 0.0 && size.is_finite() {
        size.min(1.0)
    } else {
        1.0
    }
}

/// A leaf's count word in its node when the leaf holds more than
/// triangles: its child word is then its number in `Aggregate::leaves`.
/// A leaf of triangles alone has its first triangle and their count there.
const MIXED: u16 = 0x8000;

/// Scenes of this many primitives or more get leaves costed by 8-lane
/// steps: on a million triangles they trace 10–25 % faster, on the
/// Cornell box's 32 primitives 13 % slower (docs/performance.md).
pub const WIDE_LEAVES_FROM: usize = 4096;

/// One leaf: its triangles, planar shapes and other primitives, each a run
/// from a first index, tested in that order.
#[derive(Debug, Clone, Copy)]
struct Leaf {
    tri_first: u32,
    plane_first: u32,
    other_first: u32,
    tris: u16,
    planes: u16,
    others: u16,
}

impl Aggregate {
    /// The triangles of `leaf`.
    #[inline(always)]
    fn triangles(&self, leaf: &Leaf) -> Triangles<'_> {
        Triangles {
            data: &self.tri_data[leaf.tri_first as usize * TRI_FLOATS..],
            n: leaf.tris as usize,
        }
    }

    /// The planar shapes of `leaf`.
    #[inline(always)]
    fn planar(&self, leaf: &Leaf) -> Planes<'_> {
        Planes {
            data: &self.plane_data[leaf.plane_first as usize * PLANE_FLOATS..],
            n: leaf.planes as usize,
        }
    }
}

/// The SIMD level of the leaf tests when the process runs at `level`: at
/// most AVX2. Leaves hold at most 16 primitives and mostly fewer, so
/// 16-lane steps run largely empty; they measured slower than 8-lane ones
/// (docs/performance.md, issue 23).
#[inline]
pub fn leaf_level(level: Level) -> Level {
    level.min(Level::Avx2)
}

/// A primitive while the aggregate is built.
enum Item {
    Triangle(u32, u32, [Vec3; 3]),
    Plane(u32, PlaneTest),
    Other(Prim),
}

impl Aggregate {
    pub fn new(shapes: Vec<Shape>) -> Self {
        Self::with_instances(shapes, Vec::new())
    }

    /// `shapes` and `instances` under one BVH. The groups' shapes are
    /// numbered after `shapes` (by each group's `first_shape`). The tree
    /// depends on the primitive count only, never on the SIMD level, so
    /// that every level renders the same image: [`LeafCost::SCALAR`] for
    /// small scenes, leaves costed by 8-lane steps (the most
    /// [`Aggregate::intersect`] uses) from [`WIDE_LEAVES_FROM`] primitives;
    /// 8-wide nodes at every size (fewer instructions than 4-wide ones on
    /// the Cornell box's 32 primitives as on a million triangles:
    /// docs/performance.md, "Issue 23: 8-wide nodes").
    pub fn with_instances(shapes: Vec<Shape>, instances: Vec<Instance>) -> Self {
        let count: usize =
            shapes.iter().map(Shape::primitive_count).sum::<usize>() + instances.len();
        let cost = if count >= WIDE_LEAVES_FROM {
            LeafCost::wide(8)
        } else {
            LeafCost::SCALAR
        };
        Self::built_with(&cost, Width::Eight, shapes, instances)
    }

    /// [`Aggregate::with_instances`] with leaves costed by `cost`, in
    /// nodes of `width`.
    pub fn built_with(
        cost: &LeafCost,
        width: Width,
        shapes: Vec<Shape>,
        instances: Vec<Instance>,
    ) -> Self {
        // Primitives are numbered shape by shape, then the instances.
        let bounds: Vec<Aabb> = shapes
            .iter()
            .flat_map(|shape| (0..shape.primitive_count()).map(move |p| shape.bounds(p)))
            .chain(instances.iter().map(|i| i.bounds()))
            .collect();
        let mut bvh = Bvh::build_for(&bounds, cost, width);
        drop(bounds);
        // Primitive numbers → (shape, primitive), for the leaves' items.
        let mut first = Vec::with_capacity(shapes.len() + 1);
        let mut n = 0u32;
        for shape in &shapes {
            first.push(n);
            n += shape.primitive_count() as u32;
        }
        first.push(n);
        let item = |i: u32| -> Item {
            if i >= n {
                return Item::Other(Prim::of_instance(i - n));
            }
            let s = first.partition_point(|&f| f <= i) - 1;
            let p = i - first[s];
            match &shapes[s] {
                Shape::Mesh(m) => {
                    let (a, b, c) = m.vertices(p as usize);
                    Item::Triangle(s as u32, p, [a, b, c])
                }
                Shape::Planar(pl) => Item::Plane(s as u32, pl.test),
                _ => Item::Other(
                    Prim::new(&shapes, s as u32, p).expect("spheres and cylinders are prims"),
                ),
            }
        };
        let (order, bvh_leaves) = bvh.take_layout();
        let mut agg = Self {
            shapes: Vec::new(),
            instances: Vec::new(),
            bvh,
            leaves: Vec::with_capacity(bvh_leaves.len()),
            tri_data: Vec::new(),
            tri_ids: Vec::new(),
            plane_data: Vec::new(),
            plane_tests: Vec::new(),
            others: Vec::new(),
            offset_unit: 1.0,
        };
        agg.offset_unit = unit_of(agg.bvh.bounds());
        let (mut tris, mut planes) = (Vec::new(), Vec::new());
        for &(start, count) in &bvh_leaves {
            tris.clear();
            planes.clear();
            let leaf = Leaf {
                tri_first: agg.tri_ids.len() as u32,
                plane_first: agg.plane_tests.len() as u32,
                other_first: agg.others.len() as u32,
                tris: 0,
                planes: 0,
                others: 0,
            };
            for &i in &order[start as usize..(start + count) as usize] {
                match item(i) {
                    Item::Triangle(s, p, v) => {
                        tris.push(v);
                        agg.tri_ids.push((s, p));
                    }
                    Item::Plane(s, t) => {
                        planes.push(t);
                        agg.plane_tests.push((t, s));
                    }
                    Item::Other(prim) => agg.others.push(prim),
                }
            }
            block::push_triangles(&mut agg.tri_data, &tris);
            block::push_planes(&mut agg.plane_data, &planes);
            agg.leaves.push(Leaf {
                tris: tris.len() as u16,
                planes: planes.len() as u16,
                others: (agg.others.len() as u32 - leaf.other_first) as u16,
                ..leaf
            });
        }
        let leaves = &agg.leaves;
        agg.bvh.relabel_leaves(|k| {
            let leaf = &leaves[k as usize];
            if leaf.planes == 0 && leaf.others == 0 && leaf.tris < MIXED {
                (leaf.tri_first, leaf.tris)
            } else {
                (k, MIXED)
            }
        });
        agg.tri_data.extend([0.0; PAD]);
        agg.plane_data.extend([0.0; PAD]);
        agg.tri_data.shrink_to_fit();
        agg.tri_ids.shrink_to_fit();
        agg.others.shrink_to_fit();
        agg.shapes = shapes;
        agg.instances = instances;
        agg
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
        self.offset_unit
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

    /// Bytes of the acceleration structure (BVH nodes, leaves, blocks and
    /// the other primitives' tests), not counting the shapes themselves.
    pub fn acceleration_bytes(&self) -> usize {
        use std::mem::size_of_val;
        self.bvh.node_bytes()
            + size_of_val(&self.leaves[..])
            + size_of_val(&self.tri_data[..])
            + size_of_val(&self.tri_ids[..])
            + size_of_val(&self.plane_data[..])
            + size_of_val(&self.plane_tests[..])
            + size_of_val(&self.others[..])
    }

    /// The closest hit within (0, ray.t_max), at the process's SIMD level
    /// (at most AVX2: [`leaf_level`]).
    #[inline]
    pub fn intersect(&self, ray: &Ray) -> Option<Hit> {
        self.intersect_at(leaf_level(Level::current()), ray)
    }

    /// Whether anything lies within (0, ray.t_max), at the process's SIMD
    /// level (at most AVX2: [`leaf_level`]).
    #[inline]
    pub fn occluded(&self, ray: &Ray) -> bool {
        self.occluded_at(leaf_level(Level::current()), ray)
    }

    /// [`Aggregate::intersect`] at SIMD level `level` (every level gives
    /// the same hit: the scalar test decides each one).
    #[inline]
    pub fn intersect_at(&self, level: Level, ray: &Ray) -> Option<Hit> {
        level.run(query::Closest { agg: self, ray })
    }

    /// [`Aggregate::occluded`] at SIMD level `level`.
    #[inline]
    pub fn occluded_at(&self, level: Level, ray: &Ray) -> bool {
        level.run(query::Occluded { agg: self, ray })
    }

    /// The closest hit of each ray, at SIMD level `level` (one dispatch for
    /// all: what a wavefront tracer calls).
    ///
    /// # Panics
    /// When `out` and `rays` differ in length.
    pub fn intersect_many(&self, level: Level, rays: &[Ray], out: &mut [Option<Hit>]) {
        assert_eq!(rays.len(), out.len(), "intersect_many: one output per ray");
        level.run(query::ClosestMany {
            agg: self,
            rays,
            out,
        });
    }

    /// Whether each ray is blocked, at SIMD level `level`.
    ///
    /// # Panics
    /// When `out` and `rays` differ in length.
    pub fn occluded_many(&self, level: Level, rays: &[Ray], out: &mut [bool]) {
        assert_eq!(rays.len(), out.len(), "occluded_many: one output per ray");
        level.run(query::OccludedMany {
            agg: self,
            rays,
            out,
        });
    }

    /// The world-space surface at `hit` (from `intersect(ray)`).
    pub fn surface(&self, hit: &Hit, ray: &Ray) -> Surface {
        match hit.instance {
            Some(k) => self.instances[k as usize].surface(hit, ray),
            None => self.shapes[hit.shape as usize].surface(hit, ray),
        }
    }
}

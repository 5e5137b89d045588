//! The aggregate's ray queries, once for the scalar tests and once for
//! each SIMD level's block tests (`Tester`), and the kernels that run
//! them at a level.

use super::block::{lanes, Planes, Triangles, WideRay};
use super::bvh::Visit;
use super::node::NodeLanes;
use super::{Aggregate, Leaf, MIXED};
use crate::geometry::{Hit, RayShear};
use crate::math::Ray;
use crate::simd::{Kernel, Level, Scalar8, Wide};

/// How a leaf's primitives are tested: which of their lanes the scalar
/// test must decide, `LANES` at a time.
pub(super) trait Tester: Copy {
    type Ray;
    /// The lanes of the 8-wide node test.
    type Lanes: NodeLanes;
    const LANES: usize;
    fn level(self) -> Level;
    fn lanes(self) -> Self::Lanes;
    fn prepare(self, ray: &Ray, shear: &RayShear) -> Self::Ray;
    /// Of lanes `base … base + LANES`, those to test, as bits from bit 0.
    fn tris(self, r: &Self::Ray, tris: &Triangles, base: usize, t_max: f32) -> u32;
    fn planes(self, r: &Self::Ray, planes: &Planes, base: usize, t_max: f32) -> u32;
}

/// The reference: every lane goes to the scalar test, in order.
#[derive(Clone, Copy)]
pub(super) struct Scalar;

impl Tester for Scalar {
    type Ray = ();
    type Lanes = Scalar8;
    const LANES: usize = 32;
    fn level(self) -> Level {
        Level::Scalar
    }
    #[inline(always)]
    fn lanes(self) -> Scalar8 {
        Scalar8
    }
    #[inline(always)]
    fn prepare(self, _: &Ray, _: &RayShear) {}
    #[inline(always)]
    fn tris(self, _: &(), _: &Triangles, _: usize, _: f32) -> u32 {
        u32::MAX
    }
    #[inline(always)]
    fn planes(self, _: &(), _: &Planes, _: usize, _: f32) -> u32 {
        u32::MAX
    }
}

/// The wide filters of `block.rs` at level `W`.
#[derive(Clone, Copy)]
pub(super) struct Wider<W>(pub W);

impl<W: Wide> Tester for Wider<W> {
    type Ray = WideRay<W>;
    type Lanes = W;
    const LANES: usize = W::LANES;
    fn level(self) -> Level {
        W::LEVEL
    }
    #[inline(always)]
    fn lanes(self) -> W {
        self.0
    }
    #[inline(always)]
    fn prepare(self, ray: &Ray, shear: &RayShear) -> WideRay<W> {
        WideRay::new(self.0, ray, shear)
    }
    #[inline(always)]
    fn tris(self, r: &WideRay<W>, tris: &Triangles, base: usize, t_max: f32) -> u32 {
        tris.candidates(self.0, r, t_max, base)
    }
    #[inline(always)]
    fn planes(self, r: &WideRay<W>, planes: &Planes, base: usize, t_max: f32) -> u32 {
        planes.candidates(self.0, r, t_max, base)
    }
}

impl Aggregate {
    /// Tests `leaf` against `ray` within (0, t_max), in its order
    /// (triangles, planar shapes, the others): `Some` with a closer t_max
    /// when something is hit (the nearest kept in `best`), and with `true`
    /// at the first hit when `ANY`.
    #[allow(clippy::too_many_arguments)]
    #[inline(always)]
    fn test_leaf<T: Tester, const ANY: bool>(
        &self,
        tester: T,
        r: &T::Ray,
        ray: &Ray,
        shear: &RayShear,
        leaf: &Leaf,
        mut t_max: f32,
        best: &mut Option<Hit>,
    ) -> Option<(f32, bool)> {
        let mut any = false;
        if leaf.tris > 0 {
            let tris = self.triangles(leaf);
            let mut base = 0;
            while base < tris.n {
                let mut m = tester.tris(r, &tris, base, t_max) & lanes(tris.n - base);
                while m != 0 {
                    let l = base + m.trailing_zeros() as usize;
                    m &= m - 1;
                    if let Some((t, uv)) = tris.hit_lane(l, ray, shear, t_max) {
                        if ANY {
                            return Some((t, true));
                        }
                        t_max = t;
                        any = true;
                        let (shape, prim) = self.tri_ids[leaf.tri_first as usize + l];
                        *best = Some(Hit {
                            t,
                            shape,
                            prim,
                            uv,
                            instance: None,
                        });
                    }
                }
                base += T::LANES;
            }
        }
        if leaf.planes > 0 {
            let planes = self.planar(leaf);
            let mut base = 0;
            while base < planes.n {
                let mut m = tester.planes(r, &planes, base, t_max) & lanes(planes.n - base);
                while m != 0 {
                    let l = base + m.trailing_zeros() as usize;
                    m &= m - 1;
                    let (test, shape) = &self.plane_tests[leaf.plane_first as usize + l];
                    if let Some((t, uv)) = test.intersect(ray, t_max) {
                        if ANY {
                            return Some((t, true));
                        }
                        t_max = t;
                        any = true;
                        *best = Some(Hit {
                            t,
                            shape: *shape,
                            prim: 0,
                            uv,
                            instance: None,
                        });
                    }
                }
                base += T::LANES;
            }
        }
        if leaf.others > 0 {
            let first = leaf.other_first as usize;
            for prim in &self.others[first..first + leaf.others as usize] {
                let hit = match prim.instance() {
                    Some(k) if ANY => {
                        if self.instances[k as usize].occluded_at(tester.level(), ray, t_max) {
                            return Some((t_max, true));
                        }
                        continue;
                    }
                    Some(k) => {
                        match self.instances[k as usize].intersect_at(tester.level(), ray, t_max, k)
                        {
                            Some(hit) => hit,
                            None => continue,
                        }
                    }
                    None => match prim.intersect(ray, t_max) {
                        Some((t, uv)) => Hit {
                            t,
                            shape: prim.shape,
                            prim: prim.index,
                            uv,
                            instance: None,
                        },
                        None => continue,
                    },
                };
                if ANY {
                    return Some((hit.t, true));
                }
                t_max = hit.t;
                any = true;
                *best = Some(hit);
            }
        }
        any.then_some((t_max, false))
    }

    /// The closest hit within (0, ray.t_max), or with `ANY` the first.
    #[inline(always)]
    fn query<T: Tester, const ANY: bool>(&self, tester: T, ray: &Ray) -> Option<Hit> {
        let shear = RayShear::new(ray);
        let mut visit = Visitor::<T, ANY> {
            agg: self,
            tester,
            r: tester.prepare(ray, &shear),
            ray,
            shear,
            best: None,
            any: false,
        };
        // Any-hit queries skip sorting a node's children by distance.
        if ANY {
            self.bvh
                .traverse::<false, _>(tester.lanes(), ray, ray.t_max, &mut visit);
        } else {
            self.bvh
                .traverse::<true, _>(tester.lanes(), ray, ray.t_max, &mut visit);
        }
        if ANY && visit.any {
            // Any hit will do: a placeholder at the ray's end.
            return Some(visit.best.unwrap_or(Hit {
                t: ray.t_max,
                shape: u32::MAX,
                prim: u32::MAX,
                uv: [0.0; 2],
                instance: None,
            }));
        }
        visit.best
    }

    #[inline(always)]
    fn closest<T: Tester>(&self, tester: T, ray: &Ray) -> Option<Hit> {
        self.query::<T, false>(tester, ray)
    }

    #[inline(always)]
    fn any_hit<T: Tester>(&self, tester: T, ray: &Ray) -> bool {
        self.query::<T, true>(tester, ray).is_some()
    }
}

/// The traversal's leaf step for one ray.
struct Visitor<'a, T: Tester, const ANY: bool> {
    agg: &'a Aggregate,
    tester: T,
    r: T::Ray,
    ray: &'a Ray,
    shear: RayShear,
    best: Option<Hit>,
    any: bool,
}

impl<T: Tester, const ANY: bool> Visit for &mut Visitor<'_, T, ANY> {
    #[inline(always)]
    fn leaf(&mut self, child: u32, count: u16, t_max: f32) -> Option<(f32, bool)> {
        // Triangles alone: in the node's words (`Aggregate::built_with`).
        let only_tris;
        let leaf = if count & MIXED == 0 {
            only_tris = Leaf {
                tri_first: child,
                plane_first: 0,
                other_first: 0,
                tris: count,
                planes: 0,
                others: 0,
            };
            &only_tris
        } else {
            &self.agg.leaves[child as usize]
        };
        let r = self.agg.test_leaf::<T, ANY>(
            self.tester,
            &self.r,
            self.ray,
            &self.shear,
            leaf,
            t_max,
            &mut self.best,
        );
        self.any |= r.is_some();
        r
    }
}

pub(super) struct Closest<'a> {
    pub agg: &'a Aggregate,
    pub ray: &'a Ray,
}

impl Kernel for Closest<'_> {
    type Output = Option<Hit>;
    fn scalar(self) -> Option<Hit> {
        self.agg.closest(Scalar, self.ray)
    }
    #[inline(always)]
    fn wide<W: Wide>(self, s: W) -> Option<Hit> {
        self.agg.closest(Wider(s), self.ray)
    }
}

pub(super) struct Occluded<'a> {
    pub agg: &'a Aggregate,
    pub ray: &'a Ray,
}

impl Kernel for Occluded<'_> {
    type Output = bool;
    fn scalar(self) -> bool {
        self.agg.any_hit(Scalar, self.ray)
    }
    #[inline(always)]
    fn wide<W: Wide>(self, s: W) -> bool {
        self.agg.any_hit(Wider(s), self.ray)
    }
}

pub(super) struct ClosestMany<'a> {
    pub agg: &'a Aggregate,
    pub rays: &'a [Ray],
    pub out: &'a mut [Option<Hit>],
}

impl Kernel for ClosestMany<'_> {
    type Output = ();
    fn scalar(self) {
        for (o, ray) in self.out.iter_mut().zip(self.rays) {
            *o = self.agg.closest(Scalar, ray);
        }
    }
    #[inline(always)]
    fn wide<W: Wide>(self, s: W) {
        for (o, ray) in self.out.iter_mut().zip(self.rays) {
            *o = self.agg.closest(Wider(s), ray);
        }
    }
}

pub(super) struct OccludedMany<'a> {
    pub agg: &'a Aggregate,
    pub rays: &'a [Ray],
    pub out: &'a mut [bool],
}

impl Kernel for OccludedMany<'_> {
    type Output = ();
    fn scalar(self) {
        for (o, ray) in self.out.iter_mut().zip(self.rays) {
            *o = self.agg.any_hit(Scalar, ray);
        }
    }
    #[inline(always)]
    fn wide<W: Wide>(self, s: W) {
        for (o, ray) in self.out.iter_mut().zip(self.rays) {
            *o = self.agg.any_hit(Wider(s), ray);
        }
    }
}

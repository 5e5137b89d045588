//! The wide block tests against the scalar ones: on several scenes, rays
//! at random and rays aimed at vertices and edges, every SIMD level must
//! give the scalar traversal's hit (same t, same primitive) and the same
//! occlusion; and the scalar traversal the brute-force nearest t.

use std::sync::Arc;

use super::*;
use crate::geometry::{Cylinder, Planar, PlanarKind, Sphere, TriangleMesh};
use crate::math::Transform;
use crate::test_rng::Rng;

fn mesh(positions: Vec<Vec3>, indices: Vec<[u32; 3]>) -> Shape {
    Shape::Mesh(TriangleMesh::new(positions, None, None, indices, &Transform::IDENTITY).unwrap())
}

/// `n` random triangles in [−1, 1]³, some of them tiny or degenerate.
fn soup(rng: &mut Rng, n: usize) -> Shape {
    let mut positions = Vec::new();
    for k in 0..n {
        let c = rng.vec(-1.0, 1.0);
        let size = [0.3, 0.05, 1e-4][k % 3];
        positions.push(c + rng.vec(-size, size));
        positions.push(c + rng.vec(-size, size));
        positions.push(if k % 17 == 0 {
            positions[positions.len() - 1]
        } else {
            c + rng.vec(-size, size)
        });
    }
    let indices = (0..n as u32)
        .map(|k| [3 * k, 3 * k + 1, 3 * k + 2])
        .collect();
    mesh(positions, indices)
}

/// A displaced grid over [−1, 1]² of 2·n² triangles sharing edges and
/// vertices.
fn grid(n: usize, scale: f32) -> Shape {
    let mut positions = Vec::new();
    for j in 0..=n {
        for i in 0..=n {
            let (x, y) = (
                2.0 * i as f32 / n as f32 - 1.0,
                2.0 * j as f32 / n as f32 - 1.0,
            );
            positions.push(Vec3::new(x, y, 0.2 * (3.0 * x).sin() * (2.0 * y).cos()) * scale);
        }
    }
    let w = (n + 1) as u32;
    let mut indices = Vec::new();
    for j in 0..n as u32 {
        for i in 0..n as u32 {
            let v = j * w + i;
            indices.push([v, v + 1, v + w + 1]);
            indices.push([v, v + w + 1, v + w]);
        }
    }
    mesh(positions, indices)
}

fn mixed() -> Vec<Shape> {
    vec![
        grid(6, 1.0),
        Shape::Sphere(Sphere::new(Vec3::new(0.3, -0.2, 0.4), 0.25)),
        Shape::Planar(Box::new(Planar::new(
            PlanarKind::Rectangle,
            Transform::translate(Vec3::new(0.0, 0.0, -0.5)),
        ))),
        Shape::Planar(Box::new(Planar::new(
            PlanarKind::Disk,
            Transform::translate(Vec3::new(0.2, 0.1, 0.6))
                .then_after(&Transform::rotate(Vec3::new(1.0, 0.0, 0.0), 60.0).unwrap()),
        ))),
        Shape::Cylinder(Box::new(
            Cylinder::new(
                Vec3::new(-0.5, -0.5, -0.5),
                Vec3::new(-0.4, -0.3, 0.7),
                0.1,
                &Transform::IDENTITY,
                false,
            )
            .unwrap(),
        )),
    ]
}

/// Random rays, and rays through the vertices, edge points and centres
/// of the scene's triangles.
fn rays(rng: &mut Rng, shapes: &[Shape], scale: f32, n: usize) -> Vec<Ray> {
    let mut targets: Vec<Vec3> = Vec::new();
    for s in shapes {
        if let Shape::Mesh(m) = s {
            for f in (0..m.triangle_count()).step_by(1 + m.triangle_count() / 200) {
                let (a, b, c) = m.vertices(f);
                targets.extend([
                    a,
                    b,
                    c,
                    (a + b) * 0.5,
                    a + (c - a) * 0.25,
                    (a + b + c) / 3.0,
                ]);
            }
        }
    }
    let mut out = Vec::new();
    for k in 0..n {
        let o = rng.vec(-2.0 * scale, 2.0 * scale);
        let d = if k % 2 == 0 && !targets.is_empty() {
            targets[k / 2 % targets.len()] - o
        } else {
            rng.vec(-1.0, 1.0)
        };
        let mut ray = Ray::new(o, d.normalize());
        if k % 5 == 0 {
            ray.t_max = rng.next() * 3.0 * scale;
        }
        // Axis-aligned directions (zero components, infinite 1/d).
        if k % 23 == 0 {
            ray.d = Vec3::new(0.0, 0.0, if k % 2 == 0 { 1.0 } else { -1.0 });
        }
        out.push(ray);
    }
    out
}

/// The nearest t over every primitive, tested one by one.
fn brute_force(agg: &Aggregate, ray: &Ray) -> Option<f32> {
    let shear = crate::geometry::RayShear::new(ray);
    let mut best: Option<f32> = None;
    for shape in &agg.shapes {
        for p in 0..shape.primitive_count() {
            let t_max = best.unwrap_or(ray.t_max);
            if let Some((t, _)) = shape.intersect(p, ray, &shear, t_max) {
                best = Some(t);
            }
        }
    }
    for (k, inst) in agg.instances().iter().enumerate() {
        if let Some(h) = inst.intersect_at(Level::Scalar, ray, best.unwrap_or(ray.t_max), k as u32)
        {
            best = Some(h.t);
        }
    }
    best
}

fn check(name: &str, agg: &Aggregate, rays: &[Ray]) {
    let mut hits = 0;
    for (i, ray) in rays.iter().enumerate() {
        let want = agg.intersect_at(Level::Scalar, ray);
        let blocked = agg.occluded_at(Level::Scalar, ray);
        assert_eq!(want.is_some(), blocked, "{name}: ray {i} {ray:?}");
        // The same t to a few ULPs: the division-free distance test
        // (t_scaled against t_max · det) rounds, so two hits within an ULP
        // (a shared edge) may be kept in either order.
        let brute = brute_force(agg, ray);
        assert_eq!(want.is_some(), brute.is_some(), "{name}: ray {i} {ray:?}");
        if let (Some(h), Some(t)) = (want, brute) {
            assert!(
                (h.t - t).abs() <= 4.0 * f32::EPSILON * t,
                "{name}: ray {i} {ray:?}: BVH {} against brute force {t}",
                h.t
            );
        }
        hits += want.is_some() as usize;
        for level in Level::available() {
            let got = agg.intersect_at(level, ray);
            assert_eq!(
                got.map(|h| (
                    h.t.to_bits(),
                    h.shape,
                    h.prim,
                    h.uv.map(f32::to_bits),
                    h.instance
                )),
                want.map(|h| (
                    h.t.to_bits(),
                    h.shape,
                    h.prim,
                    h.uv.map(f32::to_bits),
                    h.instance
                )),
                "{name}: ray {i} {ray:?} at {level}"
            );
            assert_eq!(
                agg.occluded_at(level, ray),
                blocked,
                "{name}: ray {i} at {level}"
            );
        }
    }
    // The rays are not all misses (nor all hits).
    assert!(
        hits > rays.len() / 10 && hits < rays.len(),
        "{name}: {hits} hits"
    );
    for level in Level::available() {
        let mut many = vec![None; rays.len()];
        agg.intersect_many(level, rays, &mut many);
        let mut blocked = vec![false; rays.len()];
        agg.occluded_many(level, rays, &mut blocked);
        for (i, ray) in rays.iter().enumerate() {
            assert_eq!(
                many[i],
                agg.intersect_at(Level::Scalar, ray),
                "{name}: {i} {level}"
            );
            assert_eq!(blocked[i], many[i].is_some(), "{name}: {i} {level}");
        }
    }
}

/// `check` on the aggregate built with the default leaves and with leaves
/// of up to 16 for the widest level.
fn check_builds(name: &str, shapes: Vec<Shape>, instances: Vec<Instance>, rays: &[Ray]) {
    for cost in [LeafCost::SCALAR, LeafCost::wide(Level::best().lanes())] {
        for width in [Width::Four, Width::Eight] {
            let agg = Aggregate::built_with(&cost, width, shapes.clone(), instances.clone());
            check(&format!("{name} ({cost:?}, {width:?})"), &agg, rays);
        }
    }
}

#[test]
fn wide_block_tests_give_the_scalar_hits() {
    let mut rng = Rng(42);
    let soup_shapes = vec![soup(&mut rng, 600)];
    let r = rays(&mut rng, &soup_shapes, 1.0, 3000);
    check_builds("soup", soup_shapes, Vec::new(), &r);

    let grid_shapes = vec![grid(24, 1.0)];
    let r = rays(&mut rng, &grid_shapes, 1.0, 3000);
    check_builds("grid", grid_shapes, Vec::new(), &r);

    let shapes = mixed();
    let r = rays(&mut rng, &shapes, 1.0, 3000);
    check_builds("mixed", shapes, Vec::new(), &r);

    // A few primitives: one leaf.
    let tiny = vec![grid(2, 1.0)];
    let r = rays(&mut rng, &tiny, 1.0, 1000);
    check_builds("tiny", tiny, Vec::new(), &r);

    // Scales where the scaled distance leaves f32 (the f64 finish).
    for scale in [1e-14f32, 1e14] {
        let big = vec![grid(5, scale)];
        let r = rays(&mut rng, &big, scale, 1000);
        check_builds(&format!("scale {scale:e}"), big, Vec::new(), &r);
    }

    // Instances of a group, beside a mesh.
    let group = Arc::new(ShapeGroup::new(mixed(), 1));
    let instances = (0..6)
        .map(|k| {
            Instance::new(
                group.clone(),
                Transform::translate(Vec3::new(k as f32 * 0.7 - 2.0, 0.0, 0.0))
                    .then_after(&Transform::scale(Vec3::splat(0.4)).unwrap()),
            )
        })
        .collect();
    let world = vec![grid(4, 2.0)];
    let r = rays(&mut rng, &world, 1.5, 2000);
    check_builds("instances", world, instances, &r);
}

/// Brute-force leaves (one leaf of more than 32 primitives: several
/// registers and mask words) give the same hits.
#[test]
fn one_big_leaf_gives_the_scalar_hits() {
    let mut rng = Rng(7);
    let mut shapes = mixed();
    shapes[0] = grid(4, 1.0);
    let r = rays(&mut rng, &shapes, 1.0, 2000);
    let bounds: Vec<Aabb> = shapes
        .iter()
        .flat_map(|s| (0..s.primitive_count()).map(move |p| s.bounds(p)))
        .collect();
    let cost = LeafCost {
        brute_force: 1000,
        ..LeafCost::wide(Level::best().lanes())
    };
    let agg = Aggregate::built_with(&cost, Width::Eight, shapes, Vec::new());
    assert_eq!(agg.leaves.len(), 1, "{} primitives", bounds.len());
    check("one leaf", &agg, &r);
}

/// The 8-wide tree on random triangles: at every level, the closest hit
/// of each random ray is brute force's (the same t within the rounding
/// of the division-free distance test), and a ray is blocked exactly when
/// it hits; the tree really is 8-wide (fewer nodes than the 4-wide one).
#[test]
fn eight_wide_nodes_find_the_brute_force_hits_at_every_level() {
    let mut rng = Rng(2024);
    for (n, cost) in [(300, LeafCost::SCALAR), (5000, LeafCost::wide(8))] {
        let shapes = vec![soup(&mut rng, n)];
        let r = rays(&mut rng, &shapes, 1.0, 2000);
        let four = Aggregate::built_with(&cost, Width::Four, shapes.clone(), Vec::new());
        let agg = Aggregate::built_with(&cost, Width::Eight, shapes, Vec::new());
        assert_eq!(agg.bvh().width(), Width::Eight);
        assert!(
            agg.bvh().node_count() < four.bvh().node_count(),
            "{} 8-wide nodes against {} 4-wide",
            agg.bvh().node_count(),
            four.bvh().node_count()
        );
        let mut hits = 0;
        for (i, ray) in r.iter().enumerate() {
            let want = brute_force(&agg, ray);
            hits += want.is_some() as usize;
            for level in Level::available() {
                let got = agg.intersect_at(level, ray);
                assert_eq!(got.is_some(), want.is_some(), "{n}: ray {i} at {level}");
                if let (Some(h), Some(t)) = (got, want) {
                    assert!(
                        (h.t - t).abs() <= 4.0 * f32::EPSILON * t,
                        "{n}: ray {i} at {level}: {} against brute force {t}",
                        h.t
                    );
                }
                assert_eq!(
                    agg.occluded_at(level, ray),
                    want.is_some(),
                    "{n}: ray {i} at {level}"
                );
                // The same tree at 4 wide gives the same hit.
                assert_eq!(
                    got,
                    four.intersect_at(level, ray),
                    "{n}: ray {i} at {level}"
                );
            }
        }
        assert!(hits > r.len() / 10 && hits < r.len(), "{n}: {hits} hits");
    }
}

/// A ray with a NaN or infinite coordinate meets nothing, at every level
/// and width, for one query and many, and the traversal returns. A NaN
/// direction's slab distances are NaN, which pass every box, the unused
/// slots' empty boxes too; those slots' child word is node 0, so the walk
/// went back to the root without end, recursing each time its stack
/// filled, until the thread's stack overflowed (a shadow ray of NaN
/// direction in the foggy street, `integrator::direct::shadow_ray`).
#[test]
fn a_ray_with_a_nan_or_infinite_coordinate_meets_nothing() {
    let (nan, inf) = (f32::NAN, f32::INFINITY);
    let d = Vec3::new(0.0, 0.0, 1.0);
    let o = Vec3::new(0.1, 0.2, -3.0);
    let bad = [
        Ray::new(o, Vec3::splat(nan)),
        Ray::new(o, Vec3::new(0.0, nan, 1.0)),
        Ray::new(Vec3::new(nan, 0.2, -3.0), d),
        Ray::new(Vec3::splat(inf), d),
        Ray::new(o, Vec3::new(0.0, -inf, inf)),
    ];
    for (name, shapes) in [("mixed", mixed()), ("tiny", vec![grid(2, 1.0)])] {
        for width in [Width::Four, Width::Eight] {
            let agg = Aggregate::built_with(&LeafCost::SCALAR, width, shapes.clone(), Vec::new());
            for level in Level::available() {
                // The ray they spoil does hit.
                assert!(agg.intersect_at(level, &Ray::new(o, d)).is_some());
                for (i, ray) in bad.iter().enumerate() {
                    let at = format!("{name}, {width:?}, {level}: ray {i}");
                    assert_eq!(agg.intersect_at(level, ray), None, "{at}");
                    assert!(!agg.occluded_at(level, ray), "{at}");
                }
                let mut hits = vec![None; bad.len()];
                agg.intersect_many(level, &bad, &mut hits);
                assert!(
                    hits.iter().all(Option::is_none),
                    "{name}, {width:?}, {level}"
                );
                let mut blocked = vec![true; bad.len()];
                agg.occluded_many(level, &bad, &mut blocked);
                assert!(!blocked.iter().any(|&b| b), "{name}, {width:?}, {level}");
            }
        }
    }
}

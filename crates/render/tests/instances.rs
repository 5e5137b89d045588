//! Instances of shape groups against the same geometry copied into the
//! world: every ray finds the same hit (the group's shape and primitive,
//! at the same world-space distance) and the same surface (position,
//! normals, uv, dpdu, dpdv), under rotation, translation and a
//! non-uniform scale; shadow rays are blocked by instances exactly where
//! the copies block them; every instance shares its group's one copy of
//! the triangles; and a non-uniformly scaled sphere instance is the
//! ellipsoid, with the implicit surface's normal.

mod common;

use common::Rng;
use std::sync::Arc;

use scotopia_render::accel::{Aggregate, Instance, ShapeGroup};
use scotopia_render::geometry::{Planar, PlanarKind, Shape, Sphere, Surface, TriangleMesh};
use scotopia_render::math::{Frame, Ray, Transform, Vec3};

/// A bumpy latitude–longitude ball (unit size) with smooth normals and
/// texture coordinates, placed by `world_from_object`.
fn ball(world_from_object: &Transform) -> TriangleMesh {
    let (rows, cols) = (9u32, 14u32);
    let mut positions = Vec::new();
    let mut normals = Vec::new();
    let mut uvs = Vec::new();
    for i in 0..=rows {
        for j in 0..=cols {
            let (u, v) = (j as f32 / cols as f32, i as f32 / rows as f32);
            let (theta, phi) = (v * std::f32::consts::PI, u * std::f32::consts::TAU);
            let n = Vec3::new(
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos(),
            );
            let r = 1.0 + 0.1 * (3.0 * phi).sin() * theta.sin();
            positions.push(n * r);
            normals.push(n);
            uvs.push([u, v]);
        }
    }
    let at = |i: u32, j: u32| i * (cols + 1) + j;
    let mut indices = Vec::new();
    for i in 0..rows {
        for j in 0..cols {
            indices.push([at(i, j), at(i + 1, j), at(i + 1, j + 1)]);
            indices.push([at(i, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    TriangleMesh::new(
        positions,
        Some(normals),
        Some(uvs),
        indices,
        world_from_object,
    )
    .unwrap()
}

/// The group's shapes, in its own space, placed by `t`: a mesh, a
/// rectangle and (when `t` is a similarity, the only placement a
/// sphere can be copied under) a sphere.
fn shapes(t: &Transform, with_sphere: bool) -> Vec<Shape> {
    let rect = Transform::translate(Vec3::new(0.0, 0.0, -1.5))
        .then_after(&Transform::rotate(Vec3::new(1.0, 0.0, 0.0), 20.0).unwrap())
        .then_after(&Transform::scale(Vec3::new(2.0, 1.5, 1.0)).unwrap());
    let mut v = vec![
        Shape::Mesh(ball(t)),
        Shape::Planar(Box::new(Planar::new(
            PlanarKind::Rectangle,
            t.then_after(&rect),
        ))),
    ];
    if with_sphere {
        // The sphere's frame turns with it (its uv follow the placement).
        let axes = [
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ]
        .map(|a| t.vector(a));
        let s = axes[0].length();
        let frame = Frame {
            s: axes[0] / s,
            t: axes[1] / s,
            n: axes[2] / s,
        };
        let c = Vec3::new(1.6, 0.4, 0.2);
        v.push(Shape::Sphere(Sphere::oriented(t.point(c), 0.5 * s, frame)));
    }
    v
}

/// Placements: a rotated, uniformly scaled one (with a sphere in its
/// group) and rotated, non-uniformly scaled ones (without).
fn placements() -> Vec<(Transform, bool)> {
    let rot = |axis: Vec3, deg: f32| Transform::rotate(axis, deg).unwrap();
    let scale = |v: Vec3| Transform::scale(v).unwrap();
    vec![
        (
            Transform::translate(Vec3::new(-3.0, 0.5, 0.0))
                .then_after(&rot(Vec3::new(0.3, 1.0, 0.2), 35.0))
                .then_after(&scale(Vec3::splat(1.3))),
            true,
        ),
        (
            Transform::translate(Vec3::new(3.0, -0.5, 1.0))
                .then_after(&rot(Vec3::new(1.0, 0.2, 0.0), -50.0))
                .then_after(&scale(Vec3::new(2.0, 0.6, 1.1))),
            false,
        ),
        (
            Transform::translate(Vec3::new(0.0, 2.5, -1.0))
                .then_after(&scale(Vec3::new(0.7, 1.0, 2.5)))
                .then_after(&rot(Vec3::new(0.0, 0.0, 1.0), 70.0)),
            false,
        ),
    ]
}

/// The same world twice: instances of two groups (one with a sphere, one
/// without) and a top-level floor; and the floor followed by each
/// placement's shapes copied, in the group's order.
fn worlds() -> (Aggregate, Aggregate) {
    let floor = || {
        Shape::Planar(Box::new(Planar::new(
            PlanarKind::Rectangle,
            Transform::translate(Vec3::new(0.0, -3.0, 0.0))
                .then_after(&Transform::rotate(Vec3::new(1.0, 0.0, 0.0), -90.0).unwrap())
                .then_after(&Transform::scale(Vec3::splat(8.0)).unwrap()),
        )))
    };
    let with = Arc::new(ShapeGroup::new(shapes(&Transform::IDENTITY, true), 1));
    let without = Arc::new(ShapeGroup::new(shapes(&Transform::IDENTITY, false), 4));
    let mut instances = Vec::new();
    let mut copied = vec![floor()];
    for (t, sphere) in placements() {
        let group = if sphere { &with } else { &without };
        instances.push(Instance::new(group.clone(), t));
        copied.extend(shapes(&t, sphere));
    }
    (
        Aggregate::with_instances(vec![floor()], instances),
        Aggregate::new(copied),
    )
}

/// Index of the copied shape that instance `k`'s hit on its group's shape
/// `local` corresponds to.
fn copied_shape(k: u32, local: u32) -> u32 {
    let sizes: Vec<u32> = placements()
        .iter()
        .map(|p| if p.1 { 3 } else { 2 })
        .collect();
    1 + sizes[..k as usize].iter().sum::<u32>() + local
}

fn close(a: Vec3, b: Vec3, tol: f32) -> bool {
    (a - b).length() <= tol * (1.0 + a.length().max(b.length()))
}

/// Rays from around the scene towards points near the instances.
fn rays(n: usize, seed: u64) -> Vec<Ray> {
    let mut rng = Rng(seed);
    let targets: Vec<Vec3> = placements()
        .iter()
        .map(|(t, _)| t.point(Vec3::ZERO))
        .collect();
    (0..n)
        .map(|i| {
            let o = rng.point(10.0);
            let target = targets[i % targets.len()] + rng.point(2.5);
            Ray::new(o, (target - o).normalize())
        })
        .collect()
}

#[test]
fn instances_hit_and_shade_as_their_copies() {
    let (inst, copy) = worlds();
    let (mut on_instances, mut on_spheres) = (0, 0);
    for ray in rays(4000, 7) {
        let (a, b) = (inst.intersect(&ray), copy.intersect(&ray));
        let (Some(a), Some(b)) = (a, b) else {
            assert_eq!(a.is_some(), b.is_some(), "{ray:?}: {a:?} vs {b:?}");
            continue;
        };
        assert!(
            (a.t - b.t).abs() <= 1e-5 * a.t,
            "{ray:?}: t {} vs {}",
            a.t,
            b.t
        );
        let Some(k) = a.instance else {
            assert_eq!((a.shape, a.prim, b.shape), (0, 0, 0));
            continue;
        };
        on_instances += 1;
        let group = inst.instances()[k as usize].group();
        let local = a.shape - group.first_shape();
        assert_eq!(
            (copied_shape(k, local), a.prim),
            (b.shape, b.prim),
            "{ray:?}"
        );
        on_spheres += matches!(group.shapes()[local as usize], Shape::Sphere(_)) as u32;
        let (s, c): (Surface, Surface) = (inst.surface(&a, &ray), copy.surface(&b, &ray));
        let what = format!("{ray:?} on instance {k}, shape {local}:\n{s:?}\n{c:?}");
        assert!(close(s.p, c.p, 1e-5), "p: {what}");
        assert!(close(s.n_geometric, c.n_geometric, 1e-4), "ng: {what}");
        assert!(close(s.n_shading, c.n_shading, 1e-4), "ns: {what}");
        assert!(
            (s.uv[0] - c.uv[0]).abs() < 1e-4 && (s.uv[1] - c.uv[1]).abs() < 1e-4,
            "uv: {what}"
        );
        assert!(close(s.dpdu, c.dpdu, 1e-4), "dpdu: {what}");
        assert!(close(s.dpdv, c.dpdv, 1e-4), "dpdv: {what}");
    }
    // The comparison reached every kind of surface.
    assert!(
        on_instances > 1000 && on_spheres > 50,
        "{on_instances} {on_spheres}"
    );
}

#[test]
fn shadow_rays_are_blocked_by_instances_as_by_copies() {
    let (inst, copy) = worlds();
    let mut hits = 0;
    for ray in rays(4000, 11) {
        let Some(hit) = copy.intersect(&ray) else {
            assert!(!inst.occluded(&ray), "{ray:?}");
            continue;
        };
        // Just past the nearest hit, the segment is blocked; just short
        // of it, clear (unless the hit is on the floor, nothing nearer).
        let past = Ray {
            t_max: hit.t * 1.001,
            ..ray
        };
        let short = Ray {
            t_max: hit.t * 0.999,
            ..ray
        };
        assert!(inst.occluded(&past), "{past:?}");
        assert_eq!(inst.occluded(&short), copy.occluded(&short), "{short:?}");
        assert!(!inst.occluded(&short), "{short:?}");
        hits += 1;
    }
    assert!(hits > 1000, "{hits}");
}

#[test]
fn ten_thousand_instances_hold_one_copy_of_the_triangles() {
    let group = Arc::new(ShapeGroup::new(
        vec![Shape::Mesh(ball(&Transform::IDENTITY))],
        0,
    ));
    let per_tree = group.geometry().stored_triangles();
    assert_eq!(per_tree, 9 * 14 * 2);
    let instances: Vec<Instance> = (0..10_000)
        .map(|i| {
            let (x, z) = ((i % 100) as f32 * 3.0, (i / 100) as f32 * 3.0);
            Instance::new(group.clone(), Transform::translate(Vec3::new(x, 0.0, z)))
        })
        .collect();
    let forest = Aggregate::with_instances(Vec::new(), instances);
    assert_eq!(forest.instances().len(), 10_000);
    assert_eq!(forest.groups().len(), 1);
    assert_eq!(forest.stored_triangles(), per_tree);
    // Every instance refers to the one group: no copy was made.
    assert_eq!(Arc::strong_count(&group), 10_001);
    // The last tree of the forest is found where it was placed (near the
    // ball's pole, at object z = 1).
    let ray = Ray::new(Vec3::new(297.01, 0.01, 310.0), Vec3::new(0.0, 0.0, -1.0));
    let hit = forest.intersect(&ray).unwrap();
    assert_eq!(hit.instance, Some(9_999));
    let s = forest.surface(&hit, &ray);
    assert!(
        (hit.t - 12.0).abs() < 1e-2 && (s.p.z - 298.0).abs() < 1e-2,
        "{hit:?} {s:?}"
    );
}

#[test]
fn a_non_uniformly_scaled_sphere_instance_is_an_ellipsoid() {
    // Semi-axes (2, 1, 0.5), turned 30° about z and moved.
    let axes = Vec3::new(2.0, 1.0, 0.5);
    let place = Transform::translate(Vec3::new(1.0, -2.0, 3.0))
        .then_after(&Transform::rotate(Vec3::new(0.0, 0.0, 1.0), 30.0).unwrap())
        .then_after(&Transform::scale(axes).unwrap());
    let group = Arc::new(ShapeGroup::new(
        vec![Shape::Sphere(Sphere::new(Vec3::ZERO, 1.0))],
        0,
    ));
    let world = Aggregate::with_instances(Vec::new(), vec![Instance::new(group, place)]);
    let mut rng = Rng(3);
    let mut hits = 0;
    for _ in 0..500 {
        let o = place.point(rng.point(6.0));
        let target = place.point(rng.point(0.9));
        let ray = Ray::new(o, (target - o).normalize());
        let Some(hit) = world.intersect(&ray) else {
            continue;
        };
        hits += 1;
        let s = world.surface(&hit, &ray);
        // The hit lies on the ellipsoid, at world distance t along the ray.
        assert!(close(s.p, ray.at(hit.t), 1e-5), "{s:?}");
        let q = place.inverse().point(s.p);
        let on = q.length_squared();
        assert!((on - 1.0).abs() < 1e-4, "{q:?}");
        // Its normal is the gradient of the implicit surface, in world
        // space: the inverse transpose of the placement applied to q.
        let n = place.normal(q).normalize();
        assert!(
            close(s.n_geometric, n, 1e-4) && close(s.n_shading, n, 1e-4),
            "{s:?} {n:?}"
        );
        // Tangents lie in the tangent plane.
        assert!(s.dpdu.normalize().dot(n).abs() < 1e-3 && s.dpdv.normalize().dot(n).abs() < 1e-3);
        // A shadow ray stopping short of the hit passes; past it, not.
        let short = Ray {
            t_max: hit.t * 0.999,
            ..ray
        };
        let past = Ray {
            t_max: hit.t * 1.001,
            ..ray
        };
        assert!(!world.occluded(&short) && world.occluded(&past));
    }
    assert!(hits > 200, "{hits}");
}

//! The BVH finds exactly the hits a brute-force loop over every primitive
//! finds, on random, degenerate and mixed scenes.

mod common;

use common::Rng;
use scotopia_render::accel::Aggregate;
use scotopia_render::geometry::{Planar, PlanarKind, RayShear, Shape, Sphere, TriangleMesh};
use scotopia_render::math::{Ray, Transform, Vec3};

fn brute_force(shapes: &[Shape], ray: &Ray) -> Option<f32> {
    let shear = RayShear::new(ray);
    let mut t_max = ray.t_max;
    let mut best = None;
    for s in shapes {
        for p in 0..s.primitive_count() {
            if let Some((t, _)) = s.intersect(p, ray, &shear, t_max) {
                t_max = t;
                best = Some(t);
            }
        }
    }
    best
}

fn mesh(positions: Vec<Vec3>, indices: Vec<[u32; 3]>) -> Shape {
    Shape::Mesh(TriangleMesh::new(positions, None, None, indices, &Transform::IDENTITY).unwrap())
}

fn random_mesh(rng: &mut Rng, n: usize) -> Shape {
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    for i in 0..n {
        let c = rng.point(4.0);
        let size = 0.05 + rng.next() * 0.6;
        for _ in 0..3 {
            positions.push(c + rng.point(size));
        }
        let b = 3 * i as u32;
        indices.push([b, b + 1, b + 2]);
    }
    mesh(positions, indices)
}

fn degenerate_mesh(rng: &mut Rng) -> Shape {
    let mut positions = Vec::new();
    let mut indices = Vec::new();
    let mut push = |tri: [Vec3; 3], positions: &mut Vec<Vec3>| {
        let b = positions.len() as u32;
        positions.extend_from_slice(&tri);
        indices.push([b, b + 1, b + 2]);
    };
    for _ in 0..200 {
        let a = rng.point(3.0);
        let d = rng.direction();
        // A point, a segment, and collinear vertices.
        push([a, a, a], &mut positions);
        push([a, a + d, a + d], &mut positions);
        push([a, a + d * 0.5, a + d], &mut positions);
    }
    // Many copies of one triangle: all centroids coincide.
    let tri = [
        Vec3::new(-1.0, -1.0, 0.5),
        Vec3::new(1.0, -1.0, 0.5),
        Vec3::new(0.0, 1.0, 0.5),
    ];
    for _ in 0..300 {
        push(tri, &mut positions);
    }
    // An axis-aligned grid of coplanar triangles sharing edges.
    let base = positions.len() as u32;
    let n = 20;
    for j in 0..=n {
        for i in 0..=n {
            positions.push(Vec3::new(i as f32 * 0.3 - 3.0, j as f32 * 0.3 - 3.0, -1.0));
        }
    }
    for j in 0..n {
        for i in 0..n {
            let v = base + (j * (n + 1) + i) as u32;
            indices.push([v, v + 1, v + n as u32 + 2]);
            indices.push([v, v + n as u32 + 2, v + n as u32 + 1]);
        }
    }
    mesh(positions, indices)
}

fn check(shapes: Vec<Shape>, rng: &mut Rng, rays: usize) -> usize {
    let agg = Aggregate::new(shapes.clone());
    let mut hits = 0;
    for i in 0..rays {
        let o = rng.point(6.0);
        // Half the rays aim at the scene's middle, half go anywhere.
        let d = if i % 2 == 0 {
            (rng.point(2.0) - o).normalize()
        } else {
            rng.direction()
        };
        let mut ray = Ray::new(o, d);
        if i % 5 == 0 {
            ray.t_max = rng.next() * 8.0;
        }
        let expected = brute_force(&shapes, &ray);
        let got = agg.intersect(&ray);
        assert_eq!(got.map(|h| h.t), expected, "ray {i}: {ray:?}");
        if let Some(h) = got {
            hits += 1;
            // The reported primitive is one that is hit at that distance.
            let shear = RayShear::new(&ray);
            let again =
                shapes[h.shape as usize].intersect(h.prim as usize, &ray, &shear, ray.t_max);
            assert_eq!(again.map(|a| a.0), Some(h.t));
        }
        assert_eq!(agg.occluded(&ray), expected.is_some(), "ray {i}");
    }
    hits
}

#[test]
fn random_meshes_match_brute_force() {
    let mut rng = Rng(1);
    let shapes = vec![random_mesh(&mut rng, 2000), random_mesh(&mut rng, 50)];
    let hits = check(shapes, &mut rng, 4000);
    assert!(hits > 1000, "the test rays must hit often: {hits}");
}

#[test]
fn degenerate_meshes_match_brute_force() {
    let mut rng = Rng(2);
    let hits = check(vec![degenerate_mesh(&mut rng)], &mut rng, 4000);
    assert!(hits > 500, "{hits}");
}

#[test]
fn mixed_shapes_match_brute_force() {
    let mut rng = Rng(3);
    let mut shapes = vec![random_mesh(&mut rng, 300)];
    for _ in 0..20 {
        shapes.push(Shape::Sphere(Sphere::new(rng.point(4.0), 0.1 + rng.next())));
        let t = Transform::translate(rng.point(4.0))
            .then_after(&Transform::rotate(rng.direction(), rng.next() * 360.0).unwrap())
            .then_after(
                &Transform::scale(Vec3::new(0.2 + rng.next(), 0.2 + rng.next(), 1.0)).unwrap(),
            );
        let kind = if rng.next() < 0.5 {
            PlanarKind::Disk
        } else {
            PlanarKind::Rectangle
        };
        shapes.push(Shape::Planar(Box::new(Planar::new(kind, t))));
    }
    let hits = check(shapes, &mut rng, 4000);
    assert!(hits > 1000, "{hits}");
}

#[test]
fn empty_scene_hits_nothing() {
    let agg = Aggregate::new(Vec::new());
    let ray = Ray::new(Vec3::ZERO, Vec3::new(0.0, 0.0, 1.0));
    assert!(agg.intersect(&ray).is_none() && !agg.occluded(&ray));
}

#[test]
fn mesh_validation() {
    let p = vec![Vec3::ZERO, Vec3::new(1.0, 0.0, 0.0)];
    let e = TriangleMesh::new(p.clone(), None, None, vec![[0, 1, 2]], &Transform::IDENTITY)
        .unwrap_err();
    assert!(e.to_string().contains("vertex 2"), "{e}");
    let bad = vec![Vec3::new(f32::NAN, 0.0, 0.0)];
    assert!(TriangleMesh::new(bad, None, None, vec![], &Transform::IDENTITY).is_err());
}

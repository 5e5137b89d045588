//! Instancing: ray throughput on a forest of 256 instances of one
//! 8,192-triangle tree (2,097,152 triangles placed), against the same
//! forest with every tree copied into one BVH. The instanced forest holds
//! one tree; the copied one, 256.

use std::hint::black_box;
use std::sync::Arc;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use scotopia_render::accel::{Aggregate, Instance, ShapeGroup};
use scotopia_render::geometry::{Shape, TriangleMesh};
use scotopia_render::math::{Ray, Transform, Vec3};

/// Quads per side of the tree's grid: 64² quads × 2 = 8,192 triangles.
const N: usize = 64;
/// Trees per side of the forest.
const SIDE: usize = 16;

/// A bumpy ball (a displaced latitude–longitude grid), placed by `t`.
fn tree(t: &Transform) -> Shape {
    let mut positions = Vec::new();
    for i in 0..=N {
        for j in 0..=N {
            let theta = std::f32::consts::PI * i as f32 / N as f32;
            let phi = std::f32::consts::TAU * j as f32 / N as f32;
            let r = 1.0 + 0.2 * (5.0 * phi).sin() * (3.0 * theta).sin();
            positions.push(
                Vec3::new(
                    theta.sin() * phi.cos(),
                    theta.sin() * phi.sin(),
                    theta.cos(),
                ) * r,
            );
        }
    }
    let mut indices = Vec::new();
    let w = (N + 1) as u32;
    for i in 0..N as u32 {
        for j in 0..N as u32 {
            let v = i * w + j;
            indices.push([v, v + w, v + w + 1]);
            indices.push([v, v + w + 1, v + 1]);
        }
    }
    Shape::Mesh(TriangleMesh::new(positions, None, None, indices, t).unwrap())
}

/// Each tree's placement: on a grid, turned and stretched a little.
fn placements() -> Vec<Transform> {
    (0..SIDE * SIDE)
        .map(|k| {
            let (x, y) = ((k % SIDE) as f32 * 3.0, (k / SIDE) as f32 * 3.0);
            Transform::translate(Vec3::new(x, y, 0.0))
                .then_after(&Transform::rotate(Vec3::new(0.0, 0.0, 1.0), 17.0 * k as f32).unwrap())
                .then_after(&Transform::scale(Vec3::new(1.0, 1.0, 1.0 + 0.01 * k as f32)).unwrap())
        })
        .collect()
}

/// Rays of a 128×128 pinhole camera looking across the forest.
fn primary_rays() -> Vec<Ray> {
    let o = Vec3::new(-6.0, -6.0, 8.0);
    let forward = (Vec3::new(24.0, 24.0, 0.0) - o).normalize();
    let right = forward.cross(Vec3::new(0.0, 0.0, 1.0)).normalize();
    let up = right.cross(forward);
    let mut rays = Vec::new();
    for j in 0..128 {
        for i in 0..128 {
            let (u, v) = ((i as f32 + 0.5) / 64.0 - 1.0, (j as f32 + 0.5) / 64.0 - 1.0);
            rays.push(Ray::new(
                o,
                (forward + right * (0.6 * u) + up * (0.6 * v)).normalize(),
            ));
        }
    }
    rays
}

fn bench(c: &mut Criterion) {
    let group_of_one = Arc::new(ShapeGroup::new(vec![tree(&Transform::IDENTITY)], 0));
    let instanced = Aggregate::with_instances(
        Vec::new(),
        placements()
            .into_iter()
            .map(|t| Instance::new(group_of_one.clone(), t))
            .collect(),
    );
    let copied = Aggregate::new(placements().iter().map(tree).collect());
    let rays = primary_rays();
    let mut group = c.benchmark_group("forest_256_trees");
    group.sample_size(10);
    group.throughput(Throughput::Elements(rays.len() as u64));
    for (name, world) in [("instanced", &instanced), ("copied", &copied)] {
        group.bench_with_input(BenchmarkId::new("closest_hit", name), &rays, |b, rays| {
            b.iter(|| rays.iter().filter(|r| world.intersect(r).is_some()).count())
        });
        group.bench_with_input(BenchmarkId::new("occluded", name), &rays, |b, rays| {
            b.iter(|| rays.iter().filter(|r| world.occluded(r)).count())
        });
    }
    group.finish();
    black_box((instanced.stored_triangles(), copied.stored_triangles()));
}

criterion_group!(benches, bench);
criterion_main!(benches);

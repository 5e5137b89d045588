//! BVH build time and ray throughput on a procedurally displaced grid of
//! 1,002,528 triangles.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use scotopia_render::accel::Aggregate;
use scotopia_render::geometry::{Shape, TriangleMesh};
use scotopia_render::math::{Ray, Transform, Vec3};

/// Quads per side: 708² quads × 2 = 1,002,528 triangles.
const N: usize = 708;

/// A terrain-like grid over [−1, 1]², displaced by a sum of sines.
fn terrain() -> Shape {
    let mut positions = Vec::with_capacity((N + 1) * (N + 1));
    for j in 0..=N {
        for i in 0..=N {
            let (x, y) = (
                2.0 * i as f32 / N as f32 - 1.0,
                2.0 * j as f32 / N as f32 - 1.0,
            );
            let h = 0.1 * (7.0 * x).sin() * (5.0 * y).cos() + 0.03 * (31.0 * x + 17.0 * y).sin();
            positions.push(Vec3::new(x, y, h));
        }
    }
    let mut indices = Vec::with_capacity(2 * N * N);
    for j in 0..N {
        for i in 0..N {
            let v = (j * (N + 1) + i) as u32;
            let w = (N + 1) as u32;
            indices.push([v, v + 1, v + w + 1]);
            indices.push([v, v + w + 1, v + w]);
        }
    }
    Shape::Mesh(TriangleMesh::new(positions, None, None, indices, &Transform::IDENTITY).unwrap())
}

/// Rays of a 128×128 pinhole camera looking down at the terrain.
fn primary_rays() -> Vec<Ray> {
    let o = Vec3::new(0.0, -2.5, 1.5);
    let forward = (Vec3::ZERO - o).normalize();
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

/// 16384 rays from random points in the scene's box in random directions.
fn incoherent_rays() -> Vec<Ray> {
    let mut state = 7u64;
    let mut next = || {
        state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = state;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32 * 2.0 - 1.0
    };
    (0..16384)
        .map(|_| {
            let o = Vec3::new(next(), next(), 0.3 * next());
            let d = Vec3::new(next(), next(), next()).normalize();
            Ray::new(o, d)
        })
        .collect()
}

fn bench(c: &mut Criterion) {
    let shape = terrain();
    let mut group = c.benchmark_group("bvh_1m_triangles");
    group.sample_size(10);
    group.bench_function("build", |b| {
        b.iter(|| black_box(Aggregate::new(vec![shape.clone()])))
    });
    let agg = Aggregate::new(vec![shape]);
    for (name, rays) in [
        ("primary", primary_rays()),
        ("incoherent", incoherent_rays()),
    ] {
        group.throughput(Throughput::Elements(rays.len() as u64));
        group.bench_with_input(BenchmarkId::new("closest_hit", name), &rays, |b, rays| {
            b.iter(|| rays.iter().filter(|r| agg.intersect(r).is_some()).count())
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

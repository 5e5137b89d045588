//! BVH build time and ray throughput on a procedurally displaced grid of
//! 1,002,528 triangles.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use scotopia_render::accel::{Aggregate, LeafCost, Width};
use scotopia_render::geometry::{Shape, TriangleMesh};
use scotopia_render::math::{Ray, Transform, Vec3};
use scotopia_render::simd::Level;

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

/// With `BVH_COUNT=level,primary` (or `incoherent`; then optionally
/// `,wide` for leaves costed by the level's own steps, and `,4` for
/// 4-wide nodes instead of 8) set, traces that ray set once at that
/// level instead of benchmarking,
/// for instruction counts: `valgrind --tool=callgrind
/// --toggle-collect='*intersect_many*'` counts the tracing alone.
fn count_once(what: &str) {
    let mut parts = what.split(',');
    let level = parts.next().unwrap_or("scalar");
    let set = parts.next().unwrap_or("primary");
    let Ok(level) = Level::parse(level) else {
        eprintln!("BVH_COUNT: no such level {level}");
        return;
    };
    let rest: Vec<&str> = parts.collect();
    let cost = if rest.contains(&"wide") {
        LeafCost::wide(level.lanes())
    } else {
        LeafCost::SCALAR
    };
    let width = if rest.contains(&"4") {
        Width::Four
    } else {
        Width::Eight
    };
    let agg = Aggregate::built_with(&cost, width, vec![terrain()], Vec::new());
    let mesh: usize = agg
        .shapes
        .iter()
        .map(|s| match s {
            Shape::Mesh(m) => {
                std::mem::size_of_val(&m.positions[..]) + std::mem::size_of_val(&m.indices[..])
            }
            _ => 0,
        })
        .sum();
    let n = agg.stored_triangles() as f64;
    eprintln!(
        "{level}: bytes per triangle: acceleration {:.1} ({} nodes), mesh {:.1}",
        agg.acceleration_bytes() as f64 / n,
        agg.bvh().node_count(),
        mesh as f64 / n
    );
    let rays = if set == "incoherent" {
        incoherent_rays()
    } else {
        primary_rays()
    };
    let mut out = vec![None; rays.len()];
    agg.intersect_many(level, &rays, &mut out);
    eprintln!(
        "{level} {set}: {} hits of {} rays",
        out.iter().flatten().count(),
        rays.len()
    );
    // BVH_REPEAT=n: the fastest of n passes, in Mrays/s (robust to a
    // shared machine's noise, which only ever slows a pass).
    let repeat: usize = std::env::var("BVH_REPEAT")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(0);
    if repeat > 0 {
        let best = (0..repeat)
            .map(|_| {
                let t = std::time::Instant::now();
                agg.intersect_many(level, &rays, &mut out);
                t.elapsed().as_secs_f64()
            })
            .fold(f64::INFINITY, f64::min);
        eprintln!(
            "{level} {set}: {:.2} Mrays/s (best of {repeat})",
            rays.len() as f64 / best / 1e6
        );
    }
}

fn bench(c: &mut Criterion) {
    if let Ok(level) = std::env::var("BVH_COUNT") {
        return count_once(&level);
    }
    let shape = terrain();
    let mut group = c.benchmark_group("bvh_1m_triangles");
    group.sample_size(10);
    group.bench_function("build", |b| {
        b.iter(|| black_box(Aggregate::new(vec![shape.clone()])))
    });
    // The default BVH (8-wide nodes, leaves costed by 8-lane steps) at
    // each level; the same leaves under 4-wide nodes; and scalar-costed
    // leaves.
    let built = |cost: &LeafCost, width: Width| {
        Aggregate::built_with(cost, width, vec![shape.clone()], Vec::new())
    };
    let default = Aggregate::new(vec![shape.clone()]);
    let four = built(&LeafCost::wide(8), Width::Four);
    let scalar_leaves = built(&LeafCost::SCALAR, Width::Eight);
    let mut runs: Vec<(String, Level, &Aggregate)> = Level::available()
        .into_iter()
        .map(|l| (l.to_string(), l, &default))
        .collect();
    for l in Level::available() {
        if l >= Level::Avx2 {
            runs.push((format!("{l}_4wide"), l, &four));
            runs.push((format!("{l}_scalar_leaves"), l, &scalar_leaves));
        }
    }
    for (name, rays) in [
        ("primary", primary_rays()),
        ("incoherent", incoherent_rays()),
    ] {
        group.throughput(Throughput::Elements(rays.len() as u64));
        for (label, level, agg) in &runs {
            let level = *level;
            group.bench_with_input(
                BenchmarkId::new(format!("closest_hit/{name}"), label),
                &rays,
                |b, rays| {
                    b.iter(|| {
                        rays.iter()
                            .filter(|r| agg.intersect_at(level, r).is_some())
                            .count()
                    })
                },
            );
        }
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

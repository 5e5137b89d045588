//! The sampler's cost per 4-dimensional point: the scalar `Sampler`, and
//! batches of 1024 lanes (random pixels and sample indices, one set) at
//! each SIMD level this machine has.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use scotopia_render::sampling::sobol::{pixel_key, set_point, Sampler};
use scotopia_render::sampling::sobol_batch::{pixel_keys, sobol_sets};
use scotopia_render::simd::Level;

const LANES: usize = 1024;

fn bench(c: &mut Criterion) {
    let mut state = 1u32;
    let mut next = move || {
        state ^= state << 13;
        state ^= state >> 17;
        state ^= state << 5;
        state
    };
    let xs: Vec<u32> = (0..LANES).map(|_| next() % 1920).collect();
    let ys: Vec<u32> = (0..LANES).map(|_| next() % 1080).collect();
    let indices: Vec<u32> = (0..LANES).map(|_| next() % 4096).collect();
    let keys: Vec<u32> = xs
        .iter()
        .zip(&ys)
        .map(|(&x, &y)| pixel_key(7, [x, y]))
        .collect();

    let mut group = c.benchmark_group("sobol_4d_point");
    group.throughput(Throughput::Elements(LANES as u64));
    // What a path tracer pays today: start a sample, draw sets 0–3.
    group.bench_function("sampler_4_sets", |b| {
        let mut s = Sampler::new(7);
        b.iter(|| {
            let mut acc = 0.0;
            for i in 0..LANES / 4 {
                s.start([xs[i], ys[i]], indices[i]);
                for _ in 0..4 {
                    acc += s.get_4d().iter().sum::<f32>();
                }
            }
            black_box(acc)
        })
    });
    group.bench_function("set_point", |b| {
        b.iter(|| {
            let mut acc = 0.0;
            for i in 0..LANES {
                acc += set_point(keys[i], indices[i].reverse_bits(), black_box(3))
                    .iter()
                    .sum::<f32>();
            }
            black_box(acc)
        })
    });
    let mut out = [
        vec![0f32; LANES],
        vec![0f32; LANES],
        vec![0f32; LANES],
        vec![0f32; LANES],
    ];
    let mut key_out = vec![0u32; LANES];
    for level in Level::available() {
        group.bench_with_input(BenchmarkId::new("batch", level), &level, |b, &level| {
            b.iter(|| {
                let [o0, o1, o2, o3] = &mut out;
                sobol_sets(level, black_box(3), &keys, &indices, [o0, o1, o2, o3]);
                black_box(o3[LANES - 1])
            })
        });
        group.bench_with_input(
            BenchmarkId::new("pixel_keys", level),
            &level,
            |b, &level| {
                b.iter(|| {
                    pixel_keys(level, black_box(7), &xs, &ys, &mut key_out);
                    black_box(key_out[LANES - 1])
                })
            },
        );
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

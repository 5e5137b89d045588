//! The path tracer's cost per camera sample on the bundled Cornell box
//! (issue 4's benchmark scene), on one thread so the figure is CPU time
//! per sample: criterion's median over many passes is steadier on a shared
//! machine than one timed render. Max depth 1 is the fixed cost of a
//! sample (camera ray, wavelength cluster, one intersection, the estimate),
//! 16 the benchmark's whole paths.

use std::path::Path;
use std::sync::atomic::AtomicBool;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use scotopia_render::integrator::{render, RenderOptions};
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

const RES: u32 = 64;
/// Samples per pixel per iteration: enough that setting up the render
/// (wavelength densities, film) is a small part of it.
const SPP: u32 = 4;

fn bench(c: &mut Criterion) {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.xml");
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool");
    let mut group = c.benchmark_group("cornell_box_64x64_1_thread");
    group.sample_size(20);
    group.throughput(Throughput::Elements((RES * RES * SPP) as u64));
    for depth in [1, 16] {
        let params = Parameters::from([
            ("res".to_string(), RES.to_string()),
            ("max_depth".to_string(), depth.to_string()),
        ]);
        let scene = load_scene(&file, &params).expect("the bundled Cornell box loads");
        let options = RenderOptions {
            spp: Some(SPP),
            ..RenderOptions::default()
        };
        let cancel = AtomicBool::new(false);
        group.bench_function(BenchmarkId::new("camera_samples_max_depth", depth), |b| {
            b.iter(|| {
                pool.install(|| render(&scene, &options, &cancel, &|_, _| {}))
                    .expect("renders")
                    .rays
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

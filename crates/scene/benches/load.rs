//! Scene loading time against the number of elements: 5 000, 20 000 and
//! 100 000 spheres sharing one BSDF, each with a property scotopia does not
//! use (one warning per sphere), so the parse, the builders and the
//! warnings all scale. Throughput is in shapes: a flat figure across sizes
//! is a linear loader. Issue 22: locating elements with roxmltree's
//! `text_pos_at` (a rescan from the file's start per element) made this
//! quadratic (20 000 spheres: 11.8 s), as did a linear search per warning.

use std::path::PathBuf;

use criterion::{criterion_group, criterion_main, BenchmarkId, Criterion, Throughput};
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

/// A scene of `n` spheres, written to the temporary folder.
fn spheres(n: usize) -> PathBuf {
    let mut s = String::from(
        "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"/>\n\
         <bsdf type=\"diffuse\" id=\"m\"/>\n",
    );
    for i in 0..n {
        s.push_str(&format!(
            "<shape type=\"sphere\"><point name=\"center\" x=\"{i}\" y=\"0\" z=\"0\"/>\
             <float name=\"radius\" value=\"0.5\"/><float name=\"unused\" value=\"1\"/>\
             <ref id=\"m\"/></shape>\n"
        ));
    }
    s.push_str("</scene>\n");
    let path = std::env::temp_dir().join(format!("scotopia-bench-load-{n}.xml"));
    std::fs::write(&path, s).expect("writes the scene");
    path
}

fn bench(c: &mut Criterion) {
    let mut group = c.benchmark_group("load_spheres");
    group.sample_size(10);
    for n in [5_000, 20_000, 100_000] {
        let path = spheres(n);
        group.throughput(Throughput::Elements(n as u64));
        group.bench_function(BenchmarkId::from_parameter(n), |b| {
            b.iter(|| {
                load_scene(&path, &Parameters::new())
                    .expect("loads")
                    .warnings
                    .len()
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);

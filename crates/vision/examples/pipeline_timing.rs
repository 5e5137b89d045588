//! Times the pipeline on a raw little-endian f32 X, Y, Z, V′ file:
//! `cargo run --release -p scotopia-vision --example pipeline_timing -- FILE W H FOV [RUNS]`
//! (for profiling; `make bench` uses bench/vision.py).

use scotopia_vision::pipeline::{display, DisplayParams};

fn main() {
    let a: Vec<String> = std::env::args().collect();
    if a.len() < 5 {
        eprintln!("usage: pipeline_timing FILE WIDTH HEIGHT FOV_DEGREES [RUNS]");
        std::process::exit(2);
    }
    let bytes = std::fs::read(&a[1]).expect("readable file");
    let (w, h): (usize, usize) = (a[2].parse().expect("width"), a[3].parse().expect("height"));
    let fov: f64 = a[4].parse().expect("fov");
    let runs: usize = a.get(5).map_or(5, |r| r.parse().expect("runs"));
    let px: Vec<[f32; 4]> = bytes
        .chunks_exact(16)
        .map(|c| {
            std::array::from_fn(|k| f32::from_le_bytes(c[4 * k..4 * k + 4].try_into().unwrap()))
        })
        .collect();
    assert_eq!(
        px.len(),
        w * h,
        "file size must be WIDTH × HEIGHT × 16 bytes"
    );
    let p = DisplayParams {
        degrees_per_pixel: fov / w as f64,
        ..Default::default()
    };
    for _ in 0..runs {
        let t = std::time::Instant::now();
        let out = display(&px, w, h, &p);
        let total = t.elapsed().as_secs_f64();
        let stages: Vec<String> = out
            .report
            .timings
            .iter()
            .map(|(n, s)| format!("{n} {:.0}", s * 1e3))
            .collect();
        println!("{:.0} ms: {}", total * 1e3, stages.join(", "));
    }
}

//! Times the pipeline on a raw little-endian f32 X, Y, Z, V′ file:
//! `cargo run --release -p scotopia-vision --example pipeline_timing -- FILE W H FOV [RUNS]`
//! (for profiling; `make bench` uses bench/vision.py).

use scotopia_vision::pipeline::{display, DisplayParams};

fn main() {
    if let Err(e) = run() {
        eprintln!("pipeline_timing: {e}");
        eprintln!("usage: pipeline_timing FILE WIDTH HEIGHT FOV_DEGREES [RUNS]");
        std::process::exit(2);
    }
}

fn run() -> Result<(), String> {
    let a: Vec<String> = std::env::args().collect();
    if a.len() < 5 {
        return Err("missing arguments".into());
    }
    let number = |i: usize, what: &str| -> Result<f64, String> {
        a[i].parse()
            .map_err(|_| format!("{what} '{}' is not a number", a[i]))
    };
    let bytes = std::fs::read(&a[1]).map_err(|e| format!("{}: {e}", a[1]))?;
    let (w, h) = (number(2, "width")? as usize, number(3, "height")? as usize);
    let fov = number(4, "field of view")?;
    let runs = if a.len() > 5 {
        number(5, "runs")? as usize
    } else {
        5
    };
    if bytes.len() != w * h * 16 || w == 0 {
        return Err(format!(
            "{}: {} bytes, not {w} × {h} pixels of four f32",
            a[1],
            bytes.len()
        ));
    }
    let px: Vec<[f32; 4]> = bytes
        .chunks_exact(16)
        .map(|c| {
            std::array::from_fn(|k| {
                f32::from_le_bytes([c[4 * k], c[4 * k + 1], c[4 * k + 2], c[4 * k + 3]])
            })
        })
        .collect();
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
    Ok(())
}

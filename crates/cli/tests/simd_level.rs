//! `SCOTOPIA_SIMD` forces a SIMD level: a bad value is a clear error
//! before anything renders, and the scalar level (the reference) gives the
//! same image as the best level the machine has, bit for bit, while every
//! kernel is exact.

use std::process::Command;

mod common;

use common::{out_dir, scenes};

fn render(simd: &str, out: &std::path::Path) -> std::process::Output {
    let scene = scenes().join("prism.xml");
    Command::new(env!("CARGO_BIN_EXE_scotopia"))
        .args([
            "render",
            scene.to_str().unwrap(),
            "--res",
            "24",
            "--spp",
            "2",
        ])
        // The prism's own integrator is bdpt, which the wavefront tracer
        // does not run (it once handed over to the scalar one quietly).
        .args(["--integrator", "path", "--tracer", "wavefront"])
        .args(["-o", out.to_str().unwrap()])
        .env("SCOTOPIA_SIMD", simd)
        .output()
        .unwrap()
}

#[test]
fn a_bad_level_is_an_error_naming_the_variable_and_the_levels() {
    let dir = out_dir("simd", "bad");
    let out = render("avx9000", &dir.join("x.exr"));
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(
        err.contains("SCOTOPIA_SIMD") && err.contains("scalar") && !err.contains("panicked"),
        "{err}"
    );
}

#[test]
fn the_scalar_level_renders_the_same_bits_as_the_best() {
    let dir = out_dir("simd", "same");
    let (a, b) = (dir.join("scalar.exr"), dir.join("best.exr"));
    for (level, path) in [("scalar", &a), ("", &b)] {
        let out = render(level, path);
        assert!(
            out.status.success(),
            "{}",
            String::from_utf8_lossy(&out.stderr)
        );
    }
    // The pixels (the header holds the render time).
    let pixels = |p: &std::path::Path| scotopia_image::read_exr(p).unwrap().channels;
    assert!(pixels(&a) == pixels(&b), "the images differ");
}

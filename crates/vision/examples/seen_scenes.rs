//! Writes the seen-image suite's synthetic scenes as X, Y, Z, V′ EXRs, for
//! looking at them through `scotopia display` (docs/vision.md's before and
//! after pictures): a lamp in a dark field, a step edge, a uniform field
//! and a saturated colour edge, each at night, dusk and day levels.
//!
//! cargo run --release -p scotopia-vision --example seen_scenes -- OUT_DIR

use std::path::Path;

use scotopia_image::exr_out::{write_exr, Meta};

/// D65 white at luminance y: X, Y, Z and V′ (V′/Y of D65 is 2.46).
fn white(y: f32) -> [f32; 4] {
    [0.9505 * y, y, 1.089 * y, 2.46 * y]
}

fn write(dir: &Path, name: &str, w: usize, h: usize, fov: f32, px: &[[f32; 4]]) {
    let channels = ["X", "Y", "Z", "V"]
        .iter()
        .enumerate()
        .map(|(c, n)| (n.to_string(), px.iter().map(|p| p[c]).collect()))
        .collect();
    let path = dir.join(format!("{name}.exr"));
    write_exr(
        &path,
        w,
        h,
        channels,
        &[("fovHorizontalDegrees", Meta::F32(fov))],
    )
    .expect("the EXR is written");
    println!("{}", path.display());
}

fn main() {
    let dir = std::env::args().nth(1).unwrap_or_else(|| "out/seen".into());
    let dir = Path::new(&dir);
    std::fs::create_dir_all(dir).expect("the folder is made");
    // The street lamp: a 500 cd/m² square 16 px wide in a uniform
    // 0.005 cd/m² field, 512 × 256 at 60°.
    let (w, h) = (512, 256);
    let mut lamp = vec![white(0.005); w * h];
    for y in h / 2 - 8..h / 2 + 8 {
        for x in w / 2 - 8..w / 2 + 8 {
            lamp[y * w + x] = white(500.0);
        }
    }
    write(dir, "lamp", w, h, 60.0, &lamp);
    for (name, dark, bright) in [
        ("step-night", 0.005, 50.0),
        ("step-dusk", 0.5, 50.0),
        ("step-day", 50.0, 5000.0),
    ] {
        let px: Vec<[f32; 4]> = (0..w * h)
            .map(|i| white(if i % w < w / 2 { dark } else { bright }))
            .collect();
        write(dir, name, w, h, 60.0, &px);
    }
    // A saturated red square on grey, at dusk.
    let mut red = vec![white(1.0); w * h];
    for y in h / 2 - 32..h / 2 + 32 {
        for x in w / 2 - 32..w / 2 + 32 {
            red[y * w + x] = [2.0, 1.0, 0.05, 0.3];
        }
    }
    write(dir, "red-square", w, h, 60.0, &red);
}

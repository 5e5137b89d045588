//! The same scene at any scale renders the same image: a diffuse wall (the
//! face of a flat cube: triangles) lit by a rectangular lamp facing it, seen by a camera behind the lamp
//! (which hides part of the wall with its black back), with every length
//! — shapes, camera, clip planes — multiplied by 10⁻⁶, 1, 10⁶ or 10¹⁴.
//! The lamp's radiance does not depend on scale, nor does the wall's.

use std::sync::atomic::AtomicBool;

use scotopia_render::integrator::{render, RenderOptions};
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

fn scene(s: f64) -> String {
    format!(
        r#"<scene version="3.0.0">
<integrator type="path"><integer name="max_depth" value="2"/></integrator>
<sensor type="perspective"><float name="fov" value="40"/>
  <float name="near_clip" value="{near:e}"/><float name="far_clip" value="{far:e}"/>
  <transform name="to_world"><lookat origin="{x:e}, {y:e}, {z:e}" target="0, 0, 0" up="0, 1, 0"/></transform>
  <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/><rfilter type="box"/></film>
</sensor>
<shape type="cube"><transform name="to_world"><scale x="2" y="2" z="0.1"/><translate z="-0.1"/><scale value="{s:e}"/></transform>
  <bsdf type="diffuse"><float name="reflectance" value="0.5"/></bsdf></shape>
<shape type="rectangle">
  <transform name="to_world"><scale value="0.4"/><rotate x="1" angle="180"/><translate z="1"/><scale value="{s:e}"/></transform>
  <bsdf type="diffuse"><float name="reflectance" value="0"/></bsdf>
  <emitter type="area"><spectrum name="radiance" value="1"/></emitter>
</shape>
</scene>"#,
        near = 0.01 * s,
        x = 0.1 * s,
        y = 0.2 * s,
        z = 3.0 * s,
        far = 100.0 * s,
    )
}

/// The image's luminance, pixel by pixel.
fn luminance(s: f64) -> Vec<f64> {
    let dir = std::env::temp_dir().join(format!("scotopia-scale-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join(format!("scale-{s:e}.xml"));
    std::fs::write(&f, scene(s)).unwrap();
    let scene = load_scene(&f, &Parameters::new()).unwrap_or_else(|e| panic!("scale {s:e}: {e}"));
    let options = RenderOptions {
        spp: Some(16),
        seed: 3,
        ..RenderOptions::default()
    };
    let r = render(&scene, &options, &AtomicBool::new(false), &|_, _| {}).unwrap();
    let px: Vec<f64> = r.film.xyzv().iter().map(|p| p[1] as f64).collect();
    assert!(px.iter().all(|v| v.is_finite()), "scale {s:e}: {px:?}");
    px
}

#[test]
fn a_scene_renders_the_same_at_any_scale() {
    // Paired by pixel (same seed, so the same random numbers): the mean
    // difference from scale 1 must lie within 4 standard errors of the
    // differences, plus 10⁻⁴ of the mean for rounding (powers of ten are
    // not exact in binary, so paths differ in their last bits); and the
    // image must not be black. Measured: |difference| ≤ 10⁻⁶ of the mean
    // from 10⁻¹⁴ to 10¹⁶; before, 10⁻⁶ was 0.8 % dark (ray offsets of a
    // unit-size scene) and 10¹² and above failed to load or were black.
    let reference = luminance(1.0);
    let n = reference.len() as f64;
    let mean_ref = reference.iter().sum::<f64>() / n;
    assert!(mean_ref > 0.0);
    for s in [1e-12, 1e-6, 1e6, 1e14, 1e16] {
        let d: Vec<f64> = luminance(s)
            .iter()
            .zip(&reference)
            .map(|(a, b)| a - b)
            .collect();
        let mean = d.iter().sum::<f64>() / n;
        let se = (d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
        assert!(
            mean.abs() <= 4.0 * se + 1e-4 * mean_ref,
            "scale {s:e}: mean difference {mean} (SE {se}) from scale 1's mean {mean_ref}"
        );
    }
}

#[test]
fn a_scene_too_large_for_single_precision_is_an_error_naming_the_range() {
    // At 10¹⁸ the lamp's power (radiance × π × area) exceeds f32.
    let dir = std::env::temp_dir().join(format!("scotopia-scale-big-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("big.xml");
    std::fs::write(&f, scene(1e18)).unwrap();
    let e = load_scene(&f, &Parameters::new()).unwrap_err().to_string();
    assert!(
        e.contains("big.xml:13:") && e.contains("single precision"),
        "{e}"
    );
}

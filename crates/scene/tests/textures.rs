//! Textures in scenes: bitmap (PNG, EXR) and checkerboard, nested or by
//! reference, on BSDF parameters; and their errors.

use std::path::PathBuf;

use scotopia_color::{rgb_to_spectrum, RgbSpace, SampledWavelengths, SpectrumKind, UpsampleMethod};
use scotopia_render::bsdf::Bsdf;
use scotopia_render::texture::Texture;
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("scotopia-tex-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes `body` into a scene `name`.xml (one name per test: they run in parallel).
fn write_scene(name: &str, body: &str) -> PathBuf {
    let f = dir().join(format!("{name}.xml"));
    std::fs::write(
        &f,
        format!("<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/></sensor>\n{body}\n</scene>"),
    )
    .unwrap();
    f
}

fn wl() -> SampledWavelengths<4> {
    SampledWavelengths::new([450.0, 520.0, 600.0, 680.0], [1.0; 4])
}

fn reflectance(linear_rgb: [f32; 3]) -> [f32; 4] {
    rgb_to_spectrum(
        linear_rgb,
        RgbSpace::Srgb,
        UpsampleMethod::Jakob2019,
        SpectrumKind::Reflectance,
    )
    .unwrap()
    .sample(&wl())
    .0
}

fn close(a: [f32; 4], b: [f32; 4], tol: f32) {
    for i in 0..4 {
        assert!((a[i] - b[i]).abs() < tol, "{a:?} vs {b:?}");
    }
}

#[test]
fn png_and_exr_bitmaps_by_reference_and_nested() {
    // 2×1 PNG: sRGB red | white; the same as a linear EXR.
    scotopia_image::write_png_rgb8(&dir().join("t.png"), 2, 1, &[255, 0, 0, 255, 255, 255])
        .unwrap();
    let exr = image::Rgb32FImage::from_raw(2, 1, vec![0.2, 0.4, 0.6, 1.0, 1.0, 1.0]).unwrap();
    exr.save(dir().join("t.exr")).unwrap();
    let f = write_scene(
        "bitmaps",
        r#"<texture type="bitmap" id="tex"><string name="filename" value="t.png"/><string name="filter_type" value="nearest"/></texture>
<shape type="sphere"><bsdf type="diffuse"><ref name="reflectance" id="tex"/></bsdf></shape>
<shape type="sphere"><bsdf type="roughplastic"><string name="distribution" value="ggx"/>
  <texture type="bitmap" name="diffuse_reflectance"><string name="filename" value="t.exr"/>
    <string name="filter_type" value="nearest"/><boolean name="accel" value="false"/></texture>
</bsdf></shape>"#,
    );
    let s = load_scene(&f, &Parameters::new()).unwrap();
    let Bsdf::Diffuse(d) = &s.materials[0] else {
        panic!("diffuse")
    };
    assert!(d.reflectance.is_varying());
    close(
        d.reflectance.eval(&wl(), [0.25, 0.5]).0,
        reflectance([1.0, 0.0, 0.0]),
        1e-5,
    );
    close(
        d.reflectance.eval(&wl(), [0.75, 0.5]).0,
        reflectance([1.0; 3]),
        1e-5,
    );
    let Bsdf::RoughPlastic(p) = &s.materials[1] else {
        panic!("roughplastic")
    };
    // EXR values are linear: no sRGB decoding.
    close(
        p.diffuse_reflectance.eval(&wl(), [0.25, 0.5]).0,
        reflectance([0.2, 0.4, 0.6]),
        1e-5,
    );
    // Mitsuba's GPU-only option is reported, once.
    assert!(
        s.warnings.iter().any(|w| w.contains("'accel'")),
        "{:?}",
        s.warnings
    );
}

#[test]
fn checkerboard_with_nested_colours_and_to_uv() {
    let f = write_scene(
        "checker",
        r#"<shape type="sphere"><bsdf type="diffuse">
  <texture type="checkerboard" name="reflectance">
    <rgb name="color0" value="0.8, 0.1, 0.1"/>
    <float name="color1" value="0.05"/>
    <transform name="to_uv"><scale x="4" y="4"/></transform>
  </texture>
</bsdf></shape>"#,
    );
    let s = load_scene(&f, &Parameters::new()).unwrap();
    let Bsdf::Diffuse(d) = &s.materials[0] else {
        panic!("diffuse")
    };
    let Texture::Checkerboard(_) = &d.reflectance else {
        panic!("checkerboard")
    };
    close(
        d.reflectance.eval(&wl(), [0.1, 0.1]).0,
        reflectance([0.8, 0.1, 0.1]),
        1e-6,
    );
    close(d.reflectance.eval(&wl(), [0.2, 0.1]).0, [0.05; 4], 1e-6);
}

#[test]
fn texture_errors_name_the_place() {
    std::fs::write(dir().join("junk.png"), b"not an image").unwrap();
    let cases = [
        (
            r#"<shape type="sphere"><bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="nope.png"/></texture></bsdf></shape>"#,
            "nope.png",
        ),
        (
            r#"<shape type="sphere"><bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="junk.png"/></texture></bsdf></shape>"#,
            "cannot read the image",
        ),
        (
            r#"<shape type="sphere"><bsdf type="diffuse"><texture type="checkerboard" name="reflectance"><string name="wrap_mode" value="x"/></texture></bsdf></shape>"#,
            "'wrap_mode' is not used",
        ),
        (
            r#"<shape type="sphere"><bsdf type="diffuse"><ref name="reflectance" id="missing"/></bsdf></shape>"#,
            "no <texture id=\"missing\">",
        ),
        (
            r#"<texture type="checkerboard" id="loop"><ref name="color0" id="loop"/></texture><shape type="sphere"><bsdf type="diffuse"><ref name="reflectance" id="loop"/></bsdf></shape>"#,
            "'loop' refers to itself",
        ),
        (
            r#"<shape type="sphere"><bsdf type="diffuse"><texture type="noise" name="reflectance"/></bsdf></shape>"#,
            "texture type 'noise' is not supported",
        ),
        (
            r#"<shape type="sphere"><bsdf type="conductor"><texture type="checkerboard" name="eta"/><float name="k" value="1"/></bsdf></shape>"#,
            "cannot be a texture here",
        ),
    ];
    for (body, needle) in cases {
        let f = write_scene("s", body);
        match load_scene(&f, &Parameters::new()) {
            Err(e) => {
                let e = e.to_string();
                assert!(
                    e.contains(needle) && e.contains("s.xml:3:"),
                    "{body}\n→ {e}"
                );
            }
            // An unknown property on a texture is a warning, not an error.
            Ok(s) => assert!(
                s.warnings.iter().any(|w| w.contains(needle)),
                "{body}\n→ {:?}",
                s.warnings
            ),
        }
    }
}

#[test]
fn envmap_from_exr_with_scale_and_rotation() {
    // 4×2 EXR: a bright upper half (sky), a dark lower half.
    let mut px = vec![];
    for y in 0..2 {
        for _ in 0..4 {
            px.extend_from_slice(if y == 0 {
                &[1.0, 1.0, 1.0]
            } else {
                &[0.1, 0.1, 0.1]
            });
        }
    }
    image::Rgb32FImage::from_raw(4, 2, px)
        .unwrap()
        .save(dir().join("sky.exr"))
        .unwrap();
    let f = write_scene(
        "envmap",
        r#"<emitter type="envmap"><string name="filename" value="sky.exr"/><float name="scale" value="3"/>
  <transform name="to_world"><rotate x="1" angle="90"/></transform></emitter>"#,
    );
    let s = load_scene(&f, &Parameters::new()).unwrap();
    let scotopia_render::light::Light::EnvMap(env) = &s.lights[0] else {
        panic!("an envmap")
    };
    assert_eq!(env.scale, 3.0);
    // Rotated 90° about x, the map's +y (its top row, the sky) is +z.
    let w = wl();
    let up = env.radiance(&w, scotopia_render::math::Vec3::new(0.0, 0.0, 1.0));
    let down = env.radiance(&w, scotopia_render::math::Vec3::new(0.0, 0.0, -1.0));
    assert!((up[1] / down[1] - 10.0).abs() < 1e-3, "{up:?} {down:?}");
    let f = write_scene(
        "envmap-missing",
        r#"<emitter type="envmap"><string name="filename" value="nope.exr"/></emitter>"#,
    );
    let e = load_scene(&f, &Parameters::new()).unwrap_err().to_string();
    assert!(
        e.contains("nope.exr") && e.contains("envmap-missing.xml:3:"),
        "{e}"
    );
}

//! Mesh attributes in scenes: PLY properties and serialized vertex colours
//! become named attributes, `mesh_attribute` textures read them (bound to
//! each shape), the tracers look them up at the hit's triangle and
//! barycentrics; textured roughness and `rawconstant` textures.

mod common;

use std::path::PathBuf;
use std::sync::atomic::AtomicBool;

use scotopia_color::{
    rgb_to_spectrum, RgbSpace, SampledSpectrum, SampledWavelengths, SpectrumKind, UpsampleMethod,
};
use scotopia_render::bsdf::{Bsdf, Roughness};
use scotopia_render::integrator::{render, RenderOptions};
use scotopia_render::scene::{IntegratorKind, Scene};
use scotopia_render::texture::{FloatTexture, TexPoint, Texture};
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("scotopia-attr-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes `body` into a scene `name`.xml beside the test's files.
fn load(name: &str, body: &str) -> Result<Scene, String> {
    let f = dir().join(format!("{name}.xml"));
    std::fs::write(
        &f,
        format!(
            "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><float name=\"fov\" value=\"20\"/>\
             <transform name=\"to_world\"><lookat origin=\"0,0,4\" target=\"0,0,0\" up=\"0,1,0\"/></transform>\
             <film type=\"hdrfilm\"><integer name=\"width\" value=\"16\"/><integer name=\"height\" value=\"16\"/>\
             <rfilter type=\"box\"/></film></sensor>\n{body}\n</scene>"
        ),
    )
    .unwrap();
    load_scene(&f, &Parameters::new()).map_err(|e| e.to_string())
}

/// The square [−1, 1]² at z = 0 facing +z, as one quad face fanned into
/// the triangles (0, 1, 2) below the diagonal and (0, 2, 3) above it, with
/// float vertex colours (`color_0..2`), a vertex weight (x + 1)/2 and a
/// face weight 1 (as `uchar`-free floats), written as ASCII PLY.
fn square_ply() -> &'static str {
    "ply\nformat ascii 1.0\nelement vertex 4\nproperty float x\nproperty float y\nproperty float z\n\
     property float color_0\nproperty float color_1\nproperty float color_2\nproperty float w_0\n\
     element face 1\nproperty list uchar int vertex_indices\nproperty float weight_0\nend_header\n\
     -1 -1 0 0.8 0.1 0.1 0\n1 -1 0 0.1 0.8 0.1 1\n1 1 0 0.1 0.1 0.8 1\n-1 1 0 0.5 0.5 0.5 0\n\
     4 0 1 2 3 0.75\n"
}

fn wl() -> SampledWavelengths<4> {
    SampledWavelengths::new([450.0, 520.0, 600.0, 680.0], [1.0; 4])
}

fn upsampled(rgb: [f32; 3]) -> SampledSpectrum<4> {
    rgb_to_spectrum(
        rgb,
        RgbSpace::Srgb,
        UpsampleMethod::Jakob2019,
        SpectrumKind::Reflectance,
    )
    .unwrap()
    .sample(&wl())
}

fn at(prim: u32, bary: [f32; 2]) -> TexPoint {
    TexPoint {
        uv: [0.0; 2],
        prim,
        bary,
    }
}

fn reflectance(b: &Bsdf) -> &Texture {
    match b {
        Bsdf::Diffuse(d) => &d.reflectance,
        other => panic!("not diffuse: {other:?}"),
    }
}

#[test]
fn ply_attributes_are_read_per_vertex_and_per_face() {
    std::fs::write(dir().join("square.ply"), square_ply()).unwrap();
    let s = load(
        "ply",
        r#"<bsdf type="diffuse" id="colour"><texture type="mesh_attribute" name="reflectance">
  <string name="name" value="vertex_color"/></texture></bsdf>
<bsdf type="blendbsdf" id="blend"><texture type="mesh_attribute" name="weight">
  <string name="name" value="face_weight"/><float name="scale" value="0.5"/></texture>
  <bsdf type="diffuse"/><bsdf type="diffuse"/></bsdf>
<shape type="ply"><string name="filename" value="square.ply"/><ref id="colour"/></shape>
<shape type="ply"><string name="filename" value="square.ply"/><ref id="colour"/></shape>
<shape type="ply"><string name="filename" value="square.ply"/><ref id="blend"/></shape>"#,
    )
    .unwrap();
    // Each shape has its own material: the texture is bound to its mesh.
    assert_eq!(s.shape_material, vec![0, 1, 2]);
    let t = reflectance(&s.materials[0]);
    let close = |a: SampledSpectrum<4>, b: SampledSpectrum<4>| {
        for k in 0..4 {
            assert!((a.0[k] - b.0[k]).abs() < 1e-4, "{a:?} vs {b:?}");
        }
    };
    // Triangle 1 is (0, 2, 3): its second vertex is vertex 2.
    close(t.eval(&wl(), at(1, [1.0, 0.0])), upsampled([0.1, 0.1, 0.8]));
    close(
        t.eval(&wl(), at(0, [0.25, 0.25])),
        upsampled([0.8, 0.1, 0.1]) * 0.5
            + upsampled([0.1, 0.8, 0.1]) * 0.25
            + upsampled([0.1, 0.1, 0.8]) * 0.25,
    );
    // The quad's face weight reaches both triangles of its fan, scaled.
    let Bsdf::Blend(b) = &s.materials[2] else {
        panic!("not a blend")
    };
    let FloatTexture::MeshAttribute(w) = &b.weight else {
        panic!("not an attribute")
    };
    for prim in [0, 1] {
        assert!((w.eval_1(at(prim, [0.3, 0.3])) - 0.375).abs() < 1e-6);
    }
}

#[test]
fn an_attribute_the_mesh_lacks_is_an_error_naming_the_mesh() {
    std::fs::write(dir().join("plain.ply"), square_ply()).unwrap();
    let cases = [
        (
            r#"<shape type="ply"><string name="filename" value="plain.ply"/><bsdf type="diffuse">
  <texture type="mesh_attribute" name="reflectance"><string name="name" value="vertex_uv"/></texture></bsdf></shape>"#,
            "no attribute 'vertex_uv' (it has vertex_color, vertex_w, face_weight)",
        ),
        (
            r#"<shape type="sphere"><bsdf type="diffuse">
  <texture type="mesh_attribute" name="reflectance"><string name="name" value="vertex_color"/></texture></bsdf></shape>"#,
            "the sphere shape at",
        ),
        (
            r#"<shape type="ply"><string name="filename" value="plain.ply"/><bsdf type="blendbsdf">
  <texture type="mesh_attribute" name="weight"><string name="name" value="vertex_color"/></texture>
  <bsdf type="diffuse"/><bsdf type="diffuse"/></bsdf></shape>"#,
            "'vertex_color' has 3 numbers per record",
        ),
    ];
    for (i, (body, needle)) in cases.into_iter().enumerate() {
        let e = load(&format!("bad{i}"), body).unwrap_err();
        assert!(e.contains(needle), "{e}");
        assert!(e.contains(&format!("bad{i}.xml:3:")), "{e}");
    }
    let e = load(
        "bad_name",
        r#"<shape type="ply"><string name="filename" value="plain.ply"/><bsdf type="diffuse">
  <texture type="mesh_attribute" name="reflectance"><string name="name" value="vertex_uv"/></texture></bsdf></shape>"#,
    )
    .unwrap_err();
    assert!(e.contains("the mesh 'plain.ply' (the shape at"), "{e}");
}

#[test]
fn serialized_vertex_colours_are_an_attribute() {
    let bytes = common::write(&[common::quad("q", 0.0)], 4, false);
    std::fs::write(dir().join("q.serialized"), bytes).unwrap();
    let s = load(
        "serialized",
        r#"<shape type="serialized"><string name="filename" value="q.serialized"/><bsdf type="diffuse">
  <texture type="mesh_attribute" name="reflectance"><string name="name" value="vertex_color"/></texture></bsdf></shape>"#,
    )
    .unwrap();
    let t = reflectance(&s.materials[0]);
    let v = t.eval(&wl(), at(1, [0.2, 0.5]));
    let want = upsampled([0.25, 0.5, 0.75]);
    for k in 0..4 {
        assert!((v.0[k] - want.0[k]).abs() < 1e-4, "{v:?} vs {want:?}");
    }
}

#[test]
fn roughness_textures_and_rawconstant() {
    let s = load(
        "rough",
        r#"<shape type="sphere"><bsdf type="roughconductor"><float name="alpha" value="0.3"/></bsdf></shape>
<shape type="sphere"><bsdf type="roughconductor"><texture type="rawconstant" name="alpha">
  <float name="value" value="0.3"/></texture></bsdf></shape>
<shape type="sphere"><bsdf type="roughdielectric"><texture type="checkerboard" name="alpha">
  <float name="color0" value="0.05"/><float name="color1" value="0.4"/></texture></bsdf></shape>
<shape type="sphere"><bsdf type="normalmap"><texture name="normalmap" type="rawconstant">
  <vector name="value" value="0.5, 0.5, 1.0"/></texture><bsdf type="diffuse"/></bsdf></shape>"#,
    )
    .unwrap();
    // A constant texture is the constant property: the same BSDF.
    assert_eq!(s.materials[0], s.materials[1]);
    let Bsdf::RoughDielectric(d) = &s.materials[2] else {
        panic!("not rough glass")
    };
    let Roughness::Textured(t) = &d.distribution else {
        panic!("not textured")
    };
    assert!(matches!(t.alpha_u, FloatTexture::Checkerboard(_)) && t.alpha_u == t.alpha_v);
    let Bsdf::NormalMap(n) = &s.materials[3] else {
        panic!("not a normal map")
    };
    assert_eq!(n.normals.eval([0.3, 0.9]), [0.5, 0.5, 1.0]);
    let e = load(
        "raw3",
        r#"<shape type="sphere"><bsdf type="diffuse"><texture type="rawconstant" name="reflectance">
  <vector name="value" value="0.5, 0.5, 1.0"/></texture></bsdf></shape>"#,
    )
    .unwrap_err();
    assert!(
        e.contains("raw3.xml:3:") && e.contains("not a spectrum"),
        "{e}"
    );
}

/// Per channel Y, the mean of `image − want` over the pixels (16 × 16,
/// row-major) of `rows` × `cols`, and its standard error from their spread.
fn residual(
    image: &[[f32; 4]],
    rows: std::ops::Range<usize>,
    cols: std::ops::Range<usize>,
    want: impl Fn(usize, usize) -> f64,
) -> (f64, f64) {
    let d: Vec<f64> = rows
        .flat_map(|r| cols.clone().map(move |c| (r, c)))
        .map(|(r, c)| image[r * 16 + c][1] as f64 - want(r, c))
        .collect();
    let n = d.len() as f64;
    let mean = d.iter().sum::<f64>() / n;
    let var = d.iter().map(|y| (y - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

#[test]
fn the_tracers_read_attributes_at_the_hit() {
    // Under a uniform sky of unit radiance, a diffuse plane of reflectance
    // w reflects w (Y = 683 · ∫ȳ · w). The camera sees x, y ∈ [−a, a],
    // a = 4 tan 10°, inside the square. The vertex weight (x + 1)/2 is
    // linear, so a pixel's expected value is its centre's; each face of
    // `split.ply` has its own weight: 1 below the diagonal, 0 above.
    let split = square_ply()
        .replace("element face 1", "element face 2")
        .replace("4 0 1 2 3 0.75\n", "3 0 1 2 1\n3 0 2 3 0\n");
    std::fs::write(dir().join("ramp.ply"), square_ply()).unwrap();
    std::fs::write(dir().join("split.ply"), split).unwrap();
    let body = |file: &str, name: &str| {
        format!(
            r#"<emitter type="constant"><spectrum name="radiance" value="1"/></emitter>
<shape type="ply"><string name="filename" value="{file}"/><bsdf type="diffuse">
  <texture type="mesh_attribute" name="reflectance"><string name="name" value="{name}"/></texture></bsdf></shape>"#
        )
    };
    let white = 683.0 * 106.857;
    let a = 4.0 * 10f64.to_radians().tan();
    let x = |c: usize| -a + 2.0 * a * (c as f64 + 0.5) / 16.0;
    let ramp = load("ramp", &body("ramp.ply", "vertex_w")).unwrap();
    let split = load("split", &body("split.ply", "face_weight")).unwrap();
    for kind in [IntegratorKind::Path, IntegratorKind::Bdpt] {
        let options = RenderOptions {
            spp: Some(16),
            integrator: Some(kind),
            ..RenderOptions::default()
        };
        let cancel = AtomicBool::new(false);
        let img = render(&ramp, &options, &cancel, &|_, _| {})
            .unwrap()
            .film
            .xyzv();
        for cols in [0..8, 8..16] {
            let (mean, se) = residual(&img, 0..16, cols, |_, c| white * (x(c) + 1.0) / 2.0);
            assert!(
                mean.abs() < 4.0 * se + 1e-4 * white,
                "{kind:?}: {mean} ± {se}"
            );
        }
        // Rows run from the top (y = a): the bottom right is below the
        // diagonal, the top left above it.
        let img = render(&split, &options, &cancel, &|_, _| {})
            .unwrap()
            .film
            .xyzv();
        for (rows, cols, w) in [(10..16, 10..16, 1.0), (0..6, 0..6, 0.0)] {
            let (mean, se) = residual(&img, rows, cols, |_, _| w * white);
            assert!(
                mean.abs() < 4.0 * se + 1e-4 * white,
                "{kind:?}: {mean} ± {se}"
            );
        }
    }
}

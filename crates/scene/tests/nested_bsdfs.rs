//! Loading the BSDFs that pass light through or wrap others (`null`,
//! `mask`, `blendbsdf`, `normalmap`, `bumpmap`) and the polarisation
//! plugins read without polarisation; their errors and warnings.

use std::path::PathBuf;

use scotopia_color::SampledWavelengths;
use scotopia_render::bsdf::{Bsdf, Transport};
use scotopia_render::math::Vec3;
use scotopia_render::texture::FloatTexture;
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("scotopia-nested-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Writes `body` into a scene `name`.xml (one name per test).
fn write_scene(name: &str, body: &str) -> PathBuf {
    let f = dir().join(format!("{name}.xml"));
    std::fs::write(
        &f,
        format!("<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/></sensor>\n{body}\n</scene>"),
    )
    .unwrap();
    f
}

/// The scene's materials, one shape per BSDF in `bsdfs`.
fn load(name: &str, defs: &str, bsdfs: &[&str]) -> (Vec<Bsdf>, Vec<String>) {
    let shapes: String = bsdfs
        .iter()
        .map(|b| format!("<shape type=\"rectangle\">{b}</shape>\n"))
        .collect();
    let s = load_scene(
        &write_scene(name, &format!("{defs}\n{shapes}")),
        &Parameters::new(),
    )
    .unwrap();
    (s.materials, s.warnings)
}

fn error(name: &str, body: &str) -> String {
    load_scene(&write_scene(name, body), &Parameters::new())
        .unwrap_err()
        .to_string()
}

fn wl() -> SampledWavelengths<4> {
    SampledWavelengths::new([450.0, 520.0, 600.0, 680.0], [1.0; 4])
}

#[test]
fn null_mask_and_blend_load_with_their_parameters() {
    scotopia_image::write_png_rgb8(&dir().join("half.png"), 1, 1, &[255, 255, 255]).unwrap();
    let (m, warnings) = load(
        "null_mask_blend",
        r#"<bsdf type="diffuse" id="grey"/>
           <texture type="bitmap" id="alpha"><string name="filename" value="half.png"/></texture>"#,
        &[
            r#"<bsdf type="null"/>"#,
            r#"<bsdf type="mask"><float name="opacity" value="0.3"/><bsdf type="diffuse"/></bsdf>"#,
            r#"<bsdf type="mask"><ref id="grey"/></bsdf>"#,
            r#"<bsdf type="mask"><ref name="opacity" id="alpha"/><ref id="grey"/></bsdf>"#,
            r#"<bsdf type="blendbsdf"><float name="weight" value="0.25"/>
                 <bsdf type="diffuse"/><bsdf type="conductor"/></bsdf>"#,
        ],
    );
    assert!(warnings.is_empty(), "{warnings:?}");
    assert!(matches!(m[0], Bsdf::Null(_)));
    let opacity = |b: &Bsdf| match b {
        Bsdf::Mask(m) => m.opacity.clone(),
        other => panic!("{other:?}"),
    };
    assert_eq!(opacity(&m[1]), FloatTexture::Constant(0.3));
    // Mitsuba's default opacity.
    assert_eq!(opacity(&m[2]), FloatTexture::Constant(0.5));
    // A white texel: opacity 1 everywhere.
    assert!((opacity(&m[3]).eval([0.4, 0.4]) - 1.0).abs() < 1e-5);
    let Bsdf::Blend(b) = &m[4] else {
        panic!("{:?}", m[4])
    };
    assert_eq!(b.weight, FloatTexture::Constant(0.25));
    assert!(matches!(b.first, Bsdf::Diffuse(_)) && matches!(b.second, Bsdf::Conductor(_)));
}

#[test]
fn normal_and_bump_maps_load() {
    // A 1×1 normal map tilted towards +u, stored raw: (n + 1)/2 in 8 bits.
    let c = |v: f32| ((v + 1.0) / 2.0 * 255.0).round() as u8;
    let n = Vec3::new(0.5, 0.0, 0.866);
    scotopia_image::write_png_rgb8(&dir().join("normals.png"), 1, 1, &[c(n.x), c(n.y), c(n.z)])
        .unwrap();
    scotopia_image::write_png_rgb8(&dir().join("height.png"), 2, 1, &[0, 0, 0, 255, 255, 255])
        .unwrap();
    let (m, warnings) = load(
        "maps",
        "",
        &[
            r#"<bsdf type="normalmap">
                 <texture name="normalmap" type="bitmap">
                   <boolean name="raw" value="true"/><string name="filename" value="normals.png"/>
                 </texture>
                 <bsdf type="conductor"/></bsdf>"#,
            r#"<bsdf type="normalmap"><rgb name="normalmap" value="0.5, 0.5, 1"/>
                 <bsdf type="diffuse"/></bsdf>"#,
            r#"<bsdf type="bumpmap"><float name="scale" value="0.25"/>
                 <texture type="bitmap" name="arbitrary"><string name="filename" value="height.png"/>
                   <boolean name="raw" value="true"/></texture>
                 <bsdf type="conductor"/></bsdf>"#,
        ],
    );
    assert!(warnings.is_empty(), "{warnings:?}");
    let w = wl();
    let up = Vec3::new(0.0, 0.0, 1.0);
    // The mapped mirror reflects normal incidence about n (8-bit rounding).
    let s = m[0]
        .sample(&w, [0.5, 0.5], up, 0.5, [0.5, 0.5], Transport::Radiance)
        .unwrap();
    let want = n.normalize() * (2.0 * n.normalize().z) - up;
    assert!((s.wo - want).length() < 0.02, "{:?} vs {want:?}", s.wo);
    assert!(matches!(&m[1], Bsdf::NormalMap(_)));
    // The bump map's slope: 2 per unit u times 0.25.
    let s = m[2]
        .sample(&w, [0.5, 0.5], up, 0.5, [0.5, 0.5], Transport::Radiance)
        .unwrap();
    let angle = s.wo.z.acos().to_degrees();
    assert!(
        (angle - 2.0 * 0.5f32.atan().to_degrees()).abs() < 0.01,
        "{angle}"
    );
}

#[test]
fn polarisation_plugins_load_with_a_warning() {
    let (m, warnings) = load(
        "polarised",
        "",
        &[
            r#"<bsdf type="pplastic"><string name="distribution" value="ggx"/>
                 <float name="alpha" value="0.2"/></bsdf>"#,
            r#"<bsdf type="polarizer"><float name="theta" value="30"/></bsdf>"#,
            r#"<bsdf type="retarder"><float name="delta" value="90"/></bsdf>"#,
            r#"<bsdf type="circular"/>"#,
            r#"<bsdf type="measured_polarized"><string name="filename" value="x.pbsdf"/></bsdf>"#,
        ],
    );
    assert_eq!(warnings.len(), 5, "{warnings:?}");
    assert!(warnings
        .iter()
        .all(|w| w.contains("polaris") || w.contains("pBRDF")));
    assert!(matches!(m[0], Bsdf::PolarizedPlastic(_)));
    // Unpolarised light through a polariser: half; a retarder: all.
    let w = wl();
    let pass = |b: &Bsdf| {
        let wi = Vec3::new(0.0, 0.0, 1.0);
        let s = b
            .sample(&w, [0.5, 0.5], wi, 0.5, [0.5, 0.5], Transport::Radiance)
            .unwrap();
        assert_eq!(s.wo, -wi);
        assert!(s.delta);
        s.weight[0]
    };
    assert!((pass(&m[1]) - 0.5).abs() < 1e-6);
    assert!((pass(&m[2]) - 1.0).abs() < 1e-6);
    assert!((pass(&m[3]) - 0.5).abs() < 1e-6);
    assert!(matches!(m[4], Bsdf::Diffuse(_)));
}

#[test]
fn malformed_wrappers_are_errors_naming_the_element() {
    let e = error(
        "mask_none",
        r#"<shape type="rectangle"><bsdf type="mask"/></shape>"#,
    );
    assert!(e.contains("mask needs exactly one nested"), "{e}");
    let e = error(
        "blend_one",
        r#"<shape type="rectangle"><bsdf type="blendbsdf"><float name="weight" value="0.5"/>
           <bsdf type="diffuse"/></bsdf></shape>"#,
    );
    assert!(e.contains("exactly two"), "{e}");
    let e = error(
        "blend_no_weight",
        r#"<shape type="rectangle"><bsdf type="blendbsdf"><bsdf type="diffuse"/>
           <bsdf type="diffuse"/></bsdf></shape>"#,
    );
    assert!(e.contains("'weight'"), "{e}");
    let e = error(
        "normalmap_missing",
        r#"<shape type="rectangle"><bsdf type="normalmap"><bsdf type="diffuse"/></bsdf></shape>"#,
    );
    assert!(e.contains("'normalmap'"), "{e}");
    let e = error(
        "bump_missing",
        r#"<shape type="rectangle"><bsdf type="bumpmap"><bsdf type="diffuse"/></bsdf></shape>"#,
    );
    assert!(e.contains("height <texture>"), "{e}");
    let e = error(
        "mask_fluorescent",
        r#"<shape type="rectangle"><bsdf type="mask"><bsdf type="fluorescent">
             <spectrum name="excitation" value="0.2"/><spectrum name="emission" value="1"/>
           </bsdf></bsdf></shape>"#,
    );
    assert!(e.contains("fluorescent"), "{e}");
    // Errors name the file, line and column.
    assert!(e.contains(".xml:"), "{e}");
}

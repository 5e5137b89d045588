//! The loader's plugin registry is true: each Mitsuba plugin's example
//! loads (or fails, or warns) as recorded, and the documentation's tables
//! are the registry's. `SCOTOPIA_BLESS=1 cargo test -p scotopia-scene
//! --test registry` rewrites the tables after a change.

use std::path::{Path, PathBuf};

use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;
use scotopia_scene::registry::{markdown_table, summary_table, Support, PLUGINS};

mod common;
use common::{quad, write};

fn repo() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

const SENSOR: &str = r#"<sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>"#;

/// A minimal scene using `<kind type="name">`.
fn example(kind: &str, name: &str) -> String {
    let sphere = |inner: &str| format!(r#"<shape type="sphere">{inner}</shape>"#);
    let body = match (kind, name) {
        ("bsdf", "twosided" | "mask" | "normalmap" | "bumpmap") => {
            let extra = match name {
                "normalmap" => r#"<texture type="bitmap" name="normalmap"><string name="filename" value="flat.png"/><boolean name="raw" value="true"/></texture>"#,
                "bumpmap" => r#"<texture type="bitmap"><string name="filename" value="flat.png"/><boolean name="raw" value="true"/></texture>"#,
                _ => "",
            };
            sphere(&format!(r#"<bsdf type="{name}">{extra}<bsdf type="diffuse"/></bsdf>"#))
        }
        ("bsdf", "blendbsdf") => sphere(r#"<bsdf type="blendbsdf"><float name="weight" value="0.3"/><bsdf type="diffuse"/><bsdf type="conductor"/></bsdf>"#),
        ("bsdf", "fluorescent") => sphere(r#"<bsdf type="fluorescent"><spectrum name="excitation" value="360:0.5, 420:0.5, 430:0"/><spectrum name="emission" value="450:0, 500:1, 550:0"/></bsdf>"#),
        ("bsdf", "measured" | "measured_polarized") => sphere(&format!(r#"<bsdf type="{name}"><string name="filename" value="x.bsdf"/></bsdf>"#)),
        ("bsdf", _) => sphere(&format!(r#"<bsdf type="{name}"/>"#)),
        ("shape", "obj" | "ply" | "serialized") => {
            let file = match name {
                "obj" => "tri.obj",
                "ply" => "tri.ply",
                _ => "quad.serialized",
            };
            format!(r#"<shape type="{name}"><string name="filename" value="{file}"/></shape>"#)
        }
        ("shape", "shapegroup") => r#"<shape type="shapegroup" id="g"><shape type="sphere"/></shape>"#.into(),
        ("shape", "instance") => r#"<shape type="shapegroup" id="g"><shape type="sphere"/></shape><shape type="instance"><ref id="g"/></shape>"#.into(),
        ("shape", "merge") => r#"<shape type="merge"><shape type="sphere"/><shape type="disk"/></shape>"#.into(),
        ("shape", _) => format!(r#"<shape type="{name}"/>"#),
        ("emitter", "area") => r#"<shape type="sphere"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>"#.into(),
        ("emitter", "projector") => r#"<emitter type="projector"><rgb name="irradiance" value="1"/></emitter>"#.into(),
        ("emitter", "point" | "spot") => format!(r#"<emitter type="{name}"><rgb name="intensity" value="1"/></emitter>"#),
        ("emitter", "directional") => r#"<emitter type="directional"><rgb name="irradiance" value="1"/></emitter>"#.into(),
        ("emitter", "envmap") => r#"<emitter type="envmap"><string name="filename" value="flat.png"/></emitter>"#.into(),
        ("emitter", "ies") => r#"<emitter type="ies"><string name="filename" value="lamp.ies"/></emitter>"#.into(),
        ("emitter", _) => format!(r#"<emitter type="{name}"/>"#),
        ("integrator", "moment" | "aov" | "stokes") => format!(r#"<integrator type="{name}"><integrator type="path"/></integrator>"#),
        ("integrator", _) => format!(r#"<integrator type="{name}"/>"#),
        ("texture", "bitmap") => sphere(r#"<bsdf type="diffuse"><texture type="bitmap" name="reflectance"><string name="filename" value="flat.png"/></texture></bsdf>"#),
        ("texture", "mesh_attribute") => r#"<shape type="ply"><string name="filename" value="attr.ply"/><bsdf type="diffuse"><texture type="mesh_attribute" name="reflectance"><string name="name" value="vertex_w"/></texture></bsdf></shape>"#.into(),
        ("texture", "rawconstant") => sphere(r#"<bsdf type="diffuse"><texture type="rawconstant" name="reflectance"><float name="value" value="0.5"/></texture></bsdf>"#),
        ("texture", _) => sphere(&format!(r#"<bsdf type="diffuse"><texture type="{name}" name="reflectance"/></bsdf>"#)),
        ("spectrum", _) => {
            let inner = match name {
                "blackbody" => r#"<float name="temperature" value="3000"/>"#,
                "regular" => r#"<float name="wavelength_min" value="400"/><float name="wavelength_max" value="700"/><string name="values" value="1, 2"/>"#,
                "irregular" => r#"<string name="wavelengths" value="400, 700"/><string name="values" value="1, 2"/>"#,
                "uniform" | "rawconstant" => r#"<float name="value" value="1"/>"#,
                "srgb" => r#"<rgb name="color" value="0.5, 0.5, 0.5"/>"#,
                _ => "",
            };
            format!(r#"<emitter type="constant"><spectrum type="{name}" name="radiance">{inner}</spectrum></emitter>"#)
        }
        ("medium", _) => format!(r#"<medium type="{name}"/>"#),
        // Sensor-side plugins replace the default sensor (below).
        _ => String::new(),
    };
    let sensor = match (kind, name) {
        ("sensor", "irradiancemeter") => {
            r#"<shape type="rectangle"><sensor type="irradiancemeter"><film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/></film></sensor></shape>"#.into()
        }
        ("sensor", _) => format!(
            r#"<sensor type="{name}"><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>"#
        ),
        ("film", _) => format!(
            r#"<sensor type="perspective"><film type="{name}"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>"#
        ),
        ("rfilter", _) => format!(
            r#"<sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/><rfilter type="{name}"/></film></sensor>"#
        ),
        ("sampler", _) => format!(
            r#"<sensor type="perspective"><film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film><sampler type="{name}"><integer name="sample_count" value="4"/></sampler></sensor>"#
        ),
        _ => SENSOR.to_string(),
    };
    format!("<scene version=\"3.0.0\">{sensor}{body}</scene>")
}

#[test]
fn every_plugin_loads_as_the_registry_says() {
    let dir = std::env::temp_dir().join(format!("scotopia-registry-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("tri.obj"), "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n").unwrap();
    std::fs::write(
        dir.join("tri.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    )
    .unwrap();
    std::fs::write(
        dir.join("attr.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nproperty float w_0\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0 0\n1 0 0 0.5\n0 1 0 1\n3 0 1 2\n",
    )
    .unwrap();
    // A 1×1 PNG of (128, 128, 255): a flat normal map, a grey texture.
    std::fs::write(
        dir.join("quad.serialized"),
        write(&[quad("q", 0.0)], 4, false),
    )
    .unwrap();
    // An isotropic 1000 cd lamp, IES LM-63-2002.
    std::fs::write(
        dir.join("lamp.ies"),
        "IESNA:LM-63-2002\nTILT=NONE\n1 -1 1 2 1 1 2 0 0 0\n1 1 100\n0 180\n0\n1000 1000\n",
    )
    .unwrap();
    image::RgbImage::from_pixel(1, 1, image::Rgb([128, 128, 255]))
        .save(dir.join("flat.png"))
        .unwrap();

    let mut wrong = Vec::new();
    for p in PLUGINS {
        let f = dir.join(format!("{}-{}.xml", p.kind, p.name));
        std::fs::write(&f, example(p.kind, p.name)).unwrap();
        let result = load_scene(&f, &Parameters::new());
        let mentions = |w: &String| w.contains(p.name);
        let ok = match (p.support, &result) {
            (Support::Unsupported, Err(e)) => e.to_string().contains(p.name),
            (Support::Unsupported, Ok(_)) => false,
            (_, Err(_)) => false,
            (Support::Skipped, Ok(s)) => s
                .warnings
                .iter()
                .any(|w| mentions(w) && w.contains("skipped")),
            (Support::Warned, Ok(s)) => s.warnings.iter().any(mentions),
            (Support::Full | Support::Partial, Ok(s)) => !s
                .warnings
                .iter()
                .any(|w| w.contains("not supported") || w.contains("ignored") && mentions(w)),
        };
        if !ok {
            let got = match result {
                Ok(s) => format!("loads, warnings {:?}", s.warnings),
                Err(e) => format!("error: {e}"),
            };
            wrong.push(format!(
                "<{} type=\"{}\"> recorded {:?}: {got}",
                p.kind, p.name, p.support
            ));
        }
    }
    assert!(wrong.is_empty(), "\n{}", wrong.join("\n"));
}

/// Replaces the text between `<!-- registry:NAME -->` and
/// `<!-- registry:end -->` in `file`, or checks it is `table`.
fn check_or_bless(file: &Path, name: &str, table: &str) {
    let text = std::fs::read_to_string(file).unwrap();
    let begin = format!("<!-- registry:{name} -->\n");
    let end = "<!-- registry:end -->";
    let start = text
        .find(&begin)
        .unwrap_or_else(|| panic!("{} has no {begin}", file.display()))
        + begin.len();
    let stop = start + text[start..].find(end).expect("registry:end");
    if std::env::var_os("SCOTOPIA_BLESS").is_some() {
        let updated = format!("{}{table}{}", &text[..start], &text[stop..]);
        std::fs::write(file, updated).unwrap();
        return;
    }
    assert_eq!(
        &text[start..stop],
        table,
        "{} is not the registry's table: run SCOTOPIA_BLESS=1 cargo test -p scotopia-scene --test registry",
        file.display()
    );
}

#[test]
fn the_docs_tables_are_the_registrys() {
    check_or_bless(
        &repo().join("docs/scene-format.md"),
        "plugins",
        &markdown_table(),
    );
    check_or_bless(&repo().join("README.md"), "summary", &summary_table());
}

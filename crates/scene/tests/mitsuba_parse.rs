//! The Mitsuba XML parse step: defaults, parameters, includes, transforms,
//! and errors that name file, line, column and element.

use std::path::{Path, PathBuf};

use scotopia_render::math::Vec3;
use scotopia_scene::mitsuba::{parse_file, read_transform, Parameters};

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("scotopia-parse-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

#[test]
fn defaults_parameters_and_includes() {
    let d = tmp("ok");
    write(
        &d,
        "part.xml",
        r#"<scene version="3.0.0"><shape type="sphere" id="ball"/></scene>"#,
    );
    let main = write(
        &d,
        "main.xml",
        r#"<scene version="3.0.0">
    <default name="spp" value="16"/>
    <default name="res" value="64"/>
    <sampler type="independent"><integer name="sample_count" value="$spp"/></sampler>
    <film type="hdrfilm"><integer name="width" value="$res"/></film>
    <include filename="part.xml"/>
</scene>"#,
    );
    let mut params = Parameters::new();
    params.insert("spp".into(), "128".into());
    let root = parse_file(&main, &params).unwrap();
    let tags: Vec<&str> = root.children.iter().map(|n| n.tag.as_str()).collect();
    assert_eq!(tags, ["sampler", "film", "shape"]);
    assert_eq!(
        root.children[0].children[0].attr("value"),
        Some("128"),
        "parameter beats default"
    );
    assert_eq!(root.children[1].children[0].attr("value"), Some("64"));
    assert_eq!(root.children[2].attr("id"), Some("ball"));
    assert!(root.children[2].location.file.ends_with("part.xml"));
}

#[test]
fn transforms_compose_in_document_order() {
    let d = tmp("tf");
    let f = write(
        &d,
        "t.xml",
        r#"<scene version="3.0.0"><transform name="to_world">
    <scale value="2"/>
    <rotate z="1" angle="90"/>
    <translate x="1" y="2" z="3"/>
</transform></scene>"#,
    );
    let root = parse_file(&f, &Parameters::new()).unwrap();
    let t = read_transform(&root.children[0]).unwrap();
    // (1,0,0) → scale (2,0,0) → rotate (0,2,0) → translate (1,4,3).
    assert!((t.point(Vec3::new(1.0, 0.0, 0.0)) - Vec3::new(1.0, 4.0, 3.0)).length() < 1e-5);
}

#[test]
fn errors_name_file_line_column_and_element() {
    let d = tmp("err");
    let cases: [(&str, &str); 8] = [
        ("<scene version=\"3.0.0\">\n  <shape type=\"sphere\">\n</scene>", "xml"),
        // Columns count characters, not bytes; a CRLF ends a line.
        ("<scene>\r\n  <transform name=\"to_world\">\r\n  <!-- é ü --><scale value=\"0\"/>\r\n  </transform>\r\n</scene>", "t.xml:3:15: <scale>: degenerate"),
        ("<scene>\n  <film type=\"hdrfilm\"><integer name=\"width\" value=\"$w\"/></film>\n</scene>", "<integer>: parameter '$w'"),
        ("<scene>\n  <include filename=\"missing.xml\"/>\n</scene>", "<include>: cannot read"),
        ("<scene>\n  <include filename=\"self.xml\"/>\n</scene>", "includes itself"),
        ("<scene>\n  <transform name=\"to_world\">\n    <scale value=\"0\"/>\n  </transform>\n</scene>", "t.xml:3:5: <scale>: degenerate"),
        ("<scene>\n  <transform name=\"to_world\"><translate value=\"1 NaN 2\"/></transform>\n</scene>", "not a finite number"),
        ("<notascene/>", "root element must be <scene>"),
    ];
    for (text, needle) in cases {
        let name = if text.contains("self.xml") {
            "self.xml"
        } else {
            "t.xml"
        };
        let f = write(&d, name, text);
        let result = parse_file(&f, &Parameters::new()).and_then(|root| {
            for n in &root.children {
                if n.tag == "transform" {
                    read_transform(n)?;
                }
            }
            Ok(root)
        });
        let e = result.unwrap_err().to_string();
        assert!(e.contains(needle), "{text}\n→ {e}");
        assert!(e.contains(name), "names the file: {e}");
    }
}

#[test]
fn spectral_values() {
    use scotopia_scene::mitsuba::{Props, Usage};
    let d = tmp("spec");
    write(&d, "lamp.spd", "400 1\n700 3\n");
    let f = write(
        &d,
        "s.xml",
        r#"<scene version="3.0.0"><bsdf type="diffuse">
    <spectrum name="a" value="400:0.1, 500:0.3"/>
    <spectrum name="b" value="0.5"/>
    <spectrum name="c" filename="lamp.spd"/>
    <spectrum name="d" type="blackbody"><float name="temperature" value="3000"/></spectrum>
    <spectrum name="e" type="d65"/>
    <spectrum name="f" type="f11"/>
    <rgb name="g" value="0.8, 0.2, 0.1"/>
    <rgb name="h" value="1.5, 0.2, 0.1"/>
    <float name="i" value="0.25"/>
    <spectrum name="bad" value="400:0.1, 390:0.3"/>
    <float name="unused" value="1"/>
</bsdf></scene>"#,
    );
    let root = parse_file(&f, &Parameters::new()).unwrap();
    let p = Props::new(&root.children[0]);
    let s = |n: &str, u| p.spectrum(n, u).unwrap().unwrap();
    assert!((s("a", Usage::Reflectance).eval(450.0) - 0.2).abs() < 1e-6);
    assert_eq!(s("b", Usage::Reflectance).eval(600.0), 0.5);
    assert_eq!(s("c", Usage::Emission).eval(550.0), 2.0);
    assert!(s("d", Usage::Emission).eval(550.0) > 0.0);
    // Mitsuba 3.9.1's `d65` is 1.01013 at 560 nm (unit luminance-weighted
    // mean); ours is 0.11% higher, from the normalising integral's grid.
    assert!((s("e", Usage::Emission).eval(560.0) - 1.01013).abs() < 2e-3);
    // F11's 545 nm line stands far above its mean.
    assert!(s("f", Usage::Emission).eval(545.0) > 5.0 * s("f", Usage::Emission).eval(500.0));
    assert!(s("g", Usage::Reflectance).eval(650.0) > s("g", Usage::Reflectance).eval(450.0));
    assert!(p
        .spectrum("h", Usage::Reflectance)
        .unwrap_err()
        .to_string()
        .contains("above 1"));
    assert!(s("h", Usage::Emission).eval(650.0) > 0.0);
    assert_eq!(s("i", Usage::Unbounded).eval(500.0), 0.25);
    let e = p
        .spectrum("bad", Usage::Reflectance)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("s.xml:11:5: <spectrum>") && e.contains("not increasing"),
        "{e}"
    );
    assert!(p.spectrum("none", Usage::Reflectance).unwrap().is_none());
    let unused: Vec<&str> = p.unused().iter().filter_map(|n| n.attr("name")).collect();
    assert_eq!(unused, ["unused"]);
}

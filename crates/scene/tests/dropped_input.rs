//! Input the loader once dropped without a word: a second object with an
//! id already used (nested as well as at the top level), and elements no
//! builder reads (an unknown tag, an object where none of its kind is
//! taken). Each is now an error or a located warning.

use std::path::{Path, PathBuf};

use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

fn write(name: &str, text: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("scotopia-dropped-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let p = d.join("s.xml");
    std::fs::write(&p, text).unwrap();
    p
}

/// A scene whose line 2 is a sensor holding `in_sensor`, then `body`.
fn scene(in_sensor: &str, body: &str) -> String {
    format!(
        "<scene version=\"3.0.0\">\n<sensor type=\"perspective\">{in_sensor}\
         <film type=\"hdrfilm\"><integer name=\"width\" value=\"8\"/></film></sensor>\n{body}\n</scene>"
    )
}

fn warnings(path: &Path) -> Vec<String> {
    load_scene(path, &Parameters::new())
        .unwrap_or_else(|e| panic!("{e}"))
        .warnings
}

#[test]
fn a_nested_object_reusing_an_id_is_an_error_naming_both_lines() {
    let f = write(
        "nested-id",
        &scene(
            "",
            "<bsdf type=\"diffuse\" id=\"m\"/>\n\
             <shape type=\"sphere\"><bsdf type=\"conductor\" id=\"m\"/></shape>\n\
             <shape type=\"sphere\" id=\"ball\"><bsdf type=\"diffuse\" id=\"ball\"/></shape>",
        ),
    );
    let e = load_scene(&f, &Parameters::new()).unwrap_err();
    let text = e.to_string();
    assert_eq!(e.errors.len(), 2, "{text}");
    assert!(
        text.contains("s.xml:4:22: <bsdf>: id 'm' is already used by the <bsdf> at ")
            && text.contains("s.xml:3:1")
            && text.contains("<bsdf>: id 'ball' is already used by the <shape> at ")
            && text.contains("s.xml:5:1"),
        "{text}"
    );
}

#[test]
fn references_are_not_definitions() {
    // Two `<ref id="m">` name one object: no duplicate.
    let f = write(
        "refs",
        &scene(
            "",
            "<bsdf type=\"diffuse\" id=\"m\"/>\n\
             <shape type=\"sphere\"><ref id=\"m\"/></shape>\n\
             <shape type=\"sphere\"><ref id=\"m\"/></shape>",
        ),
    );
    assert!(warnings(&f).is_empty());
}

#[test]
fn an_unknown_property_tag_is_a_located_warning_naming_it() {
    let f = write(
        "unknown-tag",
        &scene("<foo name=\"fov\" value=\"10\"/>", ""),
    );
    let w = warnings(&f);
    assert_eq!(w.iter().filter(|w| w.contains("<foo>")).count(), 1, "{w:?}");
    assert!(
        w.iter()
            .any(|w| w.contains("s.xml:2:28: <foo>: unknown element <foo> (named 'fov')")),
        "{w:?}"
    );
}

#[test]
fn an_object_where_none_is_read_is_a_located_warning() {
    let f = write(
        "misplaced",
        &scene(
            "<bsdf type=\"diffuse\" name=\"fov\"/>",
            "<shape type=\"sphere\"><film type=\"hdrfilm\"/>\
             <bsdf type=\"diffuse\"><bar/></bsdf></shape>",
        ),
    );
    let w = warnings(&f);
    let expected = [
        "s.xml:2:28: <bsdf>: a <bsdf> (named 'fov') in a <sensor> is not read",
        "s.xml:3:22: <film>: a <film> in a <shape> is not read",
        "<bar>: unknown element <bar> is not read",
    ];
    for e in expected {
        assert!(w.iter().any(|w| w.contains(e)), "{e} not in {w:?}");
    }
    assert_eq!(w.len(), expected.len(), "{w:?}");
}

#[test]
fn what_builders_read_is_not_warned_about() {
    let f = write(
        "read",
        &scene(
            "<sampler type=\"independent\"><integer name=\"sample_count\" value=\"4\"/></sampler>\
             <transform name=\"to_world\"><translate x=\"1\"/></transform>",
            "<integrator type=\"path\"/>\n\
             <shape type=\"sphere\"><bsdf type=\"twosided\"><bsdf type=\"diffuse\">\
             <texture type=\"checkerboard\" name=\"reflectance\"/></bsdf></bsdf>\
             <emitter type=\"area\"><rgb name=\"radiance\" value=\"1\"/></emitter></shape>",
        ),
    );
    assert!(warnings(&f).is_empty(), "{:?}", warnings(&f));
}

#[test]
fn a_second_object_where_one_is_read_is_named() {
    // A second BSDF on a shape is an error naming the first (as Mitsuba's
    // "only a single BSDF per shape"); a second film or sampler is read
    // in place of the first, with a warning; a BSDF nested in one that
    // takes none is warned about.
    let f = write(
        "second-bsdf",
        &scene(
            "",
            "<shape type=\"sphere\"><bsdf type=\"diffuse\"/>\n<bsdf type=\"conductor\"/></shape>",
        ),
    );
    let e = load_scene(&f, &Parameters::new()).unwrap_err().to_string();
    assert!(
        e.contains("s.xml:4:1: <bsdf>: a shape takes one BSDF, and one is already given at ")
            && e.contains("s.xml:3:22"),
        "{e}"
    );
    let f = write(
        "second-film",
        &scene(
            "<sampler type=\"independent\"/><sampler type=\"independent\"/>",
            "<shape type=\"sphere\"><bsdf type=\"diffuse\"><bsdf type=\"conductor\"/></bsdf></shape>\n\
             <integrator type=\"path\"><integrator type=\"direct\"/></integrator>",
        ),
    );
    let text = std::fs::read_to_string(&f).unwrap();
    let f2 = write(
        "second-film",
        &text.replace("</sensor>", "<film type=\"hdrfilm\"/></sensor>"),
    );
    let w = warnings(&f2);
    let expected = [
        "<sampler>: a <sensor> takes one <sampler>: this one replaces the one at ",
        "<film>: a <sensor> takes one <film>: this one replaces the one at ",
        "a <bsdf> in a <bsdf> is not read by scotopia",
    ];
    for e in expected {
        assert!(w.iter().any(|w| w.contains(e)), "{e} not in {w:?}");
    }
    assert!(
        w.iter()
            .any(|w| w.contains("a <integrator> in a <integrator> is not read")),
        "{w:?}"
    );
}

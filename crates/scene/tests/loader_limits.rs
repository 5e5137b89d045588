//! Inputs that once crashed or hung the loader: nesting thousands deep
//! (a stack overflow), include chains and cycles, and files without end
//! (`/dev/zero`). Each is a located error naming the limit.

use std::path::{Path, PathBuf};

use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::{parse_file, Parameters, MAX_DEPTH, MAX_INCLUDE_DEPTH, XML_LIMIT};

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("scotopia-limits-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::write(&p, text).unwrap();
    p
}

/// Runs `f` on a thread with a 512 KiB stack: nesting that recursed per
/// level would overflow it long before 10 000 levels.
fn on_small_stack<T: Send + 'static>(f: impl FnOnce() -> T + Send + 'static) -> T {
    std::thread::Builder::new()
        .stack_size(512 * 1024)
        .spawn(f)
        .unwrap()
        .join()
        .expect("the loader overflowed its stack or panicked")
}

/// `depth` copies of `open`, then `inner`, then the closing tags.
fn nested(open: &str, close: &str, inner: &str, depth: usize) -> String {
    let mut s = String::from(r#"<scene version="3.0.0">"#);
    s.push_str(&open.repeat(depth));
    s.push_str(inner);
    s.push_str(&close.repeat(depth));
    s.push_str("</scene>");
    s
}

fn load_error(path: PathBuf) -> String {
    on_small_stack(move || match load_scene(&path, &Parameters::new()) {
        Ok(_) => panic!("{} loaded", path.display()),
        Err(e) => e.to_string(),
    })
}

#[test]
fn ten_thousand_nested_bsdfs_are_a_located_error_naming_the_limit() {
    let d = tmp("bsdfs");
    let text = nested(
        r#"<bsdf type="twosided">"#,
        "</bsdf>",
        r#"<bsdf type="diffuse"/>"#,
        10_000,
    );
    let e = load_error(write(&d, "deep.xml", &text));
    assert!(
        e.contains(&format!("nested more than {MAX_DEPTH} deep")) && e.contains("deep.xml:1:"),
        "{e}"
    );
}

#[test]
fn ten_thousand_nested_unknown_elements_are_a_located_error() {
    let d = tmp("unknown");
    let text = nested("<foo>\n", "</foo>", "", 10_000);
    let e = load_error(write(&d, "deep.xml", &text));
    // The first element past the limit, on its own line.
    let line = MAX_DEPTH + 1;
    assert!(
        e.contains(&format!(
            "deep.xml:{line}:1: <foo>: elements are nested more than {MAX_DEPTH}"
        )),
        "{e}"
    );
}

#[test]
fn nesting_at_the_limit_is_read() {
    let d = tmp("at-limit");
    // <scene> holds MAX_DEPTH levels: the deepest element is at the limit.
    let text = nested("<foo>", "</foo>", "", MAX_DEPTH);
    let path = write(&d, "ok.xml", &text);
    parse_file(&path, &Parameters::new()).unwrap();
    let text = nested("<foo>", "</foo>", "", MAX_DEPTH + 1);
    let path = write(&d, "over.xml", &text);
    assert!(parse_file(&path, &Parameters::new()).is_err());
}

#[test]
fn nesting_continues_across_includes() {
    let d = tmp("include-depth");
    let half = MAX_DEPTH / 2 + 1;
    let inner = nested("<foo>", "</foo>", "", half);
    write(&d, "inner.xml", &inner);
    let outer = nested(
        "<foo>",
        "</foo>",
        r#"<include filename="inner.xml"/>"#,
        half,
    );
    let e = load_error(write(&d, "outer.xml", &outer));
    assert!(
        e.contains("inner.xml:1:") && e.contains(&format!("more than {MAX_DEPTH} deep")),
        "{e}"
    );
}

#[test]
fn a_long_reference_chain_is_an_error_not_an_overflow() {
    let d = tmp("refs");
    let mut s = String::from(
        r#"<scene version="3.0.0"><sensor type="perspective"/><bsdf type="diffuse" id="b0"/>"#,
    );
    for i in 1..10_000 {
        s.push_str(&format!(
            r#"<bsdf type="twosided" id="b{i}"><ref id="b{}"/></bsdf>"#,
            i - 1
        ));
    }
    s.push_str(r#"<shape type="sphere"><ref id="b9999"/></shape></scene>"#);
    let e = load_error(write(&d, "chain.xml", &s));
    assert!(
        e.contains(&format!("chained more than {MAX_DEPTH} deep")),
        "{e}"
    );
}

#[test]
fn an_include_cycle_names_the_files() {
    let d = tmp("cycle");
    write(
        &d,
        "a.xml",
        r#"<scene version="3.0.0"><include filename="b.xml"/></scene>"#,
    );
    write(
        &d,
        "b.xml",
        r#"<scene version="3.0.0"><include filename="a.xml"/></scene>"#,
    );
    let e = load_error(d.join("a.xml"));
    assert!(
        e.contains("b.xml:1:24: <include>: ")
            && e.contains("a.xml includes itself")
            && e.contains("a.xml → ")
            && e.contains("b.xml → "),
        "{e}"
    );
}

#[test]
fn a_deep_include_chain_is_an_error_naming_the_files() {
    let d = tmp("chain");
    let n = MAX_INCLUDE_DEPTH + 5;
    for i in 0..n {
        write(
            &d,
            &format!("f{i}.xml"),
            &format!(
                r#"<scene version="3.0.0"><include filename="f{}.xml"/></scene>"#,
                i + 1
            ),
        );
    }
    write(&d, &format!("f{n}.xml"), r#"<scene version="3.0.0"/>"#);
    let e = load_error(d.join("f0.xml"));
    let last = MAX_INCLUDE_DEPTH - 1;
    assert!(
        e.contains(&format!("f{last}.xml:1:24: <include>: includes are nested more than {MAX_INCLUDE_DEPTH} files deep"))
            && e.contains("f0.xml → "),
        "{e}"
    );
}

#[cfg(target_os = "linux")]
#[test]
fn an_endless_include_stops_at_the_limit() {
    let d = tmp("zero");
    let scene = write(
        &d,
        "scene.xml",
        r#"<scene version="3.0.0"><include filename="/dev/zero"/></scene>"#,
    );
    let e = load_error(scene);
    let mib = XML_LIMIT >> 20;
    assert!(
        e.contains("scene.xml:1:24: <include>: cannot read /dev/zero")
            && e.contains(&format!("limit of {mib} MiB")),
        "{e}"
    );
}

#[cfg(target_os = "linux")]
#[test]
fn an_endless_spectrum_file_stops_at_the_limit() {
    let d = tmp("zero-spectrum");
    let scene = write(
        &d,
        "scene.xml",
        r#"<scene version="3.0.0">
    <sensor type="perspective"/>
    <emitter type="constant"><spectrum name="radiance" filename="/dev/zero"/></emitter>
</scene>"#,
    );
    let e = load_error(scene);
    assert!(
        e.contains("scene.xml:3:30: <spectrum>: /dev/zero: larger than the limit of 64 MiB"),
        "{e}"
    );
}

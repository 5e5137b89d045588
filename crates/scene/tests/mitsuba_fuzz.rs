//! The parser never panics, whatever the bytes: random text and random
//! mutations of a valid scene either parse or give an error.

use proptest::prelude::*;
use scotopia_scene::mitsuba::{parse_file, read_transform, Parameters};

const VALID: &str = r#"<scene version="3.0.0">
    <default name="spp" value="16"/>
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <transform name="to_world"><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="$spp"/></film>
    </sensor>
    <shape type="sphere"><transform name="to_world"><scale value="2"/><rotate y="1" angle="30"/></transform></shape>
</scene>"#;

fn check(text: &str, test: &str) {
    let dir = std::env::temp_dir().join(format!("scotopia-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join(format!("{test}.xml"));
    std::fs::write(&path, text).unwrap();
    if let Ok(root) = parse_file(&path, &Parameters::new()) {
        fn walk(n: &scotopia_scene::mitsuba::Node) {
            if n.tag == "transform" {
                let _ = read_transform(n);
            }
            n.children.iter().for_each(walk);
        }
        walk(&root);
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn random_text_never_panics(text in "\\PC{0,200}") {
        check(&text, "random");
    }

    #[test]
    fn mutated_scenes_never_panic(cuts in proptest::collection::vec((0usize..VALID.len(), 0usize..8, "[<>/=\"$ a-z0-9.,-]{0,4}"), 1..4)) {
        let mut bytes = VALID.as_bytes().to_vec();
        for (at, len, insert) in cuts {
            let at = at.min(bytes.len());
            let end = (at + len).min(bytes.len());
            bytes.splice(at..end, insert.bytes());
        }
        check(&String::from_utf8_lossy(&bytes), "mutated");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn obj_reader_never_panics(text in "([vtnf/ 0-9.e-]{0,20}\n){0,12}") {
        let _ = scotopia_scene::mesh::parse_obj(&text, "fuzz.obj");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 256, ..ProptestConfig::default() })]

    #[test]
    fn ply_reader_never_panics(tail in proptest::collection::vec(any::<u8>(), 0..200), ascii in any::<bool>()) {
        let format = if ascii { "ascii" } else { "binary_little_endian" };
        let header = format!(
            "ply\nformat {format} 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\n\
             element face 1\nproperty list uchar int vertex_indices\nend_header\n"
        );
        let mut bytes = header.into_bytes();
        bytes.extend_from_slice(&tail);
        let _ = scotopia_scene::mesh::parse_ply(&bytes, "fuzz.ply");
        let _ = scotopia_scene::mesh::parse_ply(&tail, "fuzz.ply");
    }
}

/// The bundled material showcase (textures, an envmap, rough materials)
/// with the sky's path made absolute, for mutating the whole loader.
fn showcase() -> String {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes");
    let text = std::fs::read_to_string(dir.join("material-showcase.xml")).unwrap();
    text.replace(
        "textures/showcase-sky.png",
        &dir.join("textures/showcase-sky.png").display().to_string(),
    )
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, ..ProptestConfig::default() })]

    #[test]
    fn mutated_scenes_never_panic_the_builder(cuts in proptest::collection::vec((0usize..6000, 0usize..8, "[<>/=\"$ a-z0-9.,-]{0,4}"), 1..4)) {
        let mut bytes = showcase().into_bytes();
        for (at, len, insert) in cuts {
            let at = at.min(bytes.len());
            let end = (at + len).min(bytes.len());
            bytes.splice(at..end, insert.bytes());
        }
        let dir = std::env::temp_dir().join(format!("scotopia-fuzz-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("build.xml");
        std::fs::write(&path, &bytes).unwrap();
        let _ = scotopia_scene::load_scene(&path, &Parameters::new());
    }
}

//! Mitsuba's serialized meshes: files written here in both format versions
//! and both precisions, with and without normals, UVs and colours, several
//! shapes to a file; corrupt and truncated files give errors, not panics.

use std::io::Write;

use scotopia_render::geometry::Shape;
use scotopia_render::math::Vec3;
use scotopia_scene::load_scene;
use scotopia_scene::mesh::parse_serialized;
use scotopia_scene::mitsuba::Parameters;

mod common;
use common::{quad, write, Mesh};

fn v3(p: [f64; 3]) -> Vec3 {
    Vec3::new(p[0] as f32, p[1] as f32, p[2] as f32)
}

#[test]
fn every_version_precision_and_attribute_set_reads_back() {
    let full = quad("full", 0.5);
    let bare = Mesh {
        normals: None,
        uvs: None,
        colors: None,
        positions: vec![[0.1, 0.2, 0.3], [1.0, 0.0, 0.0], [0.0, 1.0, 1e-7]],
        indices: vec![[2, 1, 0]],
        ..quad("bare", 0.0)
    };
    let uv_only = Mesh {
        normals: None,
        colors: None,
        ..quad("uv only", 2.0)
    };
    let colors_only = Mesh {
        normals: None,
        uvs: None,
        ..quad("colours", 3.0)
    };
    let meshes = [full, bare, uv_only, colors_only];
    for version in [3, 4] {
        for double in [false, true] {
            let bytes = write(&meshes, version, double);
            for (i, m) in meshes.iter().enumerate() {
                let s = parse_serialized(&bytes, i, "t.serialized")
                    .unwrap_or_else(|e| panic!("v{version} double={double} shape {i}: {e}"));
                let case = format!("v{version} double={double} shape {i}");
                assert_eq!(
                    s.name.as_deref(),
                    (version == 4).then_some(m.name),
                    "{case}"
                );
                let d = &s.mesh;
                assert_eq!(
                    d.positions,
                    m.positions.iter().map(|&p| v3(p)).collect::<Vec<_>>(),
                    "{case}"
                );
                assert_eq!(
                    d.normals,
                    m.normals
                        .as_ref()
                        .map(|n| n.iter().map(|&p| v3(p)).collect()),
                    "{case}"
                );
                assert_eq!(
                    d.uvs,
                    m.uvs
                        .as_ref()
                        .map(|t| t.iter().map(|&[u, v]| [u as f32, v as f32]).collect()),
                    "{case}"
                );
                assert_eq!(d.indices, m.indices, "{case}");
            }
        }
    }
}

#[test]
fn corrupt_and_truncated_files_give_errors_naming_file_and_shape() {
    let meshes = [quad("a", 0.0), quad("b", 1.0)];
    let good = write(&meshes, 4, false);
    let e = |bytes: &[u8], index: usize| {
        parse_serialized(bytes, index, "m.serialized")
            .unwrap_err()
            .to_string()
    };
    // Index out of range, with the count.
    let msg = e(&good, 2);
    assert!(
        msg.starts_with("m.serialized:")
            && msg.contains("shape 2: shape index 2 is out of range: the file holds 2 shapes"),
        "{msg}"
    );
    // Bad magic and unsupported versions.
    let mut bad = good.clone();
    bad[0] = 0x1d;
    assert!(e(&bad, 0).contains("bad magic 0x041D"), "{}", e(&bad, 0));
    let mut v5 = good.clone();
    v5[2] = 5;
    assert!(e(&v5, 0).contains("version 5 is not supported"));
    assert!(e(&[], 0).contains("too short"));
    assert!(e(&good[..3], 0).contains("too short"));
    // Truncated compressed data, at every length: an error every time.
    let first_end = write(&meshes[..1], 4, false).len() - 12;
    for n in 4..first_end {
        let msg = e(&good[..n], 0);
        assert!(msg.contains("m.serialized:0: shape 0:"), "{n}: {msg}");
    }
    // A truncated dictionary.
    assert!(e(&good[..good.len() - 2], 1).contains("shape 1:"));
    // The dictionary pointing outside the file.
    let mut far = good.clone();
    let at = far.len() - 4 - 8;
    far[at..at + 8].copy_from_slice(&u64::MAX.to_le_bytes());
    assert!(e(&far, 1).contains("outside the file"), "{}", e(&far, 1));
    // A huge count in an otherwise short stream: an error, no allocation.
    let huge = Mesh {
        indices: vec![[0, 1, 2]],
        ..quad("h", 0.0)
    };
    let mut bytes = write(&[huge], 3, false);
    let mut d = Vec::new();
    d.extend_from_slice(&0x1000u32.to_le_bytes());
    d.extend_from_slice(&(u32::MAX as u64).to_le_bytes());
    d.extend_from_slice(&(u64::MAX / 2).to_le_bytes());
    d.extend_from_slice(&[0u8; 64]);
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
    z.write_all(&d).unwrap();
    bytes.truncate(4);
    bytes.extend_from_slice(&z.finish().unwrap());
    let msg = e(&bytes, 0);
    assert!(msg.contains("truncated: vertex positions"), "{msg}");
    // An index past the vertices.
    let wrong = Mesh {
        indices: vec![[0, 1, 4]],
        ..quad("w", 0.0)
    };
    let msg = e(&write(&[wrong], 4, true), 0);
    assert!(msg.contains("triangle 0 refers to vertex 4"), "{msg}");
    // Random garbage after a valid header never panics.
    let mut s = 0x2545_F491_4F6C_DD1Du64;
    for len in [5usize, 17, 64, 300] {
        let mut g = vec![0x1c, 0x04, 0x04, 0x00];
        for _ in 0..len {
            s ^= s << 13;
            s ^= s >> 7;
            s ^= s << 17;
            g.push(s as u8);
        }
        for index in 0..3 {
            assert!(parse_serialized(&g, index, "g").is_err());
        }
    }
}

#[test]
fn a_serialized_shape_loads_in_a_scene() {
    let dir = std::env::temp_dir().join(format!("scotopia-serialized-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("m.serialized"),
        write(&[quad("a", 0.0), quad("b", 1.0)], 4, false),
    )
    .unwrap();
    let scene = |shape: &str| {
        format!(
            "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/></sensor>\n{shape}\n</scene>"
        )
    };
    let f = dir.join("s.xml");
    std::fs::write(
        &f,
        scene(
            r#"<shape type="serialized"><string name="filename" value="m.serialized"/><integer name="shape_index" value="1"/><boolean name="flip_normals" value="true"/><transform name="to_world"><translate z="2"/></transform></shape>"#,
        ),
    )
    .unwrap();
    let s = load_scene(&f, &Parameters::new()).unwrap();
    let Shape::Mesh(m) = &s.geometry.shapes[0] else {
        panic!("a mesh")
    };
    assert_eq!(m.positions[2], Vec3::new(1.0, 1.0, 3.0));
    // Flipped: winding and normals reversed; UVs as stored (no flip).
    assert_eq!(m.indices[0], [0, 2, 1]);
    assert_eq!(m.normals.as_ref().unwrap()[0], Vec3::new(0.0, 0.0, -1.0));
    assert_eq!(m.uvs.as_ref().unwrap()[3], [0.0, 1.0]);
    // Errors name the XML element and the mesh file with the shape.
    std::fs::write(
        &f,
        scene(
            r#"<shape type="serialized"><string name="filename" value="m.serialized"/><integer name="shape_index" value="7"/></shape>"#,
        ),
    )
    .unwrap();
    let e = load_scene(&f, &Parameters::new()).unwrap_err().to_string();
    assert!(
        e.contains("s.xml:3:1: <shape>")
            && e.contains("m.serialized:0: shape 7: shape index 7 is out of range"),
        "{e}"
    );
    std::fs::write(
        &f,
        scene(
            r#"<shape type="serialized"><string name="filename" value="m.serialized"/><integer name="shape_index" value="-1"/></shape>"#,
        ),
    )
    .unwrap();
    let e = load_scene(&f, &Parameters::new()).unwrap_err().to_string();
    assert!(e.contains("shape_index must be nonnegative"), "{e}");
}

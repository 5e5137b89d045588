//! Meshes without vertex normals get smooth ones, weighted by corner angle
//! as Mitsuba 3 computes them; `face_normals` keeps them flat.

use std::path::PathBuf;

use scotopia_render::geometry::{Shape, TriangleMesh};
use scotopia_render::math::Vec3;
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("scotopia-smooth-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Loads a scene holding `shape` (written beside `files`) and returns its mesh.
fn load_mesh(name: &str, shape: &str, files: &[(&str, &str)]) -> TriangleMesh {
    let d = dir();
    for (f, text) in files {
        std::fs::write(d.join(f), text).unwrap();
    }
    let f = d.join(format!("{name}.xml"));
    std::fs::write(
        &f,
        format!(
            "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/></sensor>\n{shape}\n</scene>"
        ),
    )
    .unwrap();
    let s = load_scene(&f, &Parameters::new()).unwrap();
    let Shape::Mesh(m) = &s.geometry.shapes[0] else {
        panic!("a mesh")
    };
    m.clone()
}

/// A UV sphere of radius 1 as OBJ text without `vn`: `rows` bands of
/// latitude, `cols` of longitude, with `vt`, so the seam at φ = 0 and the
/// poles split their vertices by texture coordinate.
fn uv_sphere(rows: usize, cols: usize) -> String {
    let mut s = String::new();
    let pi = std::f64::consts::PI;
    // One vertex at each pole, `cols` on each ring between.
    s += "v 0 0 1\n";
    for i in 1..rows {
        let theta = pi * i as f64 / rows as f64;
        for j in 0..cols {
            let phi = 2.0 * pi * j as f64 / cols as f64;
            s += &format!(
                "v {} {} {}\n",
                theta.sin() * phi.cos(),
                theta.sin() * phi.sin(),
                theta.cos()
            );
        }
    }
    s += "v 0 0 -1\n";
    for i in 0..=rows {
        for j in 0..=cols {
            s += &format!("vt {} {}\n", j as f64 / cols as f64, i as f64 / rows as f64);
        }
    }
    let v = |i: usize, j: usize| match i {
        0 => 1,
        i if i == rows => (rows - 1) * cols + 2,
        i => (i - 1) * cols + j % cols + 2,
    };
    let t = |i: usize, j: usize| i * (cols + 1) + j + 1;
    for i in 0..rows {
        for j in 0..cols {
            // Counter-clockwise seen from outside (normals outwards).
            let (a, b, c, d) = ((i, j), (i + 1, j), (i + 1, j + 1), (i, j + 1));
            let corner = |(r, k): (usize, usize)| format!("{}/{}", v(r, k), t(r, k));
            if i > 0 {
                s += &format!("f {} {} {}\n", corner(a), corner(b), corner(d));
            }
            if i + 1 < rows {
                s += &format!("f {} {} {}\n", corner(b), corner(c), corner(d));
            }
        }
    }
    s
}

#[test]
fn a_normal_less_sphere_gets_normals_close_to_the_analytic_ones() {
    let (rows, cols) = (24, 48);
    let obj = uv_sphere(rows, cols);
    let centre = Vec3::new(1.0, -2.0, 3.0);
    let m = load_mesh(
        "sphere",
        r#"<shape type="obj"><string name="filename" value="sphere.obj"/><transform name="to_world"><rotate x="1" angle="30"/><translate x="1" y="-2" z="3"/></transform></shape>"#,
        &[("sphere.obj", &obj)],
    );
    let normals = m.normals.as_ref().expect("smooth normals computed");
    // Seam and poles split by UV: more vertices than surface points.
    assert!(m.positions.len() > (rows - 1) * cols + 2);
    // Flat shading would be off by about half a cell's angle at a vertex;
    // smooth normals must be much closer (the test fails for face normals,
    // for normals pointing inwards, and for seams that are not shared).
    let half_cell = (std::f32::consts::PI / rows as f32) * 0.5;
    let mut worst = 0.0f32;
    for (p, n) in m.positions.iter().zip(normals) {
        let exact = (*p - centre).normalize();
        let angle = n.dot(exact).clamp(-1.0, 1.0).acos();
        worst = worst.max(angle);
    }
    assert!(
        worst < 0.1 * half_cell,
        "worst normal error {worst} rad (half a cell: {half_cell})"
    );
    // face_normals: no vertex normals, flat shading.
    let flat = load_mesh(
        "flat",
        r#"<shape type="obj"><string name="filename" value="sphere.obj"/><boolean name="face_normals" value="true"/></shape>"#,
        &[("sphere.obj", &obj)],
    );
    assert!(flat.normals.is_none());
    // flip_normals: the computed normals point inwards.
    let flipped = load_mesh(
        "flipped",
        r#"<shape type="obj"><string name="filename" value="sphere.obj"/><boolean name="flip_normals" value="true"/></shape>"#,
        &[("sphere.obj", &obj)],
    );
    for (p, n) in flipped
        .positions
        .iter()
        .zip(flipped.normals.as_ref().unwrap())
    {
        assert!(n.dot(p.normalize()) < -0.99, "{p:?} {n:?}");
    }
}

#[test]
fn corners_are_weighted_by_angle_not_by_area_or_count() {
    // The corner at the origin of the box [0, 1] × [0, 2] × [0, 3], its
    // faces wound to face −x, −y, −z: the z = 0 face is two triangles
    // whose angles at the corner (63.4° and 26.6°) sum to 90°, the x = 0
    // and y = 0 faces are single right triangles of areas 3 and 1.5. By
    // angle the three planes weigh alike: n = −(1, 1, 1)/√3. By count
    // the z = 0 face would weigh double; by area, x = 0 the most.
    let ply = "ply\nformat ascii 1.0\nelement vertex 5\nproperty float x\nproperty float y\nproperty float z\nelement face 4\nproperty list uchar int vertex_indices\nend_header\n\
0 0 0\n1 0 0\n1 2 0\n0 2 0\n0 0 3\n\
3 0 2 1\n3 0 3 2\n3 0 1 4\n3 0 4 3\n";
    let m = load_mesh(
        "corner",
        r#"<shape type="ply"><string name="filename" value="corner.ply"/></shape>"#,
        &[("corner.ply", ply)],
    );
    let n = m.normals.as_ref().unwrap()[0];
    let want = Vec3::new(-1.0, -1.0, -1.0).normalize();
    assert!((n - want).length() < 1e-5, "{n:?}");
    // A vertex on one face only gets that face's normal.
    assert!((m.normals.as_ref().unwrap()[2] - Vec3::new(0.0, 0.0, -1.0)).length() < 1e-6);
}

#[test]
fn a_mirroring_transform_keeps_face_and_vertex_normals_on_one_side() {
    // One triangle facing +z with a stored +z normal, mirrored in z: the
    // stored normal becomes −z (transformed as a normal) and the winding
    // is reversed so that the face normal agrees, as Mitsuba does.
    let obj = "v 0 0 0\nv 1 0 0\nv 0 1 0\nvn 0 0 1\nf 1//1 2//1 3//1\n";
    let m = load_mesh(
        "mirror",
        r#"<shape type="obj"><string name="filename" value="tri.obj"/><transform name="to_world"><scale z="-1"/></transform></shape>"#,
        &[("tri.obj", obj)],
    );
    let (a, b, c) = m.vertices(0);
    let face = (b - a).cross(c - a).normalize();
    let stored = m.normals.as_ref().unwrap()[0].normalize();
    assert!(face.z < -0.99 && stored.z < -0.99, "{face:?} {stored:?}");
}

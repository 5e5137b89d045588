//! Mitsuba's analytic shapes as the loader builds them: the cylinder, and
//! the texture coordinates of spheres and cubes.

use std::path::PathBuf;

use scotopia_render::geometry::{Hit, Shape};
use scotopia_render::math::{Ray, Vec3};
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

fn dir() -> PathBuf {
    let d = std::env::temp_dir().join(format!("scotopia-shapes-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// The shapes of a scene holding `shapes`.
fn load(name: &str, shapes: &str) -> Result<Vec<Shape>, String> {
    let f = dir().join(format!("{name}.xml"));
    std::fs::write(
        &f,
        format!(
            "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/></sensor>\n{shapes}\n</scene>"
        ),
    )
    .unwrap();
    load_scene(&f, &Parameters::new())
        .map(|s| s.geometry.shapes.clone())
        .map_err(|e| e.to_string())
}

/// The surface where `ray` first meets `shape`.
fn hit(shape: &Shape, ray: &Ray) -> Option<scotopia_render::geometry::Surface> {
    let shear = scotopia_render::geometry::RayShear::new(ray);
    (0..shape.primitive_count())
        .filter_map(|p| {
            shape
                .intersect(p, ray, &shear, f32::INFINITY)
                .map(|(t, uv)| Hit {
                    t,
                    shape: 0,
                    prim: p as u32,
                    uv,
                    instance: None,
                })
        })
        .min_by(|a, b| a.t.total_cmp(&b.t))
        .map(|h| shape.surface(&h, ray))
}

#[test]
fn a_cylinder_loads_with_mitsubas_parameters() {
    let shapes = load(
        "cyl",
        r#"<shape type="cylinder"><point name="p0" x="0" y="0" z="1"/><point name="p1" x="0" y="0" z="3"/><float name="radius" value="0.5"/><transform name="to_world"><translate x="10"/></transform></shape>
<shape type="cylinder"><boolean name="flip_normals" value="true"/></shape>"#,
    )
    .unwrap();
    // From +y towards the axis at height 2: hits at y = 0.5, u = 1/4, v = 1/2.
    let ray = Ray::new(Vec3::new(10.0, 5.0, 2.0), Vec3::new(0.0, -1.0, 0.0));
    let s = hit(&shapes[0], &ray).unwrap();
    assert!((s.p - Vec3::new(10.0, 0.5, 2.0)).length() < 1e-5, "{s:?}");
    assert!(
        (s.uv[0] - 0.25).abs() < 1e-5 && (s.uv[1] - 0.5).abs() < 1e-5,
        "{s:?}"
    );
    assert!(s.n_geometric.y > 0.9999);
    assert!((shapes[0].area() - 2.0 * std::f32::consts::PI).abs() < 1e-5);
    // The default cylinder, flipped: radius 1 on z ∈ [0, 1], normals inwards.
    let ray = Ray::new(Vec3::new(5.0, 0.0, 0.5), Vec3::new(-1.0, 0.0, 0.0));
    let s = hit(&shapes[1], &ray).unwrap();
    assert!((s.p - Vec3::new(1.0, 0.0, 0.5)).length() < 1e-5, "{s:?}");
    assert!(s.n_geometric.x < -0.9999);
    // Degenerate ones are errors naming the element.
    let e = load(
        "cyl-bad",
        r#"<shape type="cylinder"><float name="radius" value="0"/></shape>"#,
    )
    .unwrap_err();
    assert!(
        e.contains("<shape>") && e.contains("radius must be positive"),
        "{e}"
    );
    let e = load(
        "cyl-bad2",
        r#"<shape type="cylinder"><point name="p1" x="0" y="0" z="0"/></shape>"#,
    )
    .unwrap_err();
    assert!(e.contains("p0 and p1 must differ"), "{e}");
}

#[test]
fn a_rotated_spheres_uvs_turn_with_it() {
    // World centre (1, 2, 3), radius 1, turned 90° about z (then x).
    let shapes = load(
        "sphere-uv",
        r#"<shape type="sphere"><float name="radius" value="0.5"/><transform name="to_world"><scale value="2"/><rotate z="1" angle="90"/><translate x="1" y="2" z="3"/></transform></shape>
<shape type="sphere"><transform name="to_world"><rotate x="1" angle="90"/></transform></shape>
<shape type="sphere"/>"#,
    )
    .unwrap();
    // Hit at world direction −x: object direction +y, φ = 90°: u = 1/4
    // (unrotated it would be 1/2), θ = 90°: v = 1/2.
    let ray = Ray::new(Vec3::new(-4.0, 2.0, 3.0), Vec3::new(1.0, 0.0, 0.0));
    let s = hit(&shapes[0], &ray).unwrap();
    assert!((s.p - Vec3::new(0.0, 2.0, 3.0)).length() < 1e-5, "{s:?}");
    assert!(
        (s.uv[0] - 0.25).abs() < 1e-5 && (s.uv[1] - 0.5).abs() < 1e-5,
        "{s:?}"
    );
    // Turned about x: world +z is object +y (v = 1/2, u = 1/4), where the
    // unrotated sphere has its pole (v = 0).
    let down = Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0));
    let s = hit(&shapes[1], &down).unwrap();
    assert!(
        (s.uv[0] - 0.25).abs() < 1e-5 && (s.uv[1] - 0.5).abs() < 1e-5,
        "{s:?}"
    );
    let s = hit(&shapes[2], &down).unwrap();
    assert!(s.uv[1].abs() < 1e-3, "{s:?}");
    // The unrotated sphere: world −x is φ = 180°, u = 1/2.
    let s = hit(
        &shapes[2],
        &Ray::new(Vec3::new(-5.0, 0.0, 0.0), Vec3::new(1.0, 0.0, 0.0)),
    )
    .unwrap();
    assert!(
        (s.uv[0] - 0.5).abs() < 1e-5 && (s.uv[1] - 0.5).abs() < 1e-5,
        "{s:?}"
    );
}

#[test]
fn each_cube_face_maps_its_corners_as_mitsubas_cube() {
    // Mitsuba's cube, face by face: the four corners and the uv there
    // ((0, 1), (1, 1), (1, 0), (0, 0) in this order), and the outward normal.
    let faces: [([[f32; 3]; 4], [f32; 3]); 6] = [
        (
            [
                [1., -1., -1.],
                [1., -1., 1.],
                [-1., -1., 1.],
                [-1., -1., -1.],
            ],
            [0., -1., 0.],
        ),
        (
            [[1., 1., -1.], [-1., 1., -1.], [-1., 1., 1.], [1., 1., 1.]],
            [0., 1., 0.],
        ),
        (
            [[1., -1., -1.], [1., 1., -1.], [1., 1., 1.], [1., -1., 1.]],
            [1., 0., 0.],
        ),
        (
            [[1., -1., 1.], [1., 1., 1.], [-1., 1., 1.], [-1., -1., 1.]],
            [0., 0., 1.],
        ),
        (
            [
                [-1., -1., 1.],
                [-1., 1., 1.],
                [-1., 1., -1.],
                [-1., -1., -1.],
            ],
            [-1., 0., 0.],
        ),
        (
            [
                [1., 1., -1.],
                [1., -1., -1.],
                [-1., -1., -1.],
                [-1., 1., -1.],
            ],
            [0., 0., -1.],
        ),
    ];
    let uv = [[0.0, 1.0], [1.0, 1.0], [1.0, 0.0], [0.0, 0.0]];
    let shapes = load(
        "cube-uv",
        r#"<shape type="cube"/>
<shape type="cube"><boolean name="flip_normals" value="true"/></shape>
<shape type="cube"><transform name="to_world"><scale x="-1"/></transform></shape>"#,
    )
    .unwrap();
    let v = |a: [f32; 3]| Vec3::new(a[0], a[1], a[2]);
    for (corners, normal) in faces {
        let n = v(normal);
        for (k, c) in corners.iter().enumerate() {
            // Just inside the corner, seen from outside along the normal.
            let target = v(*c) * 0.99 + n * 0.01;
            let ray = Ray::new(target + n * 3.0, -n);
            let s = hit(&shapes[0], &ray).unwrap();
            let want = uv[k];
            assert!(
                (s.uv[0] - want[0]).abs() < 0.006 && (s.uv[1] - want[1]).abs() < 0.006,
                "face {normal:?} corner {c:?}: uv {:?}, want {want:?}",
                s.uv
            );
            assert!((s.n_geometric - n).length() < 1e-6, "{s:?}");
            // Flipped: normals inwards, same uv.
            let f = hit(&shapes[1], &ray).unwrap();
            assert!((f.n_geometric + n).length() < 1e-6 && (f.uv[0] - s.uv[0]).abs() < 1e-6);
            // Mirrored in x: still outwards.
            let m = hit(&shapes[2], &ray).unwrap();
            assert!((m.n_geometric - n).length() < 1e-6, "mirrored: {m:?}");
        }
    }
}

#[test]
fn a_flipped_sphere_loads_with_inward_normals() {
    let shapes = load(
        "sphere-flip",
        r#"<shape type="sphere"><boolean name="flip_normals" value="true"/></shape>"#,
    )
    .unwrap();
    let s = hit(
        &shapes[0],
        &Ray::new(Vec3::new(0.0, 0.0, 5.0), Vec3::new(0.0, 0.0, -1.0)),
    )
    .unwrap();
    assert!(s.n_geometric.z < -0.9999 && s.uv[1].abs() < 1e-3, "{s:?}");
}

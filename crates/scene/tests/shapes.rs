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

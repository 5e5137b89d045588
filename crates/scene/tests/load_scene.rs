//! Loading whole scenes: the bundled Cornell box, and errors.

use std::path::{Path, PathBuf};

use scotopia_render::bsdf::Bsdf;
use scotopia_render::math::Vec3;
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

#[test]
fn cornell_box_loads() {
    let mut params = Parameters::new();
    params.insert("res".into(), "32".into());
    let s = load_scene(&scenes().join("cornell-box.xml"), &params).unwrap();
    assert_eq!(s.geometry.shapes.len(), 8);
    assert_eq!(s.lights.len(), 1);
    assert_eq!(s.shape_light.iter().filter(|l| l.is_some()).count(), 1);
    assert_eq!(
        (s.camera.width, s.camera.height, s.samples_per_pixel),
        (32, 32, 64)
    );
    assert_eq!(s.integrator.max_depth, 8);
    // The film's pixel_format is Mitsuba's business: one warning, named.
    assert!(
        s.warnings.iter().any(|w| w.contains("pixel_format")),
        "{:?}",
        s.warnings
    );
    // The light faces down, into the box.
    let ray = s.camera.generate_ray([16.0, 16.0], [0.5, 0.5]);
    let hit = s
        .geometry
        .intersect(&ray)
        .expect("the centre ray hits the box");
    assert!(hit.t > 0.0);
    let light_shape = s.shape_light.iter().position(|l| l.is_some()).unwrap();
    let down = scotopia_render::math::Ray::new(Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0));
    let h = s.geometry.intersect(&down).unwrap();
    assert_eq!(h.shape as usize, light_shape);
    let surface = s.geometry.shapes[light_shape].surface(&h, &down);
    assert!(surface.n_geometric.y < -0.99, "{:?}", surface.n_geometric);
}

#[test]
fn load_errors_name_the_place() {
    let dir = std::env::temp_dir().join(format!("scotopia-load-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let cases = [
        (
            r#"<shape type="sphere"><ref id="nope"/></shape>"#,
            "no <bsdf id=\"nope\">",
        ),
        (
            r#"<shape type="teapot"/>"#,
            "shape type 'teapot' is not supported",
        ),
        (
            r#"<shape type="sphere"><float name="radius" value="-1"/></shape>"#,
            "radius must be positive",
        ),
        (
            r#"<bsdf type="roughconductor" id="m"><string name="distribution" value="phong"/></bsdf><shape type="sphere"><ref id="m"/></shape>"#,
            "invalid microfacet distribution 'phong'",
        ),
        (
            r#"<shape type="sphere"><bsdf type="conductor"><string name="material" value="Unobtainium"/></bsdf></shape>"#,
            "unknown conductor 'Unobtainium'",
        ),
        (
            r#"<shape type="sphere"><bsdf type="dielectric"><string name="int_ior" value="glass"/></bsdf></shape>"#,
            "unknown index of refraction 'glass'",
        ),
        (
            r#"<shape type="sphere"><bsdf type="dielectric"><string name="int_ior" value="cauchy: 1.5"/></bsdf></shape>"#,
            "int_ior 'cauchy: 1.5': cauchy takes A B or A B C",
        ),
        (r#"<emitter type="point"/>"#, "missing 'intensity'"),
        (
            r#"<bsdf type="twosided" id="m"><ref id="m"/></bsdf><shape type="sphere"><ref id="m"/></shape>"#,
            "'m' refers to itself",
        ),
        (
            r#"<emitter type="constant"><spectrum name="radiance" value="0"><float name="luminance" value="1"/></spectrum></emitter>"#,
            "no luminance to scale",
        ),
        (
            r#"<emitter type="constant"><spectrum name="radiance" type="d65"><float name="luminance" value="1"/><float name="scale" value="2"/></spectrum></emitter>"#,
            "not both",
        ),
        (r#"<emitter type="envmap"/>"#, "needs a 'filename'"),
        (
            r#"<shape type="sphere"><emitter type="area"><rgb name="radiance" value="-1, 0, 0"/></emitter></shape>"#,
            "outside the srgb gamut",
        ),
        (
            r#"<shape type="sphere"><bsdf type="fluorescent"><float name="reflectance" value="0.8"/><spectrum name="excitation" value="360:0.5, 400:0.1"/><spectrum name="emission" value="420:0, 450:1, 500:0"/></bsdf></shape>"#,
            "reflectance + excitation is 1.3000 at 360 nm",
        ),
        (
            r#"<shape type="sphere"><bsdf type="fluorescent"><spectrum name="excitation" value="360:0.5, 400:0.1"/></bsdf></shape>"#,
            "needs an 'emission' spectrum",
        ),
        (
            r#"<shape type="sphere"><bsdf type="fluorescent"><spectrum name="excitation" value="360:0.5, 400:0.1"/><spectrum name="emission" value="420:0, 450:1, 500:0"/><float name="quantum_yield" value="1.5"/></bsdf></shape>"#,
            "quantum_yield 1.5",
        ),
        (
            r#"<shape type="sphere"><bsdf type="fluorescent"><string name="matrix" value="paper.csv"/></bsdf></shape>"#,
            "paper.csv: ",
        ),
        (
            r#"<shape type="sphere"><bsdf type="fluorescent"><string name="matrix" value="hot.csv"/><spectrum name="excitation" value="0.1"/></bsdf></shape>"#,
            "'excitation' and 'matrix' are two descriptions",
        ),
        (
            r#"<shape type="sphere"><bsdf type="fluorescent"><string name="matrix" value="hot.csv"/></bsdf></shape>"#,
            "re-emitted from 365 nm is 1.2000",
        ),
        (
            r#"<shape type="sphere"><bsdf type="fluorescent"><string name="matrix" value="nodiag.csv"/></bsdf></shape>"#,
            "add a 'reflectance'",
        ),
        (
            r#"<shape type="sphere"><bsdf type="fluorescent"><string name="matrix" value="bad.csv"/></bsdf></shape>"#,
            "bad.csv:3: expected 3 fields",
        ),
        (
            r#"<shape type="sphere"><bsdf type="fluorescent"><texture type="checkerboard" name="reflectance"><float name="color0" value="0.9"/><float name="color1" value="0.1"/></texture><spectrum name="excitation" value="360:0.3, 400:0"/><spectrum name="emission" value="420:0, 450:1, 500:0"/></bsdf></shape>"#,
            "reflectance + excitation is 1.2000 at 360 nm",
        ),
    ];
    // Matrices: too much light out of the 370 nm column (its 380 nm row is
    // interior, so it re-emits its cell, 0.4); no diagonal; a short row.
    std::fs::write(
        dir.join("hot.csv"),
        "nm,360,370,380,390\n360,0.8,0,0,0\n370,0,0.8,0,0\n380,0,0.4,0.8,0\n390,0,0,0,0.8\n",
    )
    .unwrap();
    std::fs::write(dir.join("nodiag.csv"), "nm,360,370\n400,0,0.1\n410,0,0.1\n").unwrap();
    std::fs::write(dir.join("bad.csv"), "nm,360,370\n360,0.5,0\n370,0.5\n").unwrap();
    let sensor = r#"<sensor type="perspective"><float name="fov" value="40"/></sensor>"#;
    for (body, needle) in cases {
        let f = dir.join("s.xml");
        std::fs::write(
            &f,
            format!("<scene version=\"3.0.0\">\n{sensor}\n{body}\n</scene>"),
        )
        .unwrap();
        let e = load_scene(&f, &Parameters::new()).unwrap_err().to_string();
        assert!(
            e.contains(needle) && e.contains("s.xml:3:"),
            "{body}\n→ {e}"
        );
    }
    let f = dir.join("nosensor.xml");
    std::fs::write(&f, "<scene version=\"3.0.0\"/>").unwrap();
    assert!(load_scene(&f, &Parameters::new())
        .unwrap_err()
        .to_string()
        .contains("no <sensor>"));
}

#[test]
fn a_film_that_cannot_fit_is_an_error_naming_the_line_and_the_limit() {
    let dir = std::env::temp_dir().join(format!("scotopia-huge-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("huge.xml");
    for size in ["1000000000", "100000"] {
        std::fs::write(
            &f,
            format!(
                "<scene version=\"3.0.0\">\n<sensor type=\"perspective\">\n<film type=\"hdrfilm\">\
                 <integer name=\"width\" value=\"{size}\"/><integer name=\"height\" value=\"{size}\"/>\
                 </film></sensor></scene>"
            ),
        )
        .unwrap();
        let e = load_scene(&f, &Parameters::new()).unwrap_err().to_string();
        assert!(e.contains("huge.xml:2:"), "{e}");
        assert!(
            e.contains(&format!("a film of {size} × {size} pixels")),
            "{e}"
        );
        assert!(e.contains("the limit is"), "{e}");
    }
}

#[test]
fn obj_and_ply_meshes_load_with_mitsuba_conventions() {
    let dir = std::env::temp_dir().join(format!("scotopia-obj-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(
        dir.join("quad.obj"),
        "v -1 -1 0\nv 1 -1 0\nv 1 1 0\nv -1 1 0\nvt 0 0\nvt 1 0\nvt 1 1\nvt 0 1\nf 1/1 2/2 3/3 4/4\n",
    )
    .unwrap();
    std::fs::write(dir.join("broken.obj"), "v 0 0 0\nf 1 2 3\n").unwrap();
    std::fs::write(
        dir.join("tri.ply"),
        "ply\nformat ascii 1.0\nelement vertex 3\nproperty float x\nproperty float y\nproperty float z\nelement face 1\nproperty list uchar int vertex_indices\nend_header\n0 0 0\n1 0 0\n0 1 0\n3 0 1 2\n",
    )
    .unwrap();
    let scene = |shape: &str| {
        format!(
            "<scene version=\"3.0.0\">\n<sensor type=\"perspective\"><float name=\"fov\" value=\"40\"/></sensor>\n{shape}\n</scene>"
        )
    };
    let f = dir.join("s.xml");
    std::fs::write(&f, scene(r#"<shape type="obj"><string name="filename" value="quad.obj"/><transform name="to_world"><translate z="2"/></transform></shape>"#)).unwrap();
    let s = load_scene(&f, &Parameters::new()).unwrap();
    let scotopia_render::geometry::Shape::Mesh(m) = &s.geometry.shapes[0] else {
        panic!("a mesh")
    };
    assert_eq!(m.triangle_count(), 2);
    assert_eq!(m.positions[0], Vec3::new(-1.0, -1.0, 2.0));
    // Texture v is flipped, as Mitsuba does for OBJ.
    assert_eq!(m.uvs.as_ref().unwrap()[0], [0.0, 1.0]);
    std::fs::write(
        &f,
        scene(r#"<shape type="obj"><string name="filename" value="broken.obj"/></shape>"#),
    )
    .unwrap();
    let e = load_scene(&f, &Parameters::new()).unwrap_err().to_string();
    assert!(
        e.contains("s.xml:3:1: <shape>")
            && e.contains("broken.obj:2: vertex index 2 is out of range"),
        "{e}"
    );
}

#[test]
fn focal_length_sets_the_diagonal_field_as_in_mitsuba() {
    let dir = std::env::temp_dir().join(format!("scotopia-focal-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("focal.xml");
    std::fs::write(
        &f,
        r#"<scene version="3.0.0"><sensor type="perspective"><string name="focal_length" value="35mm"/>
<film type="hdrfilm"><integer name="width" value="64"/><integer name="height" value="48"/></film></sensor></scene>"#,
    )
    .unwrap();
    let s = load_scene(&f, &Parameters::new()).unwrap();
    // Mitsuba 3.9.1 reports x_fov = 52.6225° for this sensor.
    let ray = s.camera.generate_ray([64.0, 24.0], [0.5, 0.5]);
    let centre = s.camera.generate_ray([32.0, 24.0], [0.5, 0.5]);
    let half = ray
        .d
        .normalize()
        .dot(centre.d.normalize())
        .acos()
        .to_degrees();
    assert!((2.0 * half - 52.6225).abs() < 1e-3, "{}", 2.0 * half);
    std::fs::write(
        &f,
        r#"<scene version="3.0.0"><sensor type="perspective"><string name="focal_length" value="wide"/></sensor></scene>"#,
    )
    .unwrap();
    let e = load_scene(&f, &Parameters::new()).unwrap_err().to_string();
    assert!(e.contains("focal_length 'wide'"), "{e}");
}

#[test]
fn bundled_scenes_load_without_warnings() {
    use scotopia_color::photometry::spectrum_to_xyzv;
    use scotopia_render::light::Light;
    // (file, shapes, lights)
    for (name, shapes, lights) in [
        ("night-street.xml", 18, 5),
        ("prism.xml", 8, 2),
        ("material-showcase.xml", 5, 2),
        ("black-light-poster.xml", 9, 1),
        ("paper.xml", 4, 2),
        ("diamond.xml", 9, 8),
        ("caustic-sphere.xml", 4, 1),
        ("lamp-shade.xml", 8, 1),
    ] {
        let s = load_scene(&scenes().join(name), &Parameters::new()).unwrap();
        assert_eq!(s.geometry.shapes.len(), shapes, "{name}");
        assert_eq!(s.lights.len(), lights, "{name}");
        assert!(s.warnings.is_empty(), "{name}: {:?}", s.warnings);
    }
    // The poster's four inks fluoresce, the highlighter's from a matrix.
    let s = load_scene(&scenes().join("black-light-poster.xml"), &Parameters::new()).unwrap();
    let inks: Vec<_> = s.materials.iter().filter_map(|m| m.fluorescent()).collect();
    assert_eq!(inks.len(), 4);
    assert_eq!(inks.iter().filter(|f| f.separable().is_none()).count(), 1);
    // The street's lamps are at their stated absolute levels (the
    // `luminance` extension): 15 000 cd/m² sodium, 13 000 cd/m² LED.
    let s = load_scene(&scenes().join("night-street.xml"), &Parameters::new()).unwrap();
    let levels: Vec<f64> = s
        .lights
        .iter()
        .filter_map(|l| match l {
            Light::Area(a) => Some(spectrum_to_xyzv(a.mean_radiance()).y),
            _ => None,
        })
        .collect();
    assert_eq!(levels.len(), 3);
    for (y, want) in levels.iter().zip([15000.0, 15000.0, 13000.0]) {
        assert!((y - want).abs() < 1e-3 * want, "{levels:?}");
    }
}

#[test]
fn a_fluorescent_bsdf_loads_with_its_spectra() {
    let dir = std::env::temp_dir().join(format!("scotopia-fluor-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("f.xml");
    std::fs::write(
        &f,
        r#"<scene version="3.0.0">
<sensor type="perspective"><float name="fov" value="40"/></sensor>
<shape type="sphere"><bsdf type="fluorescent">
  <float name="reflectance" value="0.4"/>
  <spectrum name="excitation" value="360:0.5, 400:0.3, 420:0"/>
  <spectrum name="emission" value="420:0, 450:2, 500:0"/>
  <float name="quantum_yield" value="0.9"/>
</bsdf></shape>
</scene>"#,
    )
    .unwrap();
    let s = load_scene(&f, &Parameters::new()).unwrap();
    let Bsdf::Fluorescent(b) = &s.materials[0] else {
        panic!("{:?}", s.materials[0]);
    };
    assert!((b.separable().unwrap().excitation(380.0) - 0.4).abs() < 1e-4);
    assert_eq!(b.separable().unwrap().quantum_yield(), 0.9);
    // The emission is normalised: a triangle 80 nm wide peaks at 1/40.
    assert!(
        (b.separable().unwrap().emission(450.0) - 1.0 / 40.0).abs() < 1e-4,
        "{}",
        b.separable().unwrap().emission(450.0)
    );
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
}

#[test]
fn a_reradiation_matrix_and_a_textured_reflectance_load() {
    let dir = std::env::temp_dir().join(format!("scotopia-matrix-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    // Reflectance 0.6 on the diagonal; 380 nm re-emitted at 400–420 nm;
    // one negative cell of noise.
    std::fs::write(
        dir.join("paper.csv"),
        "emission\\excitation,360,380,400,420\n\
         360,0.6,0,0,0\n380,0,0.6,0,-0.001\n400,0,0.05,0.6,0\n420,0,0.1,0,0.6\n",
    )
    .unwrap();
    let f = dir.join("m.xml");
    std::fs::write(
        &f,
        r#"<scene version="3.0.0">
<sensor type="perspective"><float name="fov" value="40"/></sensor>
<shape type="sphere"><bsdf type="fluorescent"><string name="matrix" value="paper.csv"/></bsdf></shape>
<shape type="sphere"><bsdf type="fluorescent">
  <texture type="checkerboard" name="reflectance"><float name="color0" value="0.2"/><float name="color1" value="0.6"/></texture>
  <spectrum name="excitation" value="360:0.3, 400:0"/>
  <spectrum name="emission" value="420:0, 450:1, 500:0"/>
</bsdf></shape>
</scene>"#,
    )
    .unwrap();
    let s = load_scene(&f, &Parameters::new()).unwrap();
    let Bsdf::Fluorescent(m) = &s.materials[0] else {
        panic!("{:?}", s.materials[0]);
    };
    assert_eq!(m.reflectance.max_over_surface(&[390.0]), vec![0.6]);
    // Cells are per 20 nm band of excitation: F = 0.1/20 at (380 → 420).
    assert!((m.eval_reradiation(385.0, 420.0) - 0.005).abs() < 1e-6);
    assert!((m.fluorescent_albedo(410.0) - 0.075).abs() < 1e-6);
    assert!(
        s.warnings.iter().any(|w| w.contains("1 negative cells")),
        "{:?}",
        s.warnings
    );
    let Bsdf::Fluorescent(t) = &s.materials[1] else {
        panic!("{:?}", s.materials[1]);
    };
    assert!(t.reflectance.is_varying());
    assert_eq!(s.warnings.len(), 1, "{:?}", s.warnings);
}

//! `shapegroup` + `instance` from the scene file to the image: a scene whose
//! groups are placed by instances renders as the same scene with each
//! group's shapes copied and placed by hand (the instance's `to_world`
//! after the shape's own), with the path tracer and the bidirectional
//! tracer; and a forest of instances holds one copy of its tree.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use scotopia_render::integrator::{render, RenderOptions};
use scotopia_render::scene::{IntegratorKind, Scene};
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;
use scotopia_scene::SceneInfo;

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("scotopia-instances-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn load(dir: &Path, name: &str, body: &str) -> Scene {
    let text = format!(
        r#"<scene version="3.0.0">
<sensor type="perspective"><float name="fov" value="50"/>
    <transform name="to_world"><lookat origin="0, 3, 12" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="48"/><integer name="height" value="36"/></film>
</sensor>
<integrator type="path"><integer name="max_depth" value="6"/></integrator>
<shape type="rectangle">
    <transform name="to_world"><scale value="2"/><rotate x="1" angle="90"/><translate y="6"/></transform>
    <emitter type="area"><rgb name="radiance" value="6, 5, 4"/></emitter>
</shape>
<shape type="rectangle">
    <transform name="to_world"><scale value="10"/><rotate x="1" angle="-90"/><translate y="-2.5"/></transform>
    <bsdf type="diffuse"><rgb name="reflectance" value="0.6, 0.6, 0.5"/></bsdf>
</shape>
{body}
</scene>"#
    );
    let path = dir.join(name);
    std::fs::write(&path, text).unwrap();
    load_scene(&path, &Parameters::new()).unwrap_or_else(|e| panic!("{e}"))
}

/// A bumpy ball with normals and texture coordinates, as OBJ text.
fn ball_obj() -> String {
    let (rows, cols) = (8, 12);
    let mut s = String::new();
    for i in 0..=rows {
        for j in 0..=cols {
            let (u, v) = (j as f32 / cols as f32, i as f32 / rows as f32);
            let (theta, phi) = (v * std::f32::consts::PI, u * std::f32::consts::TAU);
            let n = [
                theta.sin() * phi.cos(),
                theta.cos(),
                theta.sin() * phi.sin(),
            ];
            let r = 1.0 + 0.15 * (3.0 * phi).sin() * theta.sin();
            s += &format!("v {} {} {}\n", n[0] * r, n[1] * r, n[2] * r);
            s += &format!("vn {} {} {}\nvt {u} {v}\n", n[0], n[1], n[2]);
        }
    }
    let at = |i: usize, j: usize| i * (cols + 1) + j + 1;
    for i in 0..rows {
        for j in 0..cols {
            let (a, b, c, d) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
            s += &format!("f {a}/{a}/{a} {c}/{c}/{c} {b}/{b}/{b}\n");
            s += &format!("f {a}/{a}/{a} {d}/{d}/{d} {c}/{c}/{c}\n");
        }
    }
    s
}

/// The cube is a smooth conductor: a rough one would be a reflector that
/// the path tracer aims diffuse bounces at (`integrator/reflectors.rs`)
/// among the copies' top-level meshes but not inside instances, so the
/// two renders would draw different (equally unbiased) paths.
///
/// The shapes of a group, each placed by its own `to_world` followed by
/// the operations `then` (an instance's placement, for the copies).
/// `sphere`: a glass sphere too (a sphere may only be scaled uniformly).
fn members(then: &str, sphere: bool) -> String {
    let mut s = format!(
        r#"<shape type="obj"><string name="filename" value="ball.obj"/>
    <transform name="to_world"><scale value="0.9"/>{then}</transform>
    <bsdf type="diffuse"><texture name="reflectance" type="checkerboard">
        <rgb name="color0" value="0.8, 0.2, 0.1"/><rgb name="color1" value="0.1, 0.3, 0.8"/>
        <transform name="to_uv"><scale value="6"/></transform>
    </texture></bsdf>
</shape>
<shape type="cube">
    <transform name="to_world"><scale x="0.4" y="0.3" z="0.5"/><rotate y="1" angle="25"/><translate x="1.4" y="-0.6"/>{then}</transform>
    <bsdf type="conductor"><string name="material" value="Au"/></bsdf>
</shape>
<shape type="rectangle">
    <transform name="to_world"><scale x="0.8" y="0.5"/><rotate y="1" angle="40"/><translate x="-1.3" y="0.2" z="0.4"/>{then}</transform>
    <bsdf type="twosided"><bsdf type="diffuse"><rgb name="reflectance" value="0.2, 0.7, 0.3"/></bsdf></bsdf>
</shape>
"#
    );
    if sphere {
        s += &format!(
            r#"<shape type="sphere"><point name="center" x="0.2" y="1.3" z="0.6"/><float name="radius" value="0.45"/>
    <transform name="to_world">{then}</transform>
    <bsdf type="dielectric"><float name="int_ior" value="1.5"/></bsdf>
</shape>
"#
        );
    }
    s
}

/// Four placements: a rotated and uniformly scaled one of the group with
/// the sphere; of the group without, a rotated, non-uniformly scaled one,
/// a sheared (scaled, then rotated) one, and a mirrored one (the loader
/// reverses a mirrored copy's winding, so its face normals keep their
/// side, as an instance's do).
const PLACEMENTS: [(&str, bool); 4] = [
    (
        r#"<scale value="1.2"/><rotate x="0.3" y="1" z="0.2" angle="35"/><translate x="-3" y="-0.8"/>"#,
        true,
    ),
    (
        r#"<rotate x="1" y="0.2" angle="-30"/><scale x="1.6" y="0.7" z="1.1"/><translate x="2.6" y="-1"/>"#,
        false,
    ),
    (
        r#"<scale x="0.6" y="1.3" z="0.8"/><rotate z="1" angle="40"/><translate y="2.2" z="-2"/>"#,
        false,
    ),
    (
        r#"<scale x="-0.8" y="0.8" z="0.8"/><rotate y="1" angle="60"/><translate x="0.3" y="-1.4" z="2.5"/>"#,
        false,
    ),
];

/// The same world written with groups and instances, and with copies.
fn scenes(dir: &Path) -> (Scene, Scene) {
    std::fs::write(dir.join("ball.obj"), ball_obj()).unwrap();
    let mut instanced = format!(
        "<shape type=\"shapegroup\" id=\"with\">{}</shape>\n<shape type=\"shapegroup\" id=\"without\">{}</shape>\n",
        members("", true),
        members("", false)
    );
    let mut copied = String::new();
    for (ops, sphere) in PLACEMENTS {
        let id = if sphere { "with" } else { "without" };
        instanced += &format!(
            "<shape type=\"instance\"><ref id=\"{id}\"/><transform name=\"to_world\">{ops}</transform></shape>\n"
        );
        copied += &members(ops, sphere);
    }
    let a = load(dir, "instanced.xml", &instanced);
    let b = load(dir, "copied.xml", &copied);
    assert_eq!(a.geometry.instances().len(), 4);
    assert!(b.geometry.instances().is_empty());
    (a, b)
}

fn image(scene: &Scene, integrator: IntegratorKind) -> Vec<[f32; 4]> {
    let options = RenderOptions {
        spp: Some(16),
        seed: 5,
        integrator: Some(integrator),
        ..RenderOptions::default()
    };
    let r = render(scene, &options, &AtomicBool::new(false), &|_, _| {}).unwrap();
    r.film.xyzv()
}

/// The two renders use the same random numbers per pixel and sample, and
/// the geometry differs only by rounding (rays meet the group in its own
/// space, the copies in world space), so a pixel's value agrees to float
/// rounding unless one of its paths took a different discrete turn (a
/// ray grazing an edge, a lobe or Russian-roulette choice at a threshold).
/// Such pixels are rare: at most 2% may differ by more than 1e-3
/// (relative). Over the image, the difference is zero in the mean within
/// 4 standard errors (from the spread of the pixel differences), which
/// bounds what those few pixels can add.
fn agree(what: &str, a: &[[f32; 4]], b: &[[f32; 4]]) {
    let differing = a
        .iter()
        .zip(b)
        .filter(|(p, q)| {
            (0..4).any(|c| (p[c] - q[c]).abs() > 1e-3 * p[c].abs().max(q[c].abs()) + 1e-6)
        })
        .count();
    assert!(
        differing * 50 <= a.len(),
        "{what}: {differing} of {} pixels differ by more than float rounding",
        a.len()
    );
    for c in 0..4 {
        let d: Vec<f64> = a.iter().zip(b).map(|(p, q)| (p[c] - q[c]) as f64).collect();
        let n = d.len() as f64;
        let mean = d.iter().sum::<f64>() / n;
        let se = (d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
        let level = a.iter().map(|p| p[c] as f64).sum::<f64>() / n;
        assert!(
            mean.abs() <= 4.0 * se + 1e-6 * level && level > 0.0,
            "{what}, channel {c}: difference {mean} ± {se} (level {level})"
        );
    }
    let worst = a
        .iter()
        .zip(b)
        .flat_map(|(p, q)| {
            (0..4).map(move |c| (p[c] - q[c]).abs() / p[c].abs().max(q[c].abs()).max(1e-30))
        })
        .fold(0.0f32, f32::max);
    eprintln!(
        "{what}: {differing} of {} pixels differ beyond rounding; worst relative {worst}",
        a.len()
    );
}

#[test]
fn instances_render_as_copied_geometry() {
    let (instanced, copied) = scenes(&tmp("render"));
    for kind in [IntegratorKind::Path, IntegratorKind::Bdpt] {
        let (a, b) = (image(&instanced, kind), image(&copied, kind));
        agree(kind.name(), &a, &b);
    }
}

#[test]
fn a_forest_of_instances_holds_one_tree() {
    let dir = tmp("forest");
    std::fs::write(dir.join("ball.obj"), ball_obj()).unwrap();
    let mut body = format!(
        "<shape type=\"shapegroup\" id=\"tree\">{}</shape>\n",
        members("", false)
    );
    for i in 0..10_000 {
        let (x, z) = ((i % 100) as f32 * 3.0 - 150.0, -((i / 100) as f32) * 3.0);
        body += &format!(
            "<shape type=\"instance\"><ref id=\"tree\"/><transform name=\"to_world\"><translate x=\"{x}\" z=\"{z}\"/></transform></shape>\n"
        );
    }
    let scene = load(&dir, "forest.xml", &body);
    let tree = 8 * 12 * 2 + 12;
    let info = SceneInfo::of(&scene);
    assert_eq!(scene.geometry.instances().len(), 10_000);
    assert_eq!(scene.geometry.groups().len(), 1);
    // The ball and the cube, once; the rectangles hold no triangles.
    assert_eq!(scene.geometry.stored_triangles(), tree);
    assert_eq!(info.triangles, tree);
    assert_eq!(info.instances, 10_000);
    // Two rectangles of the scene's own and the tree's three shapes: one
    // material each, not one per instance.
    assert_eq!(info.shapes, 5);
    assert_eq!(scene.shape_material.len(), 5);
}

//! What real Mitsuba 3 scenes rely on: file lookup through `<path>` and the
//! scene's folder, top-level emitters referenced from shapes, Mitsuba's
//! integrator wrappers, all errors in one report, `--res` and film crops.

use std::path::{Path, PathBuf};

use scotopia_render::light::Light;
use scotopia_render::scene::{IntegratorKind, Scene};
use scotopia_scene::mitsuba::Parameters;
use scotopia_scene::{load_scene, load_scene_with, LoadOptions, Resolution};

fn tmp(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("scotopia-compat-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

fn write(dir: &Path, name: &str, text: &str) -> PathBuf {
    let p = dir.join(name);
    std::fs::create_dir_all(p.parent().unwrap()).unwrap();
    std::fs::write(&p, text).unwrap();
    p
}

const TRIANGLE: &str = "v 0 0 0\nv 1 0 0\nv 0 1 0\nf 1 2 3\n";
const SENSOR: &str = r#"<sensor type="perspective"><float name="fov" value="40"/>
    <film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="30"/></film>
</sensor>"#;

fn scene(body: &str) -> String {
    format!("<scene version=\"3.0.0\">\n{SENSOR}\n{body}\n</scene>")
}

fn load(path: &Path) -> Scene {
    load_scene(path, &Parameters::new()).unwrap_or_else(|e| panic!("{e}"))
}

#[test]
fn files_are_found_through_path_folders() {
    let d = tmp("path");
    write(&d, "assets/meshes/tri.obj", TRIANGLE);
    let f = write(
        &d,
        "s.xml",
        &scene(
            r#"<path value="assets"/><shape type="obj"><string name="filename" value="meshes/tri.obj"/></shape>"#,
        ),
    );
    assert_eq!(load(&f).geometry.shapes.len(), 1);
    // Without the <path>, the file is not found, and the error names the
    // shape that referred to it, with its line.
    let g = write(
        &d,
        "t.xml",
        &scene(r#"<shape type="obj"><string name="filename" value="meshes/tri.obj"/></shape>"#),
    );
    let e = load_scene(&g, &Parameters::new()).unwrap_err().to_string();
    assert!(
        e.contains("t.xml:5:1: <shape>") && e.contains("tri.obj"),
        "{e}"
    );
    // A <path> that is not a folder is an error.
    let h = write(&d, "u.xml", &scene(r#"<path value="nowhere"/>"#));
    let e = load_scene(&h, &Parameters::new()).unwrap_err().to_string();
    assert!(e.contains("<path>") && e.contains("nowhere"), "{e}");
}

#[test]
fn files_named_in_included_fragments_resolve_from_the_scene() {
    // Mitsuba's Cornell-box layout: the fragment lives in include/, the
    // meshes it names are relative to the scene file.
    let d = tmp("include");
    write(&d, "meshes/tri.obj", TRIANGLE);
    write(
        &d,
        "include/geometry.xml",
        r#"<scene version="3.0.0"><shape type="obj"><string name="filename" value="meshes/tri.obj"/></shape></scene>"#,
    );
    // scotopia's fallback: a fragment naming a file beside itself.
    write(&d, "include/beside.obj", TRIANGLE);
    write(
        &d,
        "include/local.xml",
        r#"<scene version="3.0.0"><shape type="obj"><string name="filename" value="beside.obj"/></shape></scene>"#,
    );
    let f = write(
        &d,
        "s.xml",
        &scene(
            r#"<include filename="include/geometry.xml"/><include filename="include/local.xml"/>"#,
        ),
    );
    assert_eq!(load(&f).geometry.shapes.len(), 2);
}

#[test]
fn every_error_is_reported_in_one_run() {
    let d = tmp("errors");
    let f = write(
        &d,
        "s.xml",
        &scene(
            r#"<shape type="teapot"/>
<bsdf type="velvet" id="a"/>
<shape type="sphere"><ref id="a"/></shape>
<emitter type="nova"/>
<shape type="sphere"><float name="radius" value="-1"/></shape>"#,
        ),
    );
    let e = load_scene(&f, &Parameters::new()).unwrap_err();
    assert_eq!(e.errors.len(), 4, "{e}");
    let text = e.to_string();
    assert!(text.starts_with("4 errors:"), "{text}");
    for needle in ["s.xml:5:1", "s.xml:6:1", "s.xml:8:1", "s.xml:9:1"] {
        assert!(text.contains(needle), "{needle} in {text}");
    }
    // More than the limit: the first 20, and a note.
    let many: String = (0..30).map(|_| "<shape type=\"teapot\"/>\n").collect();
    let g = write(&d, "t.xml", &scene(&many));
    let e = load_scene(&g, &Parameters::new()).unwrap_err();
    assert_eq!(e.errors.len(), 20);
    assert!(e.truncated && e.to_string().contains("stopped after 20"));
}

#[test]
fn a_second_object_with_the_same_id_is_an_error_naming_both() {
    let d = tmp("dup");
    let f = write(
        &d,
        "s.xml",
        &scene("<bsdf type=\"diffuse\" id=\"m\"/>\n<bsdf type=\"conductor\" id=\"m\"/>"),
    );
    let e = load_scene(&f, &Parameters::new()).unwrap_err().to_string();
    assert!(
        e.contains("s.xml:6:1") && e.contains("s.xml:5:1") && e.contains("'m'"),
        "{e}"
    );
}

#[test]
fn area_emitters_can_be_defined_at_the_top_level_and_referenced() {
    let d = tmp("emitref");
    let f = write(
        &d,
        "s.xml",
        &scene(
            r#"<emitter type="area" id="lamp"><rgb name="radiance" value="2, 2, 2"/></emitter>
<bsdf type="diffuse" id="white"/>
<shape type="rectangle"><ref id="white"/><ref id="lamp"/></shape>
<shape type="sphere"><ref id="white"/></shape>"#,
        ),
    );
    let s = load(&f);
    assert_eq!(s.lights.len(), 1);
    assert!(matches!(s.lights[0], Light::Area(_)));
    assert_eq!(s.shape_light, [Some(0), None]);
    assert_eq!(s.shape_material, [0, 0], "one material, shared");
}

#[test]
fn a_constant_emitter_without_radiance_is_mitsubas_unit_d65() {
    let d = tmp("constant");
    let f = write(&d, "s.xml", &scene(r#"<emitter type="constant"/>"#));
    let s = load(&f);
    let Light::Constant(c) = &s.lights[0] else {
        panic!("{:?}", s.lights)
    };
    // Mitsuba 3.9.1's normalised D65 is 1.01013 at 560 nm (ours 0.11 % higher).
    assert!((c.radiance.eval(560.0) - 1.01013).abs() < 2e-3);
}

#[test]
fn mitsuba_integrators_are_read_with_a_note() {
    let d = tmp("integrators");
    let cases = [
        (r#"<integrator type="direct"/>"#, 2, "max_depth 2"),
        (
            r#"<integrator type="aov"><string name="aovs" value="dd.y:depth"/><integrator type="path"><integer name="max_depth" value="3"/></integrator></integrator>"#,
            3,
            "AOV channels are not written",
        ),
        (
            r#"<integrator type="moment"><integrator type="bdpt"><integer name="max_depth" value="7"/></integrator></integrator>"#,
            7,
            "second moment",
        ),
        (
            r#"<integrator type="volpathmis"><integer name="max_depth" value="4"/></integrator>"#,
            4,
            "rendered as volpath",
        ),
    ];
    for (i, (xml, depth, note)) in cases.iter().enumerate() {
        let f = write(&d, &format!("s{i}.xml"), &scene(xml));
        let s = load(&f);
        assert_eq!(s.integrator.max_depth, *depth, "{xml}");
        assert!(
            s.warnings.iter().any(|w| w.contains(note)),
            "{xml}: {:?}",
            s.warnings
        );
    }
    let f = write(
        &d,
        "bdpt.xml",
        &scene(r#"<integrator type="moment"><integrator type="bdpt"/></integrator>"#),
    );
    assert_eq!(load(&f).integrator.kind, IntegratorKind::Bdpt);
    let f = write(&d, "empty.xml", &scene(r#"<integrator type="aov"/>"#));
    let e = load_scene(&f, &Parameters::new()).unwrap_err().to_string();
    assert!(e.contains("holds no nested <integrator>"), "{e}");
}

#[test]
fn media_are_never_ignored_silently() {
    // Under Mitsuba's default integrator (path) the media are left out, and
    // said so once; volpath traces them without a word; a medium type
    // scotopia lacks is a warning of its own.
    let d = tmp("media");
    let media = r#"<medium type="homogeneous" id="fog"/>
<shape type="sphere"><medium type="homogeneous" name="interior"/></shape>"#;
    let f = write(&d, "s.xml", &scene(media));
    let said = |s: &Scene| {
        s.warnings
            .iter()
            .filter(|w| w.contains("media are not rendered"))
            .count()
    };
    assert_eq!(said(&load(&f)), 1, "{:?}", load(&f).warnings);
    let f = write(
        &d,
        "v.xml",
        &scene(&format!(r#"<integrator type="volpath"/>{media}"#)),
    );
    assert_eq!(said(&load(&f)), 0);
    let f = write(
        &d,
        "u.xml",
        &scene(r#"<integrator type="volpath"/><medium type="swirl" id="x"/>"#),
    );
    let s = load(&f);
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("medium 'swirl' is ignored")),
        "{:?}",
        s.warnings
    );
}

#[test]
fn an_unknown_parameter_is_a_warning_naming_the_scenes_parameters() {
    let d = tmp("params");
    let f = write(
        &d,
        "s.xml",
        &format!(
            "<scene version=\"3.0.0\"><default name=\"spp\" value=\"4\"/><default name=\"res\" value=\"8\"/>{SENSOR}</scene>"
        ),
    );
    let mut params = Parameters::new();
    params.insert("sp".into(), "16".into());
    params.insert("res".into(), "16".into());
    let s = load_scene(&f, &params).unwrap();
    let w: Vec<&String> = s
        .warnings
        .iter()
        .filter(|w| w.contains("parameter"))
        .collect();
    assert_eq!(w.len(), 1, "{:?}", s.warnings);
    assert!(
        w[0].contains("'sp'") && w[0].contains("res, spp"),
        "{}",
        w[0]
    );
}

#[test]
fn res_overrides_the_film_keeping_the_field_of_view() {
    let d = tmp("res");
    let f = write(&d, "s.xml", &scene(""));
    let base = load(&f);
    let with = |r: &str| {
        let options = LoadOptions {
            resolution: Some(Resolution::parse(r).unwrap()),
            ..LoadOptions::default()
        };
        load_scene_with(&f, &Parameters::new(), &options).unwrap()
    };
    let wide = with("80");
    assert_eq!(
        (wide.camera.width, wide.camera.height),
        (80, 60),
        "aspect kept"
    );
    let (a, b) = (base.camera.fov_degrees(), wide.camera.fov_degrees());
    assert!((a.0 - b.0).abs() < 1e-4 && (a.1 - b.1).abs() < 1e-4);
    // WxH: the field along fov_axis (x) stays; the vertical one follows.
    let square = with("30x30");
    assert_eq!((square.camera.width, square.camera.height), (30, 30));
    assert!((square.camera.fov_degrees().0 - 40.0).abs() < 1e-4);
    for bad in ["0", "axb", "10x", "99999999"] {
        assert!(Resolution::parse(bad).is_err(), "{bad}");
    }
}

#[test]
fn a_film_crop_renders_a_window_of_the_film() {
    let d = tmp("crop");
    let crop = r#"<sensor type="perspective"><float name="fov" value="40"/>
    <film type="hdrfilm"><integer name="width" value="40"/><integer name="height" value="30"/>
        <integer name="crop_offset_x" value="10"/><integer name="crop_offset_y" value="5"/>
        <integer name="crop_width" value="20"/><integer name="crop_height" value="10"/></film>
</sensor>"#;
    let f = write(
        &d,
        "s.xml",
        &format!("<scene version=\"3.0.0\">{crop}</scene>"),
    );
    let s = load(&f);
    assert_eq!((s.camera.width, s.camera.height), (20, 10));
    assert_eq!(s.camera.full_size(), [40, 30]);
    assert_eq!(s.camera.crop_offset(), [10, 5]);
    assert!(
        s.warnings.iter().all(|w| !w.contains("crop")),
        "{:?}",
        s.warnings
    );
    let options = LoadOptions {
        resolution: Some(Resolution::parse("80").unwrap()),
        ..LoadOptions::default()
    };
    let big = load_scene_with(&f, &Parameters::new(), &options).unwrap();
    assert_eq!(
        (big.camera.width, big.camera.height),
        (40, 20),
        "the crop scales too"
    );
    let g = write(
        &d,
        "t.xml",
        &format!(
            "<scene version=\"3.0.0\">{}</scene>",
            crop.replace("\"20\"", "\"35\"")
        ),
    );
    let e = load_scene(&g, &Parameters::new()).unwrap_err().to_string();
    assert!(e.contains("does not fit the 40×30 film"), "{e}");
}

#[test]
fn a_negative_rgb_index_is_clamped_with_a_warning() {
    // Mitsuba 3.9.1 (scalar_spectral) renders a conductor of eta
    // (−0.2, 0.5, 1.2) exactly as one of (0, 0.5, 1.2).
    let d = tmp("negeta");
    let f = write(
        &d,
        "s.xml",
        &scene(
            r#"<shape type="sphere"><bsdf type="conductor">
    <rgb name="eta" value="-0.2, 0.5, 1.2"/><rgb name="k" value="3, 2.5, 2"/>
</bsdf></shape>"#,
        ),
    );
    let s = load(&f);
    let w: Vec<&String> = s
        .warnings
        .iter()
        .filter(|w| w.contains("negative component"))
        .collect();
    assert_eq!(w.len(), 1, "{:?}", s.warnings);
    assert!(w[0].contains("s.xml:6:5: <rgb>: 'eta'"), "{}", w[0]);
    let zero = write(
        &d,
        "t.xml",
        &std::fs::read_to_string(&f).unwrap().replace("-0.2", "0"),
    );
    assert_eq!(load(&zero).materials, s.materials);
}

#[test]
fn curves_and_sdf_grids_are_skipped_with_a_warning() {
    let d = tmp("skip");
    let f = write(
        &d,
        "s.xml",
        &scene(
            r#"<shape type="bsplinecurve"><string name="filename" value="hair.txt"/></shape>
<shape type="sdfgrid"/>
<shape type="sphere"/>"#,
        ),
    );
    let s = load(&f);
    assert_eq!(s.geometry.shapes.len(), 1);
    let skipped = s.warnings.iter().filter(|w| w.contains("skipped")).count();
    assert_eq!(skipped, 2, "{:?}", s.warnings);
}

#[test]
fn instances_place_the_shapes_of_a_shapegroup() {
    use scotopia_render::geometry::Shape;
    use scotopia_render::math::Vec3;
    let d = tmp("instance");
    let f = write(
        &d,
        "s.xml",
        &scene(
            r#"<shape type="shapegroup" id="pair">
    <shape type="sphere"><point name="center" x="1" y="0" z="0"/><float name="radius" value="0.5"/></shape>
    <shape type="sphere"><transform name="to_world"><scale value="2"/></transform></shape>
</shape>
<shape type="instance"><ref id="pair"/><transform name="to_world"><translate x="0" y="10" z="0"/></transform></shape>
<shape type="instance"><ref id="pair"/><transform name="to_world"><rotate z="1" angle="90"/></transform></shape>"#,
        ),
    );
    let s = load(&f);
    // The group is built once; each instance places it.
    assert!(s.geometry.shapes.is_empty());
    assert_eq!(s.geometry.groups().len(), 1);
    let spheres: Vec<(Vec3, f32)> = s
        .geometry
        .instances()
        .iter()
        .flat_map(|i| {
            let t = *i.world_from_object();
            i.group().shapes().iter().map(move |sh| match sh {
                Shape::Sphere(sp) => (
                    t.point(sp.center),
                    t.vector(Vec3::new(sp.radius, 0.0, 0.0)).length(),
                ),
                other => panic!("{other:?}"),
            })
        })
        .collect();
    let want = [
        (Vec3::new(1.0, 10.0, 0.0), 0.5),
        (Vec3::new(0.0, 10.0, 0.0), 2.0),
        (Vec3::new(0.0, 1.0, 0.0), 0.5),
        (Vec3::new(0.0, 0.0, 0.0), 2.0),
    ];
    assert_eq!(spheres.len(), 4);
    for ((c, r), (wc, wr)) in spheres.iter().zip(want) {
        assert!(
            (*c - wc).length() < 1e-5 && (r - wr).abs() < 1e-5,
            "{c:?} {r}"
        );
    }
    // Each group shape has its material, once for all instances.
    assert_eq!(s.shape_material.len(), 2);
    assert_eq!(s.shape_light, vec![None, None]);
    let g = write(
        &d,
        "t.xml",
        &scene(r#"<bsdf type="diffuse" id="m"/><shape type="instance"><ref id="m"/></shape>"#),
    );
    let e = load_scene(&g, &Parameters::new()).unwrap_err().to_string();
    assert!(e.contains("'m' is a <bsdf>"), "{e}");
    // Mitsuba refuses to instance emitters; so does scotopia, naming the
    // emitter's line.
    let h = write(
        &d,
        "u.xml",
        &scene(
            r#"<shape type="shapegroup" id="lamp">
    <shape type="sphere"><emitter type="area"><rgb name="radiance" value="1"/></emitter></shape>
</shape>
<shape type="instance"><ref id="lamp"/></shape>"#,
        ),
    );
    let e = load_scene(&h, &Parameters::new()).unwrap_err().to_string();
    assert!(
        e.contains("u.xml:6:") && e.contains("cannot hold an emitter"),
        "{e}"
    );
}

#[test]
fn mitsubas_spectrum_plugins() {
    use scotopia_scene::mitsuba::{parse_file, Props, Usage};
    let d = tmp("spectra");
    let f = write(
        &d,
        "s.xml",
        r#"<scene version="3.0.0"><bsdf type="diffuse">
    <spectrum name="reg" type="regular"><float name="wavelength_min" value="400"/><float name="wavelength_max" value="600"/><string name="values" value="0.2, 0.4, 0.8"/></spectrum>
    <spectrum name="irr" type="irregular"><string name="wavelengths" value="400, 450, 700"/><string name="values" value="1, 3, 2"/></spectrum>
    <spectrum name="uni" type="uniform"><float name="value" value="0.7"/></spectrum>
    <spectrum name="band" type="uniform"><float name="value" value="2"/><float name="wavelength_min" value="500"/><float name="wavelength_max" value="600"/></spectrum>
    <spectrum name="raw" type="rawconstant"><float name="value" value="0.3"/></spectrum>
    <spectrum name="rgb" type="srgb"><rgb name="color" value="0.8, 0.1, 0.1"/></spectrum>
    <spectrum name="short" type="irregular"><string name="wavelengths" value="400, 450"/><string name="values" value="1"/></spectrum>
</bsdf></scene>"#,
    );
    let root = parse_file(&f, &Parameters::new()).unwrap();
    let p = Props::new(&root.children[0]);
    let s = |n: &str| p.spectrum(n, Usage::Unbounded).unwrap().unwrap();
    assert!((s("reg").eval(550.0) - 0.6).abs() < 1e-6);
    assert!((s("irr").eval(425.0) - 2.0).abs() < 1e-6);
    assert_eq!(s("uni").eval(700.0), 0.7);
    assert_eq!((s("band").eval(550.0), s("band").eval(450.0)), (2.0, 0.0));
    assert_eq!(s("raw").eval(500.0), 0.3);
    let red = p.spectrum("rgb", Usage::Reflectance).unwrap().unwrap();
    assert!(red.eval(650.0) > 0.5 && red.eval(450.0) < 0.2);
    let e = p
        .spectrum("short", Usage::Unbounded)
        .unwrap_err()
        .to_string();
    assert!(e.contains("2 wavelengths but 1 values"), "{e}");
}

#[test]
fn an_orthographic_sensor_loads_and_bdpt_refuses_it() {
    use scotopia_render::camera::Projection;
    use scotopia_render::integrator::{render, RenderError, RenderOptions};
    let d = tmp("ortho");
    let f = write(
        &d,
        "s.xml",
        r#"<scene version="3.0.0"><sensor type="orthographic">
    <transform name="to_world"><scale x="3" y="3"/><lookat origin="0, 0, 5" target="0, 0, 0" up="0, 1, 0"/></transform>
    <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film>
</sensor><integrator type="bdpt"/><shape type="sphere"/></scene>"#,
    );
    let s = load(&f);
    assert_eq!(s.camera.projection, Projection::Orthographic);
    // The film spans x ∈ [−3, 3] at the camera; the centre ray goes down −z.
    let r = s.camera.generate_ray([4.0, 4.0], [0.5, 0.5]);
    assert!((r.d.z + 1.0).abs() < 1e-6, "{:?}", r.d);
    let edge = s.camera.generate_ray([0.0, 4.0], [0.5, 0.5]);
    assert!((edge.o.x.abs() - 3.0).abs() < 1e-4, "{:?}", edge.o);
    let e = render(
        &s,
        &RenderOptions::default(),
        &Default::default(),
        &|_, _| {},
    );
    assert!(
        matches!(e, Err(RenderError::BdptProjection)),
        "{:?}",
        e.err()
    );
}

#[test]
fn a_spot_light_projects_its_texture_in_its_own_frame() {
    use scotopia_color::SampledWavelengths;
    use scotopia_render::math::Vec3;
    let d = tmp("spot");
    // Black on the left (u < ½), white on the right, read without blending.
    image::RgbImage::from_fn(2, 1, |x, _| image::Rgb([255 * x as u8; 3]))
        .save(d.join("half.png"))
        .unwrap();
    let f = write(
        &d,
        "s.xml",
        &scene(
            r#"<emitter type="spot"><rgb name="intensity" value="5"/>
    <texture name="texture" type="bitmap"><string name="filename" value="half.png"/><string name="filter_type" value="nearest"/></texture>
    <float name="cutoff_angle" value="20"/><float name="beam_width" value="19"/>
    <transform name="to_world"><lookat origin="0, 0, 0" target="0, 0, 1" up="0, 1, 0"/></transform>
</emitter>"#,
        ),
    );
    let s = load(&f);
    assert!(
        s.warnings.iter().all(|w| !w.contains("texture")),
        "{:?}",
        s.warnings
    );
    let Light::Spot(spot) = &s.lights[0] else {
        panic!("{:?}", s.lights)
    };
    let wl = SampledWavelengths::<4>::new([450.0, 520.0, 600.0, 680.0], [1.0; 4]);
    // u = ½ + ½ x / (z tan 20°): x/z = ±0.8 tan 20° reads u = 0.9 and 0.1.
    let x = 0.8 * 20f32.to_radians().tan();
    let at = |sx: f32| {
        spot.sample_li(&wl, Vec3::new(sx * x, 0.0, 1.0))
            .map_or(0.0, |l| l.radiance.average())
    };
    let (right, left) = (at(1.0), at(-1.0));
    assert!(
        right > 1.0 && left < 1e-3 * right,
        "right {right}, left {left}"
    );
    // The unlit half halves the light's power for choosing lights.
    let plain = scotopia_render::light::SpotLight::new(
        Vec3::ZERO,
        Vec3::new(0.0, 0.0, 1.0),
        spot.intensity.clone(),
        20.0,
        19.0,
    );
    let ratio = spot.power().watts / plain.power().watts;
    assert!((ratio - 0.5).abs() < 0.02, "{ratio}");
}

#[test]
fn included_fragments_see_the_including_files_parameters() {
    // Mitsuba's participating-media tests: the scene declares the default,
    // the fragment uses it.
    let d = tmp("inherit");
    write(
        &d,
        "include/integrator.xml",
        r#"<scene version="3.0.0"><default name="bounces" value="9"/>
<integrator type="$integrator"><integer name="max_depth" value="$depth"/><integer name="rr_depth" value="$bounces"/></integrator></scene>"#,
    );
    let f = write(
        &d,
        "s.xml",
        &format!(
            "<scene version=\"3.0.0\"><default name=\"integrator\" value=\"bdpt\"/><default name=\"depth\" value=\"4\"/>{SENSOR}<include filename=\"include/integrator.xml\"/></scene>"
        ),
    );
    let s = load(&f);
    assert_eq!(s.integrator.kind, IntegratorKind::Bdpt);
    assert_eq!((s.integrator.max_depth, s.integrator.rr_depth), (4, 9));
    // And a fragment's defaults reach the including file (Mitsuba's
    // docs scenes declare $res in their included sensor).
    write(
        &d,
        "include/sensor.xml",
        r#"<scene version="3.0.0"><default name="res" value="24"/>
<sensor type="perspective"><film type="hdrfilm"><integer name="width" value="$res"/><integer name="height" value="$res"/></film></sensor></scene>"#,
    );
    let g = write(
        &d,
        "t.xml",
        r#"<scene version="3.0.0"><include filename="include/sensor.xml"/><shape type="sphere"><float name="radius" value="$res"/></shape></scene>"#,
    );
    assert_eq!(load(&g).camera.width, 24);
    // A parameter given on the command line reaches the fragment too.
    let mut params = Parameters::new();
    params.insert("depth".into(), "6".into());
    assert_eq!(load_scene(&f, &params).unwrap().integrator.max_depth, 6);
}

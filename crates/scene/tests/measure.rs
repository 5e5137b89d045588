//! Illuminance at virtual receivers against analytic answers, in the
//! manner of CIE 171:2006's test cases. Tolerances: 4 standard errors of
//! the measurement plus 0.5 % (the CIE's validation criterion is 5 %).

mod common;

use std::sync::atomic::AtomicBool;

use common::assert_close;
use scotopia_render::integrator::{measure, Measured, Receiver, RenderOptions};
use scotopia_render::math::Vec3;
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

fn scene(name: &str, body: &str) -> scotopia_render::scene::Scene {
    let dir = std::env::temp_dir().join(format!("scotopia-measure-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join(format!("{name}.xml"));
    // The sensor is not used by a measurement; the loader wants one.
    let sensor = if body.contains("<sensor") {
        ""
    } else {
        r#"<sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film></sensor>"#
    };
    std::fs::write(
        &f,
        format!(r#"<scene version="3.0.0">{sensor}{body}</scene>"#),
    )
    .unwrap();
    load_scene(&f, &Parameters::new()).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn run(s: &scotopia_render::scene::Scene, rs: &[Receiver], spp: u32) -> Vec<Measured> {
    let options = RenderOptions {
        spp: Some(spp),
        seed: 7,
        ..RenderOptions::default()
    };
    measure(s, rs, &options, &AtomicBool::new(false), &|_, _| {}).unwrap()
}

#[test]
fn a_point_source_over_a_plane_follows_the_inverse_square_and_cosine_laws() {
    // 1000 cd, 3 m above the origin; receivers facing up on the floor.
    let s = scene(
        "point",
        r#"<integrator type="path"><integer name="max_depth" value="2"/></integrator>
        <emitter type="point"><point name="position" x="0" y="3" z="0"/>
          <spectrum name="intensity" type="d65"><float name="luminance" value="1000"/></spectrum></emitter>"#,
    );
    let rs: Vec<Receiver> = [0.0f32, 1.0, 2.5, 4.0]
        .iter()
        .map(|&x| Receiver {
            p: Vec3::new(x, 0.0, 0.0),
            n: Vec3::new(0.0, 1.0, 0.0),
        })
        .collect();
    for (r, m) in rs.iter().zip(run(&s, &rs, 256)) {
        let d2 = (r.p.x * r.p.x + 9.0) as f64;
        let expected = 1000.0 * (3.0 / d2.sqrt()) / d2;
        assert_close(&format!("x = {}", r.p.x), &m, expected);
        // A D65 source: its scotopic/photopic ratio (S/P ≈ 2.47 for D65).
        assert!((m.sp() - 2.47).abs() < 0.05, "S/P {}", m.sp());
    }
}

#[test]
fn a_point_source_inside_a_diffuse_sphere_gives_the_integrating_sphere_illuminance() {
    // Flux Φ = 4πI at the centre of a sphere of radius R and reflectance
    // ρ: the wall receives Φ/(4πR²) directly and ρ/(1 − ρ) times that
    // again by interreflection (the integrating-sphere equation), so
    // E = I / (R² (1 − ρ)) with unlimited depth.
    let (i, r, rho) = (100.0, 2.0, 0.95);
    let s = scene(
        "sphere",
        &format!(
            r#"<integrator type="path"><integer name="max_depth" value="-1"/></integrator>
        <emitter type="point"><point name="position" x="0" y="0" z="0"/>
          <spectrum name="intensity" type="d65"><float name="luminance" value="{i}"/></spectrum></emitter>
        <shape type="sphere"><float name="radius" value="{r}"/><boolean name="flip_normals" value="true"/>
          <bsdf type="twosided"><bsdf type="diffuse"><float name="reflectance" value="{rho}"/></bsdf></bsdf></shape>"#
        ),
    );
    let rs = [
        Receiver {
            p: Vec3::new(0.0, -2.0, 0.0),
            n: Vec3::new(0.0, 1.0, 0.0),
        },
        Receiver {
            p: Vec3::new(2.0, 0.0, 0.0),
            n: Vec3::new(-1.0, 0.0, 0.0),
        },
    ];
    let expected = i / (r * r * (1.0 - rho));
    for m in run(&s, &rs, 4096) {
        assert_close("sphere wall", &m, expected);
    }
}

#[test]
fn a_rectangular_lambertian_source_gives_its_configuration_factor() {
    // A 2 × 2 m source of luminance L facing down, 1 m above a receiver
    // below its centre: E = π L F, with the configuration factor of a
    // receiver below the corner of an a × b rectangle at height c,
    // F = (1/2π)(A/√(1+A²) atan(B/√(1+A²)) + B/√(1+B²) atan(A/√(1+B²))),
    // A = a/c, B = b/c (Howell's catalogue, B-3), times 4 corners.
    let l = 1000.0;
    let s = scene(
        "rectangle",
        &format!(
            r#"<integrator type="path"><integer name="max_depth" value="2"/></integrator>
        <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="90"/><translate y="1"/></transform>
          <emitter type="area"><spectrum name="radiance" type="d65"><float name="luminance" value="{l}"/></spectrum></emitter></shape>"#
        ),
    );
    let rs = [Receiver {
        p: Vec3::ZERO,
        n: Vec3::new(0.0, 1.0, 0.0),
    }];
    let corner = |a: f64, b: f64| {
        let (qa, qb) = ((1.0 + a * a).sqrt(), (1.0 + b * b).sqrt());
        (a / qa * (b / qa).atan() + b / qb * (a / qb).atan()) / (2.0 * std::f64::consts::PI)
    };
    let f = 4.0 * corner(1.0, 1.0);
    let m = run(&s, &rs, 4096)[0];
    assert_close("rectangle", &m, std::f64::consts::PI * l * f);
}

#[test]
fn an_illuminance_render_holds_the_illuminance_of_the_surfaces_seen() {
    // Sunlight of 500 lx straight down on a grey floor seen from above:
    // every pixel holds 500 lx (the floor's reflectance plays no part),
    // and a pixel that sees no surface holds 0.
    use scotopia_render::integrator::{render, Quantity};
    let s = scene(
        "sunlit",
        r#"<integrator type="path"><integer name="max_depth" value="2"/></integrator>
        <emitter type="directional"><vector name="direction" x="0" y="-1" z="0"/>
          <spectrum name="irradiance" type="d65"><float name="luminance" value="500"/></spectrum></emitter>
        <shape type="rectangle"><transform name="to_world"><scale value="0.5"/><rotate x="1" angle="-90"/></transform>
          <bsdf type="diffuse"><float name="reflectance" value="0.3"/></bsdf></shape>
        <sensor type="perspective"><float name="fov" value="40"/>
          <transform name="to_world"><lookat origin="0, 2, 0" target="0, 0, 0" up="0, 0, 1"/></transform>
          <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film></sensor>"#,
    );
    let options = RenderOptions {
        spp: Some(64),
        seed: 1,
        quantity: Quantity::Illuminance,
        ..RenderOptions::default()
    };
    let r = render(&s, &options, &AtomicBool::new(false), &|_, _| {}).unwrap();
    let y: Vec<f32> = r.film.xyzv().iter().map(|p| p[1]).collect();
    let (w, h) = (r.film.width as usize, r.film.height as usize);
    // The centre sees the floor, the corners (beyond its half-metre) the sky.
    let centre = y[h / 2 * w + w / 2] as f64;
    assert!((centre / 500.0 - 1.0).abs() < 0.01, "centre {centre} lx");
    assert_eq!(y[0], 0.0);
}

#[test]
fn a_melanopic_render_holds_the_melanopic_edi_of_the_surfaces_seen() {
    // 500 lx of illuminant A straight down on a floor seen from above:
    // Y holds 500 lx, the fourth channel the melanopic EDI, 500 lx times
    // A's melanopic daylight efficacy ratio (luxpy 1.12.5: 0.657464 /
    // 1.326213 mW/lm), where `illuminance` holds V′ (scotopic lx).
    use scotopia_render::integrator::{render, Quantity};
    let s = scene(
        "sunlit-a",
        r#"<integrator type="path"><integer name="max_depth" value="2"/></integrator>
        <emitter type="directional"><vector name="direction" x="0" y="-1" z="0"/>
          <spectrum name="irradiance" type="A"><float name="luminance" value="500"/></spectrum></emitter>
        <shape type="rectangle"><transform name="to_world"><scale value="0.5"/><rotate x="1" angle="-90"/></transform>
          <bsdf type="diffuse"><float name="reflectance" value="0.3"/></bsdf></shape>
        <sensor type="perspective"><float name="fov" value="20"/>
          <transform name="to_world"><lookat origin="0, 2, 0" target="0, 0, 0" up="0, 0, 1"/></transform>
          <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor>"#,
    );
    let pixels = |quantity| {
        let options = RenderOptions {
            spp: Some(256),
            seed: 1,
            quantity,
            ..RenderOptions::default()
        };
        let r = render(&s, &options, &AtomicBool::new(false), &|_, _| {}).unwrap();
        assert_eq!(r.quantity, quantity);
        r.film.xyzv()
    };
    let (mel, lux) = (
        pixels(Quantity::MelanopicEdi),
        pixels(Quantity::Illuminance),
    );
    let n = mel.len() as f64;
    let mean = |px: &[[f32; 4]], c: usize| px.iter().map(|p| f64::from(p[c])).sum::<f64>() / n;
    // Within 4 standard errors of the pixels' mean, and 0.5 %.
    let close = |c: usize, want: f64| {
        let m = mean(&mel, c);
        let var = mel
            .iter()
            .map(|p| (f64::from(p[c]) - m).powi(2))
            .sum::<f64>()
            / (n - 1.0);
        let tol = 4.0 * (var / n).sqrt() + 5e-3 * want;
        assert!(
            (m - want).abs() <= tol,
            "channel {c}: {m}, expected {want} ± {tol}"
        );
        m
    };
    close(1, 500.0);
    let m = close(3, 500.0 * 0.657464 / 1.326213);
    // Illuminant A is rich in what rods see, poor in what melanopsin does.
    assert!(mean(&lux, 3) > 500.0 && m < 250.0);
}

/// A type C luminaire, bilateral about C0–C180: 1000 cd down, falling
/// off, brighter towards C = 90° than C = 0°.
const IES: &str = "IESNA:LM-63-2002
[TEST] scotopia measure test
TILT=NONE
1 -1 1 5 3 1 2 0 0 0
1 1 100
0 22.5 45 67.5 90
0 90 180
1000 900 600 200 0
1000 950 800 500 100
1000 700 300 100 0
";

#[test]
fn an_ies_distribution_over_a_plane_gives_i_cos_over_d_squared() {
    let dir = std::env::temp_dir().join(format!("scotopia-measure-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("lamp.ies"), IES).unwrap();
    // 4 m up, nadir down (local +z → world −y), C0 along +x, C90 along +z.
    let s = scene(
        "ies",
        r#"<integrator type="path"><integer name="max_depth" value="2"/></integrator>
        <emitter type="ies"><string name="filename" value="lamp.ies"/>
          <transform name="to_world"><rotate x="1" angle="90"/><translate y="4"/></transform></emitter>"#,
    );
    let h = 4.0f32;
    // (γ, C, the file's candela there).
    let cases = [
        (0.0f32, 0.0f32, 1000.0),
        (45.0, 0.0, 600.0),
        (22.5, 90.0, 950.0),
        (45.0, 90.0, 800.0),
        (67.5, 180.0, 100.0),
        (45.0, 270.0, 800.0), // bilateral: C 270° is C 90°'s mirror
    ];
    let rs: Vec<Receiver> = cases
        .iter()
        .map(|&(g, c, _)| {
            let r = h * g.to_radians().tan();
            Receiver {
                p: Vec3::new(r * c.to_radians().cos(), 0.0, r * c.to_radians().sin()),
                n: Vec3::new(0.0, 1.0, 0.0),
            }
        })
        .collect();
    for ((g, c, i), m) in cases.iter().zip(run(&s, &rs, 256)) {
        let cos = g.to_radians().cos() as f64;
        let d2 = (h as f64 / cos).powi(2);
        assert_close(&format!("γ {g}, C {c}"), &m, i * cos / d2);
    }
    // The rendered lamp's flux is the file's.
    let file = scotopia_scene::luminaire::parse_luminaire(IES, "lamp.ies").unwrap();
    let power = s.lights[0].power(&scotopia_render::light::SceneExtent {
        shapes: &[],
        center: Vec3::ZERO,
        radius: 1.0,
        casters: &[],
    });
    let rel = power.lumens / file.total_flux_lm() - 1.0;
    assert!(
        rel.abs() < 2e-3,
        "{} lm vs {} lm",
        power.lumens,
        file.total_flux_lm()
    );
}

#[test]
fn the_bidirectional_tracer_sees_an_ies_lamp_as_the_path_tracer_does() {
    // Light paths start from the lamp's own distribution (its emission
    // sampling); the image mean must agree with the path tracer's. The
    // lamp itself is out of view: light tracing would show the point
    // (a filtered dot), which camera paths can never hit.
    use scotopia_render::integrator::render;
    use scotopia_render::scene::IntegratorKind;
    let dir = std::env::temp_dir().join(format!("scotopia-measure-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join("lamp.ies"), IES).unwrap();
    let s = scene(
        "ies-bdpt",
        r#"<integrator type="path"><integer name="max_depth" value="3"/></integrator>
        <emitter type="ies"><string name="filename" value="lamp.ies"/>
          <transform name="to_world"><rotate x="1" angle="90"/><translate y="2"/></transform></emitter>
        <shape type="rectangle"><transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/></transform>
          <bsdf type="diffuse"><float name="reflectance" value="0.5"/></bsdf></shape>
        <shape type="rectangle"><transform name="to_world"><scale value="3"/><translate z="-2"/></transform>
          <bsdf type="diffuse"><float name="reflectance" value="0.5"/></bsdf></shape>
        <sensor type="perspective"><float name="fov" value="60"/>
          <transform name="to_world"><lookat origin="0, 1.8, 1.5" target="0, 0, 0.5" up="0, 0, -1"/></transform>
          <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="16"/></film></sensor>"#,
    );
    let mean_and_se = |kind: IntegratorKind| {
        let image = |seed: u32| -> Vec<f64> {
            let options = RenderOptions {
                spp: Some(64),
                seed,
                integrator: Some(kind),
                ..RenderOptions::default()
            };
            let r = render(&s, &options, &AtomicBool::new(false), &|_, _| {}).unwrap();
            r.film.xyzv().iter().map(|p| p[1] as f64).collect()
        };
        let (a, b) = (image(1), image(2));
        let n = a.len() as f64;
        let mean = (a.iter().sum::<f64>() + b.iter().sum::<f64>()) / (2.0 * n);
        let var = a.iter().zip(&b).map(|(x, y)| (x - y).powi(2)).sum::<f64>() / (2.0 * n);
        (mean, (var / (2.0 * n)).sqrt())
    };
    let (path, se_p) = mean_and_se(IntegratorKind::Path);
    let (bdpt, se_b) = mean_and_se(IntegratorKind::Bdpt);
    assert!(path > 0.0);
    assert!(
        (path - bdpt).abs() <= 4.0 * (se_p * se_p + se_b * se_b).sqrt() + 1e-3 * path,
        "path {path} ± {se_p}, bdpt {bdpt} ± {se_b}"
    );
}

/// Mitsuba's irradiancemeter on `shape` (its one pixel, as rendered),
/// over `seeds` renders of `spp` each: the mean and its standard error.
fn meter_reading(name: &str, body: &str, spp: u32, seeds: u32) -> (f64, f64) {
    use scotopia_render::integrator::{render, Quantity};
    let s = scene(name, body);
    assert!(s.meter.is_some(), "{name}: no meter");
    assert!(s.warnings.is_empty(), "{name}: {:?}", s.warnings);
    let y: Vec<f64> = (0..seeds)
        .map(|seed| {
            let options = RenderOptions {
                spp: Some(spp),
                seed,
                ..RenderOptions::default()
            };
            let r = render(&s, &options, &AtomicBool::new(false), &|_, _| {}).unwrap();
            assert_eq!((r.film.width, r.film.height), (1, 1));
            assert_eq!(r.quantity, Quantity::Illuminance);
            assert_eq!(r.integrator, scotopia_render::scene::IntegratorKind::Path);
            r.film.xyzv()[0][1] as f64
        })
        .collect();
    let n = y.len() as f64;
    let mean = y.iter().sum::<f64>() / n;
    let var = y.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0);
    (mean, (var / n).sqrt())
}

#[test]
fn an_irradiancemeter_averages_the_illuminance_over_its_shape() {
    // 1000 cd 1 m above the centre of a 2 × 2 m meter facing it. The
    // irradiance I h / (h² + r²)^{3/2} integrates over an a × b rectangle
    // seen from above its corner to I atan(ab / (h √(h² + a² + b²))) (its
    // solid angle): over four 1 × 1 quarters at h = 1, 4 I atan(1/√3) =
    // 4 I π/6, so the mean over the 4 m² is I π/6 = 523.6 lx.
    let (mean, se) = meter_reading(
        "meter",
        r#"<integrator type="path"><integer name="max_depth" value="2"/></integrator>
        <emitter type="point"><point name="position" x="0" y="0" z="1"/>
          <spectrum name="intensity" type="d65"><float name="luminance" value="1000"/></spectrum></emitter>
        <shape type="rectangle"><sensor type="irradiancemeter">
          <film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/></film>
          <sampler type="independent"><integer name="sample_count" value="16"/></sampler></sensor></shape>"#,
        1024,
        8,
    );
    let expected = 1000.0 * std::f64::consts::PI / 6.0;
    assert!(
        (mean - expected).abs() <= 4.0 * se + 5e-3 * expected,
        "{mean} ± {se} lx, expected {expected}"
    );
}

#[test]
fn an_irradiancemeter_on_a_mesh_samples_every_triangle() {
    // A cube (12 triangles) under a uniform sky of luminance L: every face
    // of a convex shape sees a whole hemisphere of it, E = π L.
    let l = 100.0;
    let (mean, se) = meter_reading(
        "meter-cube",
        &format!(
            r#"<integrator type="path"><integer name="max_depth" value="2"/></integrator>
        <emitter type="constant"><spectrum name="radiance" type="d65"><float name="luminance" value="{l}"/></spectrum></emitter>
        <shape type="cube"><sensor type="irradiancemeter">
          <film type="hdrfilm"><integer name="width" value="1"/><integer name="height" value="1"/></film></sensor></shape>"#
        ),
        256,
        8,
    );
    let expected = std::f64::consts::PI * l;
    assert!(
        (mean - expected).abs() <= 4.0 * se + 5e-3 * expected,
        "{mean} ± {se} lx, expected {expected}"
    );
}

#[test]
fn an_irradiancemeter_is_read_as_mitsuba_defines_it() {
    use scotopia_scene::load_scene as load;
    let dir = std::env::temp_dir().join(format!("scotopia-meter-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let write = |name: &str, body: &str| {
        let f = dir.join(name);
        std::fs::write(&f, format!(r#"<scene version="3.0.0">{body}</scene>"#)).unwrap();
        f
    };
    // A larger film is warned about and measured as one pixel.
    let f = write(
        "wide.xml",
        r#"<shape type="rectangle"><sensor type="irradiancemeter">
          <film type="hdrfilm"><integer name="width" value="8"/><integer name="height" value="8"/></film></sensor></shape>"#,
    );
    let s = load(&f, &Parameters::new()).unwrap();
    assert_eq!((s.camera.width, s.camera.height), (1, 1));
    assert!(
        s.warnings.iter().any(|w| w.contains("8×8 film")),
        "{:?}",
        s.warnings
    );
    // Errors name the line: a placement of its own, another sensor type
    // on a shape, a meter at the top level.
    for (name, body, message) in [
        (
            "placed.xml",
            "<shape type=\"rectangle\">\n<sensor type=\"irradiancemeter\"><transform name=\"to_world\"><translate x=\"1\"/></transform></sensor></shape>",
            "has no to_world",
        ),
        (
            "camera-on-shape.xml",
            "<shape type=\"rectangle\">\n<sensor type=\"perspective\"/></shape>",
            "only an 'irradiancemeter'",
        ),
        (
            "top-level.xml",
            "\n<sensor type=\"irradiancemeter\"/>",
            "child of a shape",
        ),
    ] {
        let e = load(&write(name, body), &Parameters::new()).unwrap_err();
        let text = e.to_string();
        assert!(text.contains(message), "{name}: {text}");
        assert!(text.contains(&format!("{name}:2")), "{name}: {text}");
    }
}

#[test]
fn an_ies_lamp_in_a_black_enclosure_delivers_the_files_flux_to_its_walls() {
    // The example street's luminaire (asymmetric, full cut-off) at the
    // centre of a black sphere of radius R: receivers on the wall at the
    // midpoints of 2° × 10° cells in (γ, C), facing the lamp, give
    // Φ = Σ E R² sin γ Δγ ΔC, the flux its walls receive; it must be the
    // file's (CIE 171:2006 checks energy conservation this way).
    let lamp = std::path::Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes/lamps/street-type2.ies")
        .canonicalize()
        .unwrap();
    let r = 5.0f32;
    let s = scene(
        "enclosure",
        &format!(
            r#"<integrator type="path"><integer name="max_depth" value="-1"/></integrator>
        <emitter type="ies"><string name="filename" value="{}"/></emitter>
        <shape type="sphere"><float name="radius" value="{r}"/><boolean name="flip_normals" value="true"/>
          <bsdf type="diffuse"><float name="reflectance" value="0"/></bsdf></shape>"#,
            lamp.display()
        ),
    );
    let (n_gamma, n_c) = (90usize, 36usize);
    let (dg, dc) = (
        std::f64::consts::PI / n_gamma as f64,
        2.0 * std::f64::consts::PI / n_c as f64,
    );
    let mut rs = Vec::new();
    let mut weights = Vec::new();
    for i in 0..n_gamma {
        let g = (i as f64 + 0.5) * dg;
        for j in 0..n_c {
            let c = (j as f64 + 0.5) * dc;
            // Nadir is the emitter's +z, C = 0 its +x.
            let d = Vec3::new(
                (g.sin() * c.cos()) as f32,
                (g.sin() * c.sin()) as f32,
                g.cos() as f32,
            );
            rs.push(Receiver { p: d * r, n: -d });
            weights.push((r * r) as f64 * g.sin() * dg * dc);
        }
    }
    let measured = run(&s, &rs, 8);
    let flux: f64 = measured.iter().zip(&weights).map(|(m, w)| m.e * w).sum();
    let se = measured
        .iter()
        .zip(&weights)
        .map(|(m, w)| (m.e_se * w).powi(2))
        .sum::<f64>()
        .sqrt();
    let file = scotopia_scene::luminaire::read_luminaire(&lamp)
        .unwrap()
        .total_flux_lm();
    assert!(
        (flux - file).abs() <= 4.0 * se + 5e-3 * file,
        "walls receive {flux} ± {se} lm, the file emits {file} lm"
    );
}

#[test]
fn a_lamp_whose_candela_are_all_tiny_is_refused_like_an_all_zero_one() {
    let dir = std::env::temp_dir().join(format!("scotopia-tiny-lamp-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for (name, value) in [("zero", "0"), ("tiny", "1e-40"), ("faint", "1e-20")] {
        let lamp = dir.join(format!("{name}.ies"));
        let values = format!("{value} ").repeat(15);
        std::fs::write(
            &lamp,
            IES.lines().take(7).collect::<Vec<_>>().join("\n") + "\n" + &values + "\n",
        )
        .unwrap();
        let xml = dir.join(format!("{name}.xml"));
        std::fs::write(
            &xml,
            format!(
                r#"<scene version="3.0.0"><sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film></sensor>
<emitter type="ies"><string name="filename" value="{}"/></emitter></scene>"#,
                lamp.display()
            ),
        )
        .unwrap();
        let e = match load_scene(&xml, &Parameters::new()) {
            Ok(_) => panic!("{name}: a {value} cd lamp was accepted"),
            Err(e) => e.to_string(),
        };
        assert!(e.contains("the luminaire emits nothing"), "{name}: {e}");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_street_of_forty_lamps_and_a_sky_give_the_sum_of_their_illuminances() {
    // More lights than the per-point table holds: the light hierarchy
    // chooses among them, and its pmf must be exact for the estimate to
    // be unbiased. 32 point lamps 4 m high every 5 m along x (800 and
    // 300 cd in turn), 8 spots 6 m high aimed straight down (a receiver
    // inside a 25° beam sees its full 2000 cd, one outside the 30° cutoff
    // none) and a uniform sky of 0.05 cd/m² (E = π L facing up).
    let mut body = String::from(
        r#"<integrator type="path"><integer name="max_depth" value="2"/></integrator>
        <emitter type="constant"><spectrum name="radiance" type="d65"><float name="luminance" value="0.05"/></spectrum></emitter>"#,
    );
    let lamp = |x: f64, y: f64, z: f64, cd: f64| (x, y, z, cd);
    let mut lamps = Vec::new();
    for k in 0..32 {
        let l = lamp(5.0 * k as f64 - 60.0, 4.0, 0.0, [800.0, 300.0][k % 2]);
        body += &format!(
            r#"<emitter type="point"><point name="position" x="{}" y="{}" z="{}"/>
            <spectrum name="intensity" type="d65"><float name="luminance" value="{}"/></spectrum></emitter>"#,
            l.0, l.1, l.2, l.3
        );
        lamps.push(l);
    }
    let mut spots = Vec::new();
    for k in 0..8 {
        let l = lamp(10.0 * k as f64 - 35.0, 6.0, 2.0, 2000.0);
        body += &format!(
            r#"<emitter type="spot"><spectrum name="intensity" type="d65"><float name="luminance" value="{}"/></spectrum>
            <float name="cutoff_angle" value="30"/><float name="beam_width" value="25"/>
            <transform name="to_world"><lookat origin="{x}, {y}, {z}" target="{x}, 0, {z}" up="0, 0, 1"/></transform></emitter>"#,
            l.3,
            x = l.0,
            y = l.1,
            z = l.2
        );
        spots.push(l);
    }
    let s = scene("many-lamps", &body);
    let rs: Vec<Receiver> = [-42.0f32, -7.5, 0.0, 13.0, 31.0, 70.0]
        .iter()
        .map(|&x| Receiver {
            p: Vec3::new(x, 0.0, 2.0),
            n: Vec3::new(0.0, 1.0, 0.0),
        })
        .collect();
    for (r, m) in rs.iter().zip(run(&s, &rs, 2048)) {
        let (x, z) = (r.p.x as f64, r.p.z as f64);
        // I cos θ / d² from a lamp straight above the line at height h.
        let from = |&(lx, h, lz, cd): &(f64, f64, f64, f64)| {
            let d2 = (x - lx).powi(2) + h * h + (z - lz).powi(2);
            cd * h / d2.powf(1.5)
        };
        let in_beam = |l: &&(f64, f64, f64, f64)| {
            let off = ((x - l.0).powi(2) + (z - l.2).powi(2)).sqrt();
            (off / l.1).atan() < 25f64.to_radians()
        };
        let expected = std::f64::consts::PI * 0.05
            + lamps.iter().map(from).sum::<f64>()
            + spots.iter().filter(in_beam).map(from).sum::<f64>();
        assert_close(&format!("x = {x}"), &m, expected);
    }
}

#[test]
fn the_alpha_opic_daylight_illuminances_follow_the_lamps_spectrum() {
    // CIE S 026: D65 of E lx has every α-opic equivalent daylight
    // illuminance equal to E; illuminant A has E times its daylight
    // efficacy ratios, ELR_A / ELR_D65 (luxpy 1.12.5, an independent
    // implementation: sc mc lc rh mel, mW/lm).
    let d65 = [0.817289, 1.455826, 1.628907, 1.449703, 1.326213];
    let a = [0.254149, 1.174203, 1.656715, 0.830718, 0.657464];
    for (kind, ratio) in [
        ("d65", [1.0; 5]),
        ("A", std::array::from_fn(|k| a[k] / d65[k])),
    ] {
        let s = scene(
            &format!("aopic-{kind}"),
            &format!(
                r#"<integrator type="path"><integer name="max_depth" value="1"/></integrator>
        <emitter type="point"><point name="position" x="0" y="3" z="0"/>
          <spectrum name="intensity" type="{kind}"><float name="luminance" value="1000"/></spectrum></emitter>"#
            ),
        );
        let r = Receiver {
            p: Vec3::new(0.0, 0.0, 0.0),
            n: Vec3::new(0.0, 1.0, 0.0),
        };
        let m = run(&s, &[r], 512)[0];
        let e = 1000.0 / 9.0;
        assert_close(kind, &m, e);
        for (k, r) in ratio.into_iter().enumerate() {
            let want = e * r;
            let tol = 4.0 * m.edi_se[k] + 5e-3 * want;
            assert!(
                (m.edi[k] - want).abs() <= tol,
                "{kind} {}: {} ± {} lx, expected {want}",
                scotopia_color::alpha_opic::NAMES[k],
                m.edi[k],
                m.edi_se[k]
            );
        }
    }
}

/// [`run`] with receivers of `shape`.
fn run_shaped(
    s: &scotopia_render::scene::Scene,
    rs: &[Receiver],
    shape: scotopia_render::integrator::ReceiverShape,
    spp: u32,
) -> Result<Vec<Measured>, scotopia_render::integrator::RenderError> {
    let options = RenderOptions {
        spp: Some(spp),
        seed: 7,
        ..RenderOptions::default()
    };
    let none = AtomicBool::new(false);
    scotopia_render::integrator::measure_with(s, rs, shape, &options, &none, &|_, _| {})
}

#[test]
fn cylindrical_and_semi_cylindrical_illuminances_are_pi_l_in_a_uniform_field() {
    // EN 12464-1 / EN 13201-2: E_z = E_sc = πL under a uniform sky of
    // luminance L, as for a plane.
    use scotopia_render::integrator::ReceiverShape;
    let s = scene(
        "uniform",
        r#"<integrator type="path"><integer name="max_depth" value="1"/></integrator>
        <emitter type="constant"><spectrum name="radiance" type="d65"><float name="luminance" value="100"/></spectrum></emitter>"#,
    );
    let up = Vec3::new(0.0, 1.0, 0.0);
    let r = [Receiver {
        p: Vec3::new(0.0, 0.0, 0.0),
        n: Vec3::new(1.0, 0.0, 0.0),
    }];
    for shape in [
        ReceiverShape::Plane,
        ReceiverShape::Cylinder { up },
        ReceiverShape::SemiCylinder { up },
    ] {
        let m = run_shaped(&s, &r, shape, 1024).unwrap()[0];
        assert_close(&format!("{shape:?}"), &m, std::f64::consts::PI * 100.0);
    }
}

#[test]
fn a_lamp_lights_a_cylinder_by_sin_theta_and_a_half_cylinder_by_its_facing() {
    // 1000 cd at (4, 3, 0), 5 m from the receiver at the origin, 37° above
    // the horizon: sin θ = 0.8 from the vertical axis. E_z = I sin θ/(π d²);
    // a half-cylinder facing azimuth φ from the lamp gets (1 + cos φ) times
    // that: twice facing it, once across, nothing facing away.
    use scotopia_render::integrator::{ReceiverShape, RenderError};
    let s = scene(
        "lamp-cylinder",
        r#"<integrator type="path"><integer name="max_depth" value="1"/></integrator>
        <emitter type="point"><point name="position" x="4" y="3" z="0"/>
          <spectrum name="intensity" type="d65"><float name="luminance" value="1000"/></spectrum></emitter>"#,
    );
    let up = Vec3::new(0.0, 1.0, 0.0);
    let at = |x, z| Receiver {
        p: Vec3::new(0.0, 0.0, 0.0),
        n: Vec3::new(x, 0.3, z),
    };
    let ez = 1000.0 * 0.8 / (std::f64::consts::PI * 25.0);
    let m = run_shaped(&s, &[at(1.0, 0.0)], ReceiverShape::Cylinder { up }, 2048).unwrap();
    assert_close("cylinder", &m[0], ez);
    let facings = [at(1.0, 0.0), at(0.0, 1.0), at(-1.0, 0.0)];
    let m = run_shaped(&s, &facings, ReceiverShape::SemiCylinder { up }, 2048).unwrap();
    assert_close("facing the lamp", &m[0], 2.0 * ez);
    assert_close("across", &m[1], ez);
    assert_eq!(m[2].e, 0.0, "facing away");
    // A half-cylinder cannot face along its axis; an axis must be one.
    let e = run_shaped(&s, &[at(0.0, 0.0)], ReceiverShape::SemiCylinder { up }, 4);
    assert!(matches!(e, Err(RenderError::Facing(0))), "{e:?}");
    let zero = ReceiverShape::Cylinder {
        up: Vec3::new(0.0, 0.0, 0.0),
    };
    assert!(matches!(
        run_shaped(&s, &facings, zero, 4),
        Err(RenderError::Axis)
    ));
}

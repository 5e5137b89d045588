//! The fisheye sensor (`render/src/camera/fisheye.rs`): it sees what a
//! perspective camera sees in the same directions, both tracers agree
//! through it (the bidirectional tracer's light paths reach it by its
//! importance), and a picture of a uniform sky gives E_v = πL.

mod common;

use std::sync::atomic::AtomicBool;

use common::{agree, inline};
use scotopia_render::camera::Projection;
use scotopia_render::integrator::{render, BdptStrategy, RenderOptions};
use scotopia_render::math::Vec3;
use scotopia_render::scene::{IntegratorKind, Scene};

/// A sensor looking along +z from (0, 1, 0) over a grey floor (y = 0,
/// reflectance 0.5) under a uniform sky, with a bright square facing it
/// up and to the left of its axis, and a small lamp over the floor.
fn world(sensor: &str, size: u32) -> String {
    format!(
        r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="6"/></integrator>
    {sensor}
        <transform name="to_world"><lookat origin="0, 1, 0" target="0, 1, 1" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
        <film type="hdrfilm"><integer name="width" value="{size}"/><integer name="height" value="{size}"/><rfilter type="box"/></film>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="0.2, 0.2, 0.2"/></emitter>
    <shape type="rectangle">
        <transform name="to_world"><scale value="0.4"/><rotate y="1" angle="180"/><translate x="0.5" y="1.3" z="2"/></transform>
        <emitter type="area"><rgb name="radiance" value="3, 3, 3"/></emitter>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="0.1"/><rotate x="1" angle="90"/><translate x="-0.5" y="0.6" z="0.8"/></transform>
        <emitter type="area"><rgb name="radiance" value="40, 40, 40"/></emitter>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="50"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.5, 0.5"/></bsdf>
    </shape>
</scene>"#
    )
}

fn fisheye(projection: &str, fov: u32) -> String {
    format!(
        r#"<sensor type="fisheye"><string name="projection" value="{projection}"/><float name="fov" value="{fov}"/>"#
    )
}

fn image(s: &Scene, spp: u32, seed: u32, integrator: Option<IntegratorKind>) -> Vec<[f32; 4]> {
    let o = RenderOptions {
        spp: Some(spp),
        seed,
        integrator,
        ..RenderOptions::default()
    };
    render(s, &o, &AtomicBool::new(false), &|_, _| {})
        .unwrap()
        .film
        .xyzv()
}

/// The direction a pixel's centre looks in, from the sensor itself.
fn centre_direction(s: &Scene, x: u32, y: u32) -> Vec3 {
    s.camera
        .generate_ray([x as f32 + 0.5, y as f32 + 0.5], [0.5, 0.5])
        .d
}

#[test]
fn a_fisheye_sees_the_luminance_a_perspective_camera_sees_in_the_same_direction() {
    let persp = inline(
        "fisheye-persp",
        &world(
            r#"<sensor type="perspective"><float name="fov" value="110"/>"#,
            96,
        ),
    );
    let p = image(&persp, 64, 1, None);
    for (projection, fov) in [("angular", 180), ("equisolid", 200)] {
        let eye = inline("fisheye-eye", &world(&fisheye(projection, fov), 96));
        assert_eq!(
            eye.camera.projection,
            Projection::Fisheye(
                scotopia_render::camera::FisheyeMap::from_name(projection).unwrap()
            )
        );
        let f = image(&eye, 64, 2, None);
        // Pixels of each that look into the same few degrees: compared
        // where the luminance is smooth (the square's face, the sky, the
        // floor), by the mean over the pixels whose centres fall within
        // 4° of directions spread over the perspective view.
        let near = |s: &Scene, size: u32, img: &[[f32; 4]], d: Vec3| {
            let (mut sum, mut sq, mut n) = (0.0f64, 0.0f64, 0.0f64);
            for y in 0..size {
                for x in 0..size {
                    let c = centre_direction(s, x, y);
                    if s.camera.sees([x as f32 + 0.5, y as f32 + 0.5])
                        && c.dot(d) > 4f32.to_radians().cos()
                    {
                        let v = f64::from(img[(y * size + x) as usize][1]);
                        sum += v;
                        sq += v * v;
                        n += 1.0;
                    }
                }
            }
            let mean = sum / n;
            (
                mean,
                ((sq / n - mean * mean).max(0.0) / (n - 1.0)).sqrt(),
                n,
            )
        };
        let checks = [
            ("square", Vec3::new(0.5, 0.3, 2.0)),
            ("sky", Vec3::new(-0.3, 0.6, 1.0)),
            ("floor", Vec3::new(0.2, -0.6, 1.0)),
            ("floor by the lamp", Vec3::new(-0.4, -0.8, 1.0)),
        ];
        for (what, d) in checks {
            let d = d.normalize();
            let (a, sa, na) = near(&persp, 96, &p, d);
            let (b, sb, nb) = near(&eye, 96, &f, d);
            eprintln!("{projection} {fov}°, {what}: perspective {a:.3} ± {sa:.3} ({na} px), fisheye {b:.3} ± {sb:.3} ({nb} px)");
            assert!(na >= 4.0 && nb >= 4.0, "{what}: too few pixels");
            // Within their standard errors, and the slope of the light
            // across two windows that are not the same shape (1 %).
            let tol = 4.0 * (sa * sa + sb * sb).sqrt() + 0.01 * a;
            assert!(
                (a - b).abs() <= tol,
                "{projection}, {what}: {a} against {b} (± {tol})"
            );
        }
    }
}

#[test]
fn path_and_bidirectional_tracers_agree_through_a_fisheye() {
    // 220°: the field looks behind the sensor's plane, where a
    // perspective camera cannot; the bidirectional tracer's light paths
    // reach the film by the fisheye's importance.
    for (projection, fov) in [("angular", 220), ("equisolid", 180)] {
        let s = inline("fisheye-bdpt", &world(&fisheye(projection, fov), 24));
        let path = image(&s, 512, 1, Some(IntegratorKind::Path));
        let bdpt = image(&s, 256, 2, Some(IntegratorKind::Bdpt));
        agree(
            &format!("{projection} {fov}°, bdpt against path"),
            &bdpt,
            &path,
        );
    }
}

#[test]
fn pixels_outside_the_circle_are_black_in_both_tracers() {
    let s = inline("fisheye-rim", &world(&fisheye("angular", 180), 16));
    for kind in [IntegratorKind::Path, IntegratorKind::Bdpt] {
        let img = image(&s, 16, 3, Some(kind));
        // The corners lie outside the circle.
        for (x, y) in [(0usize, 0usize), (15, 0), (0, 15), (15, 15)] {
            assert_eq!(img[y * 16 + x], [0.0; 4], "{kind:?} ({x}, {y})");
        }
    }
}

#[test]
fn a_fisheye_is_refused_a_crop_window_and_a_bad_field() {
    let crop = world(&fisheye("angular", 180), 16).replace(
        r#"<rfilter type="box"/>"#,
        r#"<integer name="crop_width" value="8"/><integer name="crop_height" value="8"/><rfilter type="box"/>"#,
    );
    for (name, xml, says) in [
        ("crop", crop, "no crop window"),
        ("fov", world(&fisheye("angular", 400), 16), "(0°, 360°]"),
        (
            "projection",
            world(&fisheye("stereographic", 180), 16),
            "angular or equisolid",
        ),
    ] {
        let file = std::env::temp_dir().join(format!(
            "scotopia-fisheye-{name}-{}.xml",
            std::process::id()
        ));
        std::fs::write(&file, xml).unwrap();
        let err = scotopia_scene::load_scene(&file, &scotopia_scene::mitsuba::Parameters::new())
            .unwrap_err()
            .to_string();
        let _ = std::fs::remove_file(&file);
        assert!(err.contains(says), "{name}: {err}");
    }
}

#[test]
fn light_tracing_reaches_a_fisheye_by_its_importance() {
    // Paths of two segments (the floor lit by the two lamps), built by
    // light tracing alone (s = 2, t = 1: the fisheye's importance) and by
    // next-event estimation alone (1, 2: its rays), unweighted.
    let sky = r#"<emitter type="constant"><rgb name="radiance" value="0.2, 0.2, 0.2"/></emitter>"#;
    for (projection, fov) in [("angular", 220), ("equisolid", 180)] {
        let xml = world(&fisheye(projection, fov), 24).replace(sky, "");
        let s = inline("fisheye-importance", &xml);
        let only = |st: (usize, usize), seed| {
            let o = RenderOptions {
                spp: Some(1024),
                seed,
                integrator: Some(IntegratorKind::Bdpt),
                only_strategy: Some(BdptStrategy::new(st.0, st.1).unwrap()),
                ..RenderOptions::default()
            };
            render(&s, &o, &AtomicBool::new(false), &|_, _| {})
                .unwrap()
                .film
                .xyzv()
        };
        agree(
            &format!("{projection} {fov}°, light tracing against next-event estimation"),
            &only((2, 1), 1),
            &only((1, 2), 2),
        );
    }
}

//! The bidirectional tracer through participating media (issue 25)
//! against the volume path tracer, on small fog scenes: a grey fog box
//! with null boundaries under an area light, a camera inside fog with a
//! spot light (the beam in fog), and a fog whose σ_t varies with
//! wavelength (the cluster collapses). Each comparison is of independent
//! renders: per channel, the pixel mean of their difference is zero within
//! 4 standard errors (from the spread of the pixel differences), and the
//! strategies alone converge to the path tracer's paths of their length.

mod common;

use std::sync::atomic::AtomicBool;

use common::agree;
use scotopia_render::integrator::{render, BdptStrategy, RenderOptions};
use scotopia_render::scene::{IntegratorKind, Scene};
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

fn scene(name: &str, body: &str) -> Scene {
    let dir = std::env::temp_dir().join(format!("scotopia-bdpt-media-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join(format!("{name}.xml"));
    std::fs::write(&f, format!(r#"<scene version="3.0.0">{body}</scene>"#)).unwrap();
    load_scene(&f, &Parameters::new()).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn image(scene: &Scene, options: RenderOptions) -> Vec<[f32; 4]> {
    rendered(scene, options).0
}

/// The image and the fraction of samples whose cluster collapsed.
fn rendered(scene: &Scene, options: RenderOptions) -> (Vec<[f32; 4]>, f64) {
    let r = render(scene, &options, &AtomicBool::new(false), &|_, _| {}).unwrap();
    (r.film.xyzv(), r.collapsed_fraction())
}

fn options(integrator: IntegratorKind, spp: u32, seed: u32) -> RenderOptions {
    RenderOptions {
        spp: Some(spp),
        seed,
        integrator: Some(integrator),
        ..RenderOptions::default()
    }
}

/// A 24 × 18 camera at `origin` looking at (0, 0.8, 0), with `inside`
/// (a medium reference for a camera in fog, or nothing). A box filter:
/// light tracing splats no light from beyond the film's edges, which a
/// wider filter gives the border pixels of the path tracer's image.
fn sensor(origin: &str, inside: &str) -> String {
    format!(
        r#"<sensor type="perspective">{inside}<float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="{origin}" target="0, 0.8, 0" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="24"/><integer name="height" value="18"/>
        <rfilter type="box"/></film></sensor>"#
    )
}

const FLOOR: &str = r#"<shape type="rectangle"><bsdf type="diffuse"/>
    <transform name="to_world"><scale value="4"/><rotate x="1" angle="-90"/></transform></shape>"#;

/// A fog box (null boundaries) of extinction `sigma_t` floating just over a
/// floor (not touching it: coplanar faces would be hit in either order),
/// lit by a small area light above it, seen from outside, paths of
/// at most `depth` segments.
fn fog_box(name: &str, sigma_t: &str, depth: i32) -> Scene {
    scene(
        name,
        &format!(
            r#"<integrator type="volpath"><integer name="max_depth" value="{depth}"/></integrator>
            {sensor}
            <medium type="{kind}" id="fog">{sigma_t}
              <spectrum name="albedo" value="400:0.9, 700:0.6"/>
              <phase type="hg"><float name="g" value="0.3"/></phase></medium>
            <shape type="cube"><bsdf type="null"/><ref name="interior" id="fog"/>
              <transform name="to_world"><scale x="1" y="0.8" z="1"/><translate y="0.85"/></transform></shape>
            <shape type="rectangle">
              <transform name="to_world"><scale value="0.25"/><rotate x="1" angle="90"/><translate y="2.2"/></transform>
              <emitter type="area"><spectrum name="radiance" value="400:40, 700:40"/></emitter></shape>
            {FLOOR}"#,
            sensor = sensor("0, 1, 4.5", ""),
            kind = if sigma_t.contains("volume") {
                "heterogeneous"
            } else {
                "homogeneous"
            },
        ),
    )
}

const GREY: &str = r#"<float name="sigma_t" value="1.2"/>"#;
/// The grey σ_t of a heterogeneous medium (tracked, not drawn in closed
/// form).
const TRACKED: &str =
    r#"<volume type="constvolume" name="sigma_t"><float name="value" value="1.2"/></volume>"#;
/// σ_t falling fourfold from 400 to 700 nm (haze).
const CHROMATIC: &str = r#"<spectrum name="sigma_t" value="400:2.0, 700:0.5"/>"#;

/// The camera and a spot light inside unbounded fog (the sensor's
/// medium): the beam in fog, over a floor.
fn beam(depth: i32) -> Scene {
    beam_with("beam", depth, 0.5, "")
}

/// [`beam`] with the phase function's mean cosine `g` and `shapes` added,
/// written as `name`.
fn beam_with(name: &str, depth: i32, g: f32, shapes: &str) -> Scene {
    scene(
        name,
        &format!(
            r#"<integrator type="volpath"><integer name="max_depth" value="{depth}"/></integrator>
            {sensor}
            <medium type="homogeneous" id="fog"><float name="sigma_t" value="0.4"/>
              <float name="albedo" value="0.8"/><phase type="hg"><float name="g" value="{g}"/></phase></medium>
            <emitter type="spot"><spectrum name="intensity" value="400:30, 700:30"/>
              <float name="cutoff_angle" value="20"/><float name="beam_width" value="15"/>
              <transform name="to_world"><lookat origin="-1, 2.5, 0" target="0.3, 0, 0" up="0, 1, 0"/></transform></emitter>
            {shapes}{FLOOR}"#,
            sensor = sensor("0, 1, 4", r#"<ref id="fog"/>"#),
        ),
    )
}

#[test]
fn bdpt_and_volpath_agree_on_a_grey_fog_box_under_an_area_light() {
    let s = fog_box("grey", GREY, 8);
    let (b, collapsed) = rendered(&s, options(IntegratorKind::Bdpt, 128, 1));
    // Grey σ_t keeps the whole cluster (the albedo varies).
    assert_eq!(collapsed, 0.0);
    agree(
        "grey fog box",
        &b,
        &image(&s, options(IntegratorKind::Path, 512, 2)),
    );
}

#[test]
fn bdpt_and_volpath_agree_on_a_heterogeneous_fog_box() {
    // The same fog as a heterogeneous medium: delta tracking draws the
    // flights and ratio tracking attenuates the connections.
    let s = fog_box("tracked", TRACKED, 8);
    agree(
        "heterogeneous fog box",
        &image(&s, options(IntegratorKind::Bdpt, 128, 50)),
        &image(&s, options(IntegratorKind::Path, 512, 51)),
    );
}

#[test]
fn bdpt_and_volpath_agree_on_a_spot_beam_seen_from_inside_the_fog() {
    let s = beam(8);
    agree(
        "beam in fog",
        &image(&s, options(IntegratorKind::Bdpt, 512, 3)),
        &image(&s, options(IntegratorKind::Path, 2048, 4)),
    );
}

/// A rough aluminium post beside the spot light of [`beam_with`], in
/// the fog: a lamp-lit reflector, which the volume path tracer's bounces
/// in the fog aim at (`reflectors::MEDIUM_SHARE`); the bidirectional
/// tracer knows nothing of it.
const POST: &str = r#"<shape type="cube">
    <transform name="to_world"><scale x="0.06" y="0.6" z="0.06"/><translate x="-0.55" y="1.1" z="0"/></transform>
    <bsdf type="roughconductor"><string name="material" value="Al"/><float name="alpha" value="0.2"/></bsdf></shape>"#;

#[test]
fn bdpt_and_volpath_agree_on_fog_lit_by_a_lamp_lit_post() {
    let s = beam_with("beam-post", 8, 0.7, POST);
    agree(
        "beam and post in fog",
        &image(&s, options(IntegratorKind::Bdpt, 512, 5)),
        &image(&s, options(IntegratorKind::Path, 2048, 6)),
    );
}

#[test]
fn bdpt_and_volpath_agree_with_the_camera_in_a_fog_box_and_a_point_light_outside() {
    // The light's medium is found by walking from the lens to it: out of
    // the box, so vacuum; were it given the camera's fog, light tracing
    // would darken by e^{−0.5 · 0.75} on the light's way to the box.
    let s = scene(
        "inside",
        &format!(
            r#"<integrator type="volpath"><integer name="max_depth" value="6"/></integrator>
            {sensor}
            <medium type="homogeneous" id="fog"><float name="sigma_t" value="0.5"/>
              <float name="albedo" value="0.8"/><phase type="isotropic"/></medium>
            <shape type="cube"><bsdf type="null"/><ref name="interior" id="fog"/>
              <transform name="to_world"><scale x="2" y="1.2" z="2"/><translate y="1.25"/></transform></shape>
            <emitter type="point"><point name="position" x="0.3" y="3.2" z="0"/>
              <spectrum name="intensity" value="400:20, 700:20"/></emitter>
            {FLOOR}"#,
            sensor = sensor("0, 1, 1.8", r#"<ref id="fog"/>"#),
        ),
    );
    agree(
        "camera in a fog box, point light outside",
        &image(&s, options(IntegratorKind::Bdpt, 1024, 40)),
        &image(&s, options(IntegratorKind::Path, 4096, 41)),
    );
}

#[test]
fn bdpt_and_volpath_agree_on_a_chromatic_fog_box() {
    // The bidirectional tracer collapses the cluster in the fog; the
    // path tracer keeps it, with its spectral MIS: independent answers.
    // Both subpaths collapse in most samples: counting their factor K
    // twice in the connections fails this (checked).
    let s = fog_box("chromatic", CHROMATIC, 8);
    let (b, collapsed) = rendered(&s, options(IntegratorKind::Bdpt, 128, 5));
    eprintln!(
        "chromatic fog box: {:.1} % of samples collapsed",
        100.0 * collapsed
    );
    assert!(collapsed > 0.1, "{collapsed}");
    agree(
        "chromatic fog box",
        &b,
        &image(&s, options(IntegratorKind::Path, 512, 6)),
    );
}

/// The path tracer's image of paths of exactly `depth` segments: its
/// depth `depth` image minus its depth `depth − 1` image.
fn paths_of_length(at: impl Fn(i32) -> Scene, depth: i32, spp: u32) -> Vec<[f32; 4]> {
    let a = image(&at(depth), options(IntegratorKind::Path, spp, 7));
    let b = image(&at(depth - 1), options(IntegratorKind::Path, spp, 8));
    a.iter()
        .zip(&b)
        .map(|(p, q)| std::array::from_fn(|c| p[c] - q[c]))
        .collect()
}

#[test]
fn every_strategy_alone_converges_through_the_fog_box() {
    // Paths of exactly 2 segments (one scattering, in the fog or on the
    // floor, between lens and light), against each strategy that builds
    // them, unweighted.
    let at = |d: i32| fog_box("strategies", GREY, d);
    let reference = paths_of_length(at, 2, 1024);
    let two = at(2);
    for (s, t) in [(0, 3), (1, 2), (2, 1)] {
        let o = RenderOptions {
            only_strategy: Some(BdptStrategy::new(s, t).unwrap()),
            ..options(IntegratorKind::Bdpt, 1024, 10 + s as u32)
        };
        agree(
            &format!("fog box, strategy ({s}, {t})"),
            &image(&two, o),
            &reference,
        );
    }
}

#[test]
fn every_strategy_alone_converges_in_the_beam() {
    // Paths of 2 segments from a camera in fog lit by a spot (a delta
    // light: s = 0 cannot build them).
    let reference = paths_of_length(beam, 2, 1024);
    let two = beam(2);
    for (s, t) in [(1, 2), (2, 1)] {
        let o = RenderOptions {
            only_strategy: Some(BdptStrategy::new(s, t).unwrap()),
            ..options(IntegratorKind::Bdpt, 1024, 20 + s as u32)
        };
        agree(
            &format!("beam, strategy ({s}, {t})"),
            &image(&two, o),
            &reference,
        );
    }
}

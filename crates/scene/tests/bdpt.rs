//! The bidirectional tracer against the path tracer and against itself:
//! each strategy (s, t) alone converges to the same image as the others
//! and as the path tracer's paths of that length, and with MIS it
//! converges to the path tracer's image on the bundled scenes. Each
//! comparison is of two independent renders: per channel, the mean over
//! pixels of their difference is zero within 4 standard errors (from the
//! spread of the pixel differences).

mod common;

use std::sync::atomic::AtomicBool;

use common::{agree, inline, scene};
use scotopia_render::integrator::{render, BdptStrategy, Quantity, RenderOptions};
use scotopia_render::math::Vec3;
use scotopia_render::scene::{IntegratorKind, Scene};
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

fn image(scene: &Scene, options: RenderOptions) -> Vec<[f32; 4]> {
    let r = render(scene, &options, &AtomicBool::new(false), &|_, _| {}).unwrap();
    r.film.xyzv()
}

fn bdpt(spp: u32, seed: u32) -> RenderOptions {
    RenderOptions {
        spp: Some(spp),
        seed,
        integrator: Some(IntegratorKind::Bdpt),
        ..RenderOptions::default()
    }
}

fn path(spp: u32, seed: u32) -> RenderOptions {
    RenderOptions {
        integrator: Some(IntegratorKind::Path),
        ..bdpt(spp, seed)
    }
}

/// The Cornell box at `res`² with max depth `depth`, and the path
/// tracer's image of its paths of exactly `depth` segments: its depth
/// `depth` image minus its depth `depth − 1` image, `spp` samples each.
fn paths_of_length(res: &str, depth: i32, spp: u32) -> (Scene, Vec<[f32; 4]>) {
    let at = |d: i32| {
        scene(
            "cornell-box.xml",
            &[("res", res), ("max_depth", &d.to_string())],
        )
    };
    let (long, short) = (at(depth), at(depth - 1));
    let a = image(&long, path(spp, 1));
    let b = image(&short, path(spp, 2));
    let reference = a
        .iter()
        .zip(&b)
        .map(|(p, q)| std::array::from_fn(|c| p[c] - q[c]))
        .collect();
    (long, reference)
}

#[test]
fn every_strategy_alone_converges_to_the_same_image() {
    // Paths of exactly 3 segments in the Cornell box, against each of the
    // four strategies that build such paths, unweighted.
    let (three, reference) = paths_of_length("12", 3, 4096);
    for (s, t) in [(0, 4), (1, 3), (2, 2), (3, 1)] {
        let options = RenderOptions {
            only_strategy: Some(BdptStrategy::new(s, t).unwrap()),
            ..bdpt(8192, 10 + s as u32)
        };
        agree(
            &format!("strategy ({s}, {t})"),
            &image(&three, options),
            &reference,
        );
    }
}

#[test]
fn bidirectional_and_path_tracing_agree_on_the_bundled_scenes() {
    let small = [("width", "24"), ("height", "16")];
    let cases: [(&str, &[(&str, &str)]); 7] = [
        ("cornell-box.xml", &[("res", "16")]),
        ("glass-and-metals.xml", &small),
        ("material-showcase.xml", &small),
        ("night-street.xml", &small),
        ("prism.xml", &small),
        ("black-light-poster.xml", &small),
        ("paper.xml", &small),
    ];
    for (name, params) in cases {
        let s = scene(name, params);
        agree(name, &image(&s, bdpt(256, 1)), &image(&s, path(256, 2)));
    }
}

/// Per pixel, the squared difference between the two tracers exceeds the
/// sum of their noises only by twice the squared bias: with two renders
/// of each, d = (B₁−P₁)² + (B₂−P₂)² − (B₁−B₂)² − (P₁−P₂)² has expectation
/// 2·bias² (the noise terms cancel). Weighted by 1/scale² per pixel (from
/// a fifth, independent render, so the weights do not correlate with the
/// noise), so that a few bright pixels do not decide it, its pixel mean
/// must be zero within 4 standard errors.
fn rmse_is_the_noise(what: &str, b: [&[[f32; 4]]; 2], p: [&[[f32; 4]]; 2], scale: &[[f32; 4]]) {
    let n = scale.len();
    let nf = n as f64;
    for c in 0..4 {
        let floor = scale.iter().map(|v| v[c] as f64).sum::<f64>() / nf;
        let sq = |x: &[[f32; 4]], y: &[[f32; 4]], i: usize| {
            ((x[i][c] - y[i][c]) as f64 / (scale[i][c] as f64).max(floor)).powi(2)
        };
        let d: Vec<f64> = (0..n)
            .map(|i| sq(b[0], p[0], i) + sq(b[1], p[1], i) - sq(b[0], b[1], i) - sq(p[0], p[1], i))
            .collect();
        let mean = d.iter().sum::<f64>() / nf;
        let se = (d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (nf - 1.0) / nf).sqrt();
        let mse = |x: &[[f32; 4]], y: &[[f32; 4]]| (0..n).map(|i| sq(x, y, i)).sum::<f64>() / nf;
        let between = ((mse(b[0], p[0]) + mse(b[1], p[1])) / 2.0).sqrt();
        let noise = ((mse(b[0], b[1]) + mse(p[0], p[1])) / 2.0).sqrt();
        assert!(
            mean <= 4.0 * se && noise > 0.0,
            "{what}, channel {c}: relative RMSE between the tracers {between}, their noise \
             {noise}; excess 2·bias² = {mean} ± {se}"
        );
    }
}

#[test]
fn per_pixel_the_tracers_differ_only_by_their_noise() {
    // Pixel by pixel rather than in the mean, so that a bias which moves
    // light within the image (a wrong camera importance, a misplaced
    // splat) is caught too. Only scenes whose every path the path tracer
    // can sample: in the material showcase it cannot sample the sun's
    // caustics under the glass and gold spheres (a delta light through a
    // specular bounce), in the prism scene (practically) the spectrum on
    // the wall, so there the bidirectional image is the right one and the
    // two differ by more than their noise (docs/bdpt.md).
    let small = [("width", "16"), ("height", "12")];
    type Case<'a> = (&'a str, &'a [(&'a str, &'a str)], u32);
    // The glass ball's caustics: the path tracer finds them by manifold
    // next-event estimation, weighed against its BSDF sampling; the
    // bidirectional tracer by light tracing.
    let cases: [Case; 4] = [
        ("cornell-box.xml", &[("res", "12")], 2048),
        ("glass-and-metals.xml", &small, 4096),
        ("night-street.xml", &small, 4096),
        ("black-light-poster.xml", &small, 4096),
    ];
    for (name, params, spp) in cases {
        let s = scene(name, params);
        let b = [image(&s, bdpt(spp, 1)), image(&s, bdpt(spp, 3))];
        let p = [image(&s, path(spp, 2)), image(&s, path(spp, 4))];
        let scale = image(&s, path(128, 5));
        rmse_is_the_noise(name, [&b[0], &b[1]], [&p[0], &p[1]], &scale);
    }
}

#[test]
fn light_tracing_alone_matches_direct_lighting() {
    // Strategy (2, 1) (a light vertex, one surface vertex, the lens) is
    // the direct lighting of every visible surface, splatted: the path
    // tracer's depth-2 image minus its depth-1 image. Many samples, so
    // that an error of a few percent in the camera importance shows.
    let (two, reference) = paths_of_length("8", 2, 8192);
    let options = RenderOptions {
        only_strategy: Some(BdptStrategy::new(2, 1).unwrap()),
        ..bdpt(32768, 3)
    };
    agree("strategy (2, 1)", &image(&two, options), &reference);
}

#[test]
fn bdpt_is_chosen_in_the_scene_file_and_bad_strategies_are_errors() {
    let s = scene("cornell-box.xml", &[("res", "8")]);
    assert_eq!(s.integrator.kind, IntegratorKind::Path);
    let bad = |[ls, lt]: [usize; 2], integrator| {
        let o = RenderOptions {
            spp: Some(1),
            only_strategy: Some(BdptStrategy::new(ls, lt).unwrap()),
            integrator: Some(integrator),
            ..RenderOptions::default()
        };
        render(&s, &o, &AtomicBool::new(false), &|_, _| {}).is_err()
    };
    // Strategies that do not exist cannot be made at all.
    assert!(BdptStrategy::new(1, 0).is_err());
    assert!(BdptStrategy::new(0, 1).is_err());
    assert!(bad([1, 1], IntegratorKind::Path));
    assert!(!bad([1, 1], IntegratorKind::Bdpt));
}

#[test]
fn a_projector_renders_alike_in_both_tracers_and_lights_its_plane_as_mitsuba() {
    // A projector 2 m in front of a white diffuse wall, its texture black
    // on the left half and white on the right; the camera beside it.
    let dir = std::env::temp_dir().join(format!("scotopia-projector-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    image::RgbImage::from_fn(2, 1, |x, _| image::Rgb([255 * x as u8; 3]))
        .save(dir.join("half.png"))
        .unwrap();
    let xml = r#"<scene version="3.0.0">
    <sensor type="perspective"><float name="fov" value="60"/>
        <transform name="to_world"><lookat origin="0.3, 0, 0" target="0.3, 0, 2" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="12"/><integer name="height" value="12"/></film></sensor>
    <integrator type="path"><integer name="max_depth" value="2"/></integrator>
    <emitter type="projector"><float name="fov" value="40"/><float name="scale" value="3"/>
        <texture type="bitmap" name="irradiance"><string name="filename" value="half.png"/><string name="filter_type" value="nearest"/></texture>
        <transform name="to_world"><lookat origin="0, 0, 0" target="0, 0, 1" up="0, 1, 0"/></transform></emitter>
    <shape type="rectangle"><bsdf type="diffuse"><rgb name="reflectance" value="0.8"/></bsdf>
        <transform name="to_world"><scale value="3"/><rotate y="1" angle="180"/><translate z="2"/></transform></shape>
</scene>"#;
    std::fs::write(dir.join("p.xml"), xml).unwrap();
    let s = load_scene(&dir.join("p.xml"), &Parameters::new()).unwrap();
    let Some(scotopia_render::light::Light::Projector(p)) = s.lights.first() else {
        panic!("{:?}", s.lights)
    };
    // Irradiance on a surface facing the projector one unit along a ray
    // is π·scale·E(uv) (Mitsuba's projector.cpp): E here is the white
    // texel's illuminant spectrum, 1 luminance-weighted on average.
    let wl = scotopia_color::SampledWavelengths::<4>::new([450.0, 520.0, 600.0, 680.0], [1.0; 4]);
    let white = p.irradiance.eval(&wl, [0.75, 0.5]);
    for x in [0.05f32, 0.2] {
        let at = Vec3::new(-x, 0.0, 1.0);
        let l = p.sample_li(&wl, at).unwrap();
        let cos = l.wi.dot(Vec3::new(0.0, 0.0, -1.0));
        let e = l.radiance * cos;
        for i in 0..4 {
            let want = std::f32::consts::PI * 3.0 * white[i];
            assert!(
                (e[i] / want - 1.0).abs() < 1e-4,
                "x {x}: {} vs {want}",
                e[i]
            );
        }
        // The left half of the image (+x in camera space) is black.
        assert!(p.sample_li(&wl, Vec3::new(x, 0.0, 1.0)).is_none());
    }
    agree(
        "projector",
        &image(&s, bdpt(64, 1)),
        &image(&s, path(64, 2)),
    );
}

/// Relative mean squared difference of two renders per pixel, channel `c`,
/// each pixel scaled by an independent render (as in `rmse_is_the_noise`).
fn relative_mse(a: &[[f32; 4]], b: &[[f32; 4]], scale: &[[f32; 4]], c: usize) -> f64 {
    let n = scale.len() as f64;
    let floor = scale.iter().map(|v| v[c] as f64).sum::<f64>() / n;
    a.iter()
        .zip(b)
        .zip(scale)
        .map(|((p, q), s)| ((p[c] - q[c]) as f64 / (s[c] as f64).max(floor)).powi(2))
        .sum::<f64>()
        / n
}

#[test]
fn aiming_light_paths_at_casters_keeps_the_image_and_lowers_its_noise() {
    // The showcase's sun and sky start light subpaths on a disk; aimed
    // partly at the glass and gold balls (`light::emit_disk`), the
    // caustics they cast (seen on the floor and in the copper and plastic
    // balls) are found far more often. Per pixel the image must not move
    // beyond the noise, and the noise must drop.
    let aimed = scene(
        "material-showcase.xml",
        &[("width", "32"), ("height", "18")],
    );
    let mut uniform = aimed.clone();
    uniform.integrator.aim_at_casters = false;
    let spp = 256;
    let a = [image(&aimed, bdpt(spp, 1)), image(&aimed, bdpt(spp, 3))];
    let u = [image(&uniform, bdpt(spp, 2)), image(&uniform, bdpt(spp, 4))];
    let scale = image(&aimed, bdpt(spp, 5));
    rmse_is_the_noise(
        "showcase, aimed against uniform light subpaths",
        [&a[0], &a[1]],
        [&u[0], &u[1]],
        &scale,
    );
    let (noise_aimed, noise_uniform) = (
        relative_mse(&a[0], &a[1], &scale, 1),
        relative_mse(&u[0], &u[1], &scale, 1),
    );
    eprintln!("relative MSE of Y: aimed {noise_aimed}, uniform {noise_uniform}");
    assert!(
        noise_aimed < 0.9 * noise_uniform,
        "aimed {noise_aimed}, uniform {noise_uniform}"
    );
}

/// A floor and a wall under 24 small sphere lamps of two spectra, above
/// the camera and out of its view: more lights than the
/// per-point table holds, so next-event estimation (s = 1 in the
/// bidirectional tracer) chooses by the light hierarchy while the light
/// subpaths choose by the cluster.
fn many_lamps() -> Scene {
    let mut lamps = String::new();
    for k in 0..24 {
        let (x, z) = ((k % 6) as f32 * 1.6 - 4.0, (k / 6) as f32 * 1.5 - 3.0);
        // Four bright warm lamps high up and twenty dim ones low down: by
        // power the light subpaths mostly start at the bright ones, while
        // next-event estimation at the floor picks the dim ones near it.
        let (y, spectrum) = if k % 6 == 0 {
            (3.0, r#"<blackbody name="radiance" temperature="2700"/><float name="scale" value="40"/>"#.to_string())
        } else {
            (
                0.4 + 0.1 * (k % 4) as f32,
                format!(
                    r#"<spectrum name="radiance" type="d65"><float name="luminance" value="{}"/></spectrum>"#,
                    20 + 10 * (k % 5)
                ),
            )
        };
        lamps += &format!(
            r#"<shape type="sphere"><point name="center" x="{x}" y="{y}" z="{z}"/><float name="radius" value="0.08"/>
            <emitter type="area">{spectrum}</emitter></shape>"#
        );
    }
    let xml = format!(
        r#"<scene version="3.0.0">
        <integrator type="path"><integer name="max_depth" value="4"/></integrator>
        <sensor type="perspective"><float name="fov" value="40"/>
          <transform name="to_world"><lookat origin="0, 0.3, 6" target="0, 0, 4" up="0, 1, 0"/></transform>
          <film type="hdrfilm"><integer name="width" value="16"/><integer name="height" value="12"/></film></sensor>
        <shape type="rectangle"><transform name="to_world"><rotate x="1" angle="-90"/><scale value="8"/></transform>
          <bsdf type="diffuse"><rgb name="reflectance" value="0.5, 0.45, 0.4"/></bsdf></shape>
        <shape type="rectangle"><transform name="to_world"><scale value="8"/><translate z="-5"/></transform>
          <bsdf type="roughconductor"><string name="material" value="Al"/><float name="alpha" value="0.3"/></bsdf></shape>
        {lamps}</scene>"#
    );
    let dir = std::env::temp_dir().join(format!("scotopia-bdpt-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join("many-lamps.xml");
    std::fs::write(&f, xml).unwrap();
    let s = load_scene(&f, &Parameters::new()).unwrap();
    assert!(s.lights.len() > 16);
    s
}

#[test]
fn with_many_lights_the_tracers_differ_only_by_their_noise() {
    let s = many_lamps();
    let b = [image(&s, bdpt(2048, 1)), image(&s, bdpt(2048, 3))];
    let p = [image(&s, path(2048, 2)), image(&s, path(2048, 4))];
    agree("many lamps", &b[0], &p[0]);
    let scale = image(&s, path(128, 5));
    rmse_is_the_noise("many lamps", [&b[0], &b[1]], [&p[0], &p[1]], &scale);
}

/// A glass ball on a white floor under a small lamp, seen close up from
/// the side: the caustic under it and the lamp's reflection in it fill
/// most of the image.
const LENS: &str = r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="6"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="24"/>
        <transform name="to_world">
            <lookat origin="0.1, 0.7, 1.6" target="0.05, 0.08, 0.05" up="0, 1, 0"/>
        </transform>
        <film type="hdrfilm">
            <integer name="width" value="16"/><integer name="height" value="12"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><scale value="2"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.8"/></bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" x="0" y="0.25" z="0"/>
        <float name="radius" value="0.25"/>
        <bsdf type="dielectric"><float name="int_ior" value="1.5"/></bsdf>
    </shape>
    <shape type="rectangle">
        <transform name="to_world">
            <scale value="0.08"/><rotate x="1" angle="90"/><translate x="-0.3" y="1.6" z="-0.3"/>
        </transform>
        <emitter type="area"><rgb name="radiance" value="100"/></emitter>
    </shape>
</scene>"#;

#[test]
fn through_a_glass_ball_the_tracers_differ_only_by_their_noise() {
    // The path tracer reaches the caustic mostly by manifold next-event
    // estimation through the ball, weighed against BSDF sampling; the
    // bidirectional tracer by light tracing. A weight that counted a path
    // twice, or a wrong Jacobian, shows here first.
    let s = inline("lens", LENS);
    let b = [image(&s, bdpt(8192, 1)), image(&s, bdpt(8192, 3))];
    let p = [image(&s, path(8192, 2)), image(&s, path(8192, 4))];
    let scale = image(&s, path(128, 5));
    agree("glass ball", &b[0], &p[0]);
    // And over the pixels bright with the caustic and the lamp's images
    // (chosen from a fifth, independent render), where the two
    // strategies' shares meet: a path the weights miss, or count twice,
    // moves these by 20-40 %.
    let mut ys: Vec<f32> = scale.iter().map(|v| v[1]).collect();
    ys.sort_by(f32::total_cmp);
    let bright: Vec<usize> = (0..scale.len())
        .filter(|&i| scale[i][1] > 4.0 * ys[ys.len() / 2])
        .collect();
    assert!(bright.len() >= 6, "{} bright pixels", bright.len());
    let pick = |img: &[[f32; 4]]| bright.iter().map(|&i| img[i]).collect::<Vec<_>>();
    agree("glass ball, bright pixels", &pick(&b[0]), &pick(&p[0]));
    rmse_is_the_noise("glass ball", [&b[0], &b[1]], [&p[0], &p[1]], &scale);
}

/// The caustic on a white floor (the ball lifted 25 cm), seen by a
/// perspective and by an orthographic camera away from the ball: per pixel
/// the path tracer's radiance is ρ/π times the illuminance its receivers
/// measure at the same points. The radiance reaches the caustic by light
/// tracing (`manifold::seen`) and joins weighed against the estimator;
/// the receivers by the estimator and BSDF sampling alone. An orthographic
/// camera's rays meet no point a light path can be joined to: splatted as
/// through a lens, its caustic came out wrong.
#[test]
fn the_caustics_radiance_on_a_white_floor_is_its_illuminance_times_rho_over_pi() {
    let look = r#"<transform name="to_world">
            <lookat origin="0.6, 0.3, 0.6" target="0.14, 0, 0.14" up="0, 1, 0"/>
        </transform>"#;
    let film = r#"<film type="hdrfilm">
            <integer name="width" value="12"/><integer name="height" value="12"/>
            <rfilter type="box"/>
        </film>"#;
    let perspective = format!(
        r#"<sensor type="perspective"><float name="fov" value="12"/>{look}{film}</sensor>"#
    );
    let scaled = look.replace("<lookat", "<scale value=\"0.08\"/><lookat");
    let orthographic = format!(r#"<sensor type="orthographic">{scaled}{film}</sensor>"#);
    let sensors = [("perspective", perspective), ("orthographic", orthographic)];
    let start = LENS.find("<sensor").unwrap();
    let end = LENS.find("</sensor>").unwrap() + "</sensor>".len();
    for (i, (what, sensor)) in sensors.iter().enumerate() {
        let text = format!("{}{sensor}{}", &LENS[..start], &LENS[end..])
            .replacen(
                r#"<rgb name="reflectance" value="0.8"/>"#,
                r#"<float name="reflectance" value="0.8"/>"#,
                1,
            )
            .replace(r#"y="0.25" z="0"/>"#, r#"y="0.5" z="0"/>"#);
        let s = inline(&format!("caustic-floor-{i}"), &text);
        let radiance = image(&s, path(4096, 1));
        let lux = image(
            &s,
            RenderOptions {
                quantity: Quantity::Illuminance,
                ..path(4096, 2)
            },
        );
        let rho_over_pi = 0.8 / std::f32::consts::PI;
        // Y only: the receivers measure illuminance (Y) and its scotopic V.
        let pick = |img: &[[f32; 4]], k: f32| -> Vec<[f32; 4]> {
            img.iter().map(|v| [v[1] * k; 4]).collect()
        };
        let level = lux.iter().map(|v| v[1]).sum::<f32>() / lux.len() as f32;
        assert!(level > 1.0, "{what}: illuminance {level}");
        agree(what, &pick(&radiance, 1.0), &pick(&lux, rho_over_pi));
    }
}

/// [`LENS`] with its floor black but for a white square of half-width
/// `half` at (`x`, `z`), with `more` shapes and each of `edits` made.
fn lens_lit_by_its_caustic(
    name: &str,
    (half, x, z): (f32, f32, f32),
    more: &str,
    edits: &[(&str, &str)],
) -> Scene {
    let square = format!(
        r#"<shape type="rectangle">
        <transform name="to_world">
            <scale value="{half}"/><rotate x="1" angle="-90"/><translate x="{x}" y="0.001" z="{z}"/>
        </transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.8"/></bsdf>
    </shape>
    {more}
    <sensor"#
    );
    let black = r#"<rgb name="reflectance" value="0"/>"#;
    let mut text = LENS
        .replacen(r#"<rgb name="reflectance" value="0.8"/>"#, black, 1)
        .replacen("<sensor", &square, 1);
    for (from, to) in edits {
        text = text.replace(from, to);
    }
    inline(name, &text)
}

/// The two tracers, twice each at 4096 spp, agree on `s` in the mean and
/// per pixel.
fn tracers_agree_on(what: &str, s: &Scene) {
    let b = [image(s, bdpt(4096, 1)), image(s, bdpt(4096, 3))];
    let p = [image(s, path(4096, 2)), image(s, path(4096, 4))];
    let scale = image(s, path(128, 5));
    agree(what, &b[0], &p[0]);
    rmse_is_the_noise(what, [&b[0], &b[1]], [&p[0], &p[1]], &scale);
}

/// The ball lifted 25 cm, a white square where its caustic falls, and a
/// white wall before it that a black shade keeps from the lamp (but not
/// the ball), seen from beside: the wall is lit mostly by the caustic.
/// The path tracer reaches that light three ways, weighed against each
/// other: its bounce at the wall landing in the caustic and the estimator
/// there, the same and BSDF sampling through the ball, and light
/// subpaths traced through the ball to the square and joined to the
/// wall's points (`manifold::connect`).
///
/// The join carries most of the wall's light: without its density in the
/// estimator's weight (the light counted twice) the path tracer came out
/// 28 % brighter (−338 ± 24 of 1 226); without the joins, half as bright.
#[test]
fn the_caustic_lights_a_wall_alike_in_both_tracers() {
    let wall_and_shade = r#"<shape type="rectangle">
        <transform name="to_world"><scale value="1"/><rotate y="1" angle="180"/><translate z="0.6"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.8"/></bsdf>
    </shape>
    <shape type="rectangle">
        <transform name="to_world">
            <scale x="1" y="0.4"/><rotate x="1" angle="90"/><translate y="1.2" z="0.3"/>
        </transform>
        <bsdf type="diffuse"><float name="reflectance" value="0"/></bsdf>
    </shape>"#;
    let edits = [
        (r#"y="0.25" z="0"/>"#, r#"y="0.5" z="0"/>"#),
        ("0.1, 0.7, 1.6", "0.9, 0.35, -0.3"),
        ("0.05, 0.08, 0.05", "-0.2, 0.25, 0.6"),
    ];
    let s = lens_lit_by_its_caustic("caustic-wall", (0.06, 0.14, 0.14), wall_and_shade, &edits);
    tracers_agree_on("wall lit by a caustic", &s);
}

/// A white square where the caustic falls and a white ceiling above the
/// lamp (which lights only downwards), seen from below: the ceiling sees
/// the caustic only through the ball or reflected off it (paths of 7
/// segments: the depth is 8). The path tracer joins its light subpaths to
/// the ceiling by way of the ball (`manifold::connect::THROUGH`), weighed
/// against its bounce through the ball into the caustic and the estimator
/// or BSDF sampling there.
///
/// Both ways of counting matter here: without the joins' density in the
/// weights of the path that reaches the caustic through the ball, the
/// path tracer came out 16 % too bright (−515 ± 41 of 3 153); without the
/// joins by way of the ball, 21 % too dark.
#[test]
fn the_caustic_through_a_ball_lights_a_ceiling_alike_in_both_tracers() {
    let ceiling = r#"<shape type="rectangle">
        <transform name="to_world"><scale value="2"/><rotate x="1" angle="90"/><translate y="2"/></transform>
        <bsdf type="diffuse"><rgb name="reflectance" value="0.8"/></bsdf>
    </shape>"#;
    let edits = [
        (
            r#"name="max_depth" value="6""#,
            r#"name="max_depth" value="8""#,
        ),
        ("0.1, 0.7, 1.6", "0.3, 0.8, 0.8"),
        ("0.05, 0.08, 0.05", "-0.3, 2.0, -0.3"),
    ];
    let s = lens_lit_by_its_caustic("caustic-ceiling", (0.05, 0.1, 0.06), ceiling, &edits);
    tracers_agree_on("ceiling lit through a ball", &s);
}

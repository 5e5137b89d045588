//! The wavefront tracer gives the scalar tracer's image bit for bit: every
//! bundled scene (dispersion and its cluster collapse, fluorescence,
//! textures, every light kind the scenes use), cluster sizes 1, 4 and 8,
//! the three wavelength strategies, spectral bands, and on 1 and 2 threads.

use std::path::Path;
use std::sync::atomic::AtomicBool;

use scotopia_render::integrator::{render, ClusterSize, RenderOptions, Rendered, Tracer};
use scotopia_render::wavelength::WavelengthStrategy;
use scotopia_scene::mitsuba::Parameters;
use scotopia_scene::{load_scene_with, LoadOptions, Resolution};

fn scene(name: &str) -> scotopia_render::scene::Scene {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name);
    let load = LoadOptions {
        resolution: Some(Resolution::parse("20").unwrap()),
        ..LoadOptions::default()
    };
    load_scene_with(&path, &Parameters::new(), &load).unwrap()
}

fn run(scene: &scotopia_render::scene::Scene, o: &RenderOptions, threads: usize) -> Rendered {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap()
        .install(|| render(scene, o, &AtomicBool::new(false), &|_, _| {}).unwrap())
}

fn same(a: &Rendered, b: &Rendered, what: &str) {
    // (Not assert_eq: the films' Debug text would flood the report.)
    assert!(a.film == b.film, "{what}: films differ");
    assert_eq!(
        (a.spp, a.nonfinite, a.rays, a.collapsed),
        (b.spp, b.nonfinite, b.rays, b.collapsed),
        "{what}: counts differ"
    );
}

#[test]
fn every_bundled_scene_renders_the_scalar_tracers_image() {
    for name in [
        "cornell-box.xml",
        "prism.xml",
        "diamond.xml",
        "black-light-poster.xml",
        "paper.xml",
        "material-showcase.xml",
        "night-street.xml",
        "lamp-shade.xml",
        "caustic-sphere.xml",
    ] {
        let s = scene(name);
        for (cluster, strategy) in [
            (ClusterSize::K4, WavelengthStrategy::Swc),
            (ClusterSize::K1, WavelengthStrategy::Swc),
            (ClusterSize::K8, WavelengthStrategy::Hero),
            (ClusterSize::K4, WavelengthStrategy::Single),
        ] {
            let o = RenderOptions {
                spp: Some(3),
                seed: 7,
                cluster,
                strategy,
                bands: Some(5),
                integrator: Some(scotopia_render::scene::IntegratorKind::Path),
                tracer: Tracer::Wavefront,
                ..RenderOptions::default()
            };
            let scalar = run(
                &s,
                &RenderOptions {
                    tracer: Tracer::Scalar,
                    ..o.clone()
                },
                1,
            );
            let what = format!("{name}, K = {cluster}, {strategy:?}");
            assert!(scalar.rays > 0, "{what}");
            same(&run(&s, &o, 1), &scalar, &format!("{what}, 1 thread"));
            same(&run(&s, &o, 2), &scalar, &format!("{what}, 2 threads"));
        }
    }
}

/// What the wavefront tracer does not run (media, the bidirectional
/// tracer, illuminance) is an error naming it, never a quiet hand-over to
/// the scalar tracer; a lone bidirectional strategy asked of the path
/// tracer is an error too.
#[test]
fn unsupported_combinations_are_errors_that_say_so() {
    use scotopia_render::integrator::{BdptStrategy, Quantity, RenderError};
    use scotopia_render::scene::IntegratorKind;
    let wavefront = RenderOptions {
        spp: Some(1),
        tracer: Tracer::Wavefront,
        ..RenderOptions::default()
    };
    let cases = [
        ("foggy-street.xml", wavefront.clone(), "participating media"),
        (
            "cornell-box.xml",
            RenderOptions {
                integrator: Some(IntegratorKind::Bdpt),
                ..wavefront.clone()
            },
            "bidirectional",
        ),
        (
            "cornell-box.xml",
            RenderOptions {
                quantity: Quantity::Illuminance,
                ..wavefront.clone()
            },
            "illuminance",
        ),
    ];
    for (name, o, words) in cases {
        let e = render(&scene(name), &o, &AtomicBool::new(false), &|_, _| {}).unwrap_err();
        assert!(matches!(e, RenderError::Wavefront(_)), "{name}: {e}");
        let text = e.to_string();
        assert!(
            text.contains(words) && text.contains("scalar"),
            "{name}: {text}"
        );
    }
    let path_alone = RenderOptions {
        spp: Some(1),
        integrator: Some(IntegratorKind::Path),
        only_strategy: Some(BdptStrategy::new(1, 1).unwrap()),
        ..RenderOptions::default()
    };
    let e = render(
        &scene("cornell-box.xml"),
        &path_alone,
        &AtomicBool::new(false),
        &|_, _| {},
    );
    let e = e.unwrap_err();
    assert_eq!(e, RenderError::Strategy(BdptStrategy::new(1, 1).unwrap()));
    assert_eq!(e.to_string(), "strategy s=1, t=1 needs --integrator bdpt");
}

//! A render stopped part-way and resumed from its checkpoint ends
//! bit-identical to the uninterrupted render: path and bidirectional
//! tracing (whose light-tracing splats are added at pass ends), with
//! spectral bands, the checkpoint written to disk and read back.

use std::path::Path;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::Duration;

use scotopia_render::film::Checkpoint;
use scotopia_render::integrator::{
    render, render_with, Checkpointing, Hooks, Observer, RenderOptions, RunFacts,
};
use scotopia_render::scene::IntegratorKind;
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

fn options(integrator: IntegratorKind) -> RenderOptions {
    RenderOptions {
        spp: Some(40),
        seed: 3,
        bands: Some(8),
        integrator: Some(integrator),
        ..RenderOptions::default()
    }
}

#[test]
fn a_resumed_render_is_bit_identical_to_an_uninterrupted_one() {
    let mut params = Parameters::new();
    params.insert("res".into(), "12".into());
    let scene = load_scene(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.xml"),
        &params,
    )
    .unwrap();
    let file = std::env::temp_dir().join(format!("scotopia-resume-{}.ckpt", std::process::id()));
    for integrator in [IntegratorKind::Path, IntegratorKind::Bdpt] {
        let opts = options(integrator);
        let whole = render(&scene, &opts, &AtomicBool::new(false), &|_, _| {}).unwrap();

        // Stopped after 11 spp (mid-pass: Ctrl-C lands between passes, so
        // it stops at the next boundary, 16), saving every pass.
        let cancel = AtomicBool::new(false);
        let saves = Mutex::new(0u32);
        let save = |c: &Checkpoint| {
            *saves.lock().unwrap() += 1;
            c.write(&file)
        };
        let stop = |done: u32, _: u32| {
            if done >= 11 {
                cancel.store(true, Ordering::Relaxed);
            }
        };
        let first = render_with(
            &scene,
            &opts,
            Hooks {
                progress: Some(&stop),
                checkpoints: Some(Checkpointing {
                    key: 42,
                    resume: None,
                    every: Duration::ZERO,
                    save: &save,
                }),
                ..Hooks::new(&cancel)
            },
        )
        .unwrap();
        assert!(
            first.cancelled && first.spp == 16,
            "{integrator:?}: {}",
            first.spp
        );
        assert!(*saves.lock().unwrap() >= 2);

        let saved = Checkpoint::read(&file).unwrap();
        assert_eq!(saved.done, 16);
        let resumed = render_with(
            &scene,
            &opts,
            Hooks {
                checkpoints: Some(Checkpointing {
                    key: 42,
                    resume: Some(saved.clone()),
                    every: Duration::from_secs(3600),
                    save: &|_| Ok(()),
                }),
                ..Hooks::new(&AtomicBool::new(false))
            },
        )
        .unwrap();
        assert_eq!(resumed.spp, 40);
        assert!(
            resumed.film == whole.film,
            "{integrator:?}: the resumed film differs from the uninterrupted one"
        );
        assert_eq!(
            (resumed.rays, resumed.nonfinite),
            (whole.rays, whole.nonfinite)
        );

        // Another scene or options: refused.
        let e = render_with(
            &scene,
            &opts,
            Hooks {
                checkpoints: Some(Checkpointing {
                    key: 43,
                    resume: Some(saved),
                    every: Duration::ZERO,
                    save: &|_| Ok(()),
                }),
                ..Hooks::new(&AtomicBool::new(false))
            },
        )
        .unwrap_err();
        assert!(e.to_string().contains("another scene"), "{e}");
    }
    let _ = std::fs::remove_file(&file);
}

#[test]
fn an_observer_sees_the_film_grow_and_its_last_look_is_the_result() {
    let mut params = Parameters::new();
    params.insert("res".into(), "8".into());
    let scene = load_scene(
        &Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.xml"),
        &params,
    )
    .unwrap();
    let opts = RenderOptions {
        spp: Some(40),
        ..RenderOptions::default()
    };
    let seen = Mutex::new(Vec::new());
    let see = |film: &scotopia_render::film::Film, facts: &RunFacts| {
        seen.lock().unwrap().push((facts.spp, film.xyzv()));
    };
    let observer = Observer {
        every: Duration::ZERO,
        see: &see,
    };
    let cancel = AtomicBool::new(false);
    let hooks = Hooks {
        observer: Some(observer),
        ..Hooks::new(&cancel)
    };
    let rendered = render_with(&scene, &opts, hooks).unwrap();
    let seen = seen.into_inner().unwrap();
    // Every pass boundary (1, 2, 4, 8, 16, 32 spp) and the end (40).
    let spps: Vec<u32> = seen.iter().map(|(s, _)| *s).collect();
    assert_eq!(spps, [1, 2, 4, 8, 16, 32, 40]);
    assert_eq!(seen.last().unwrap().1, rendered.film.xyzv());
    assert_ne!(seen[0].1, rendered.film.xyzv());
}

//! Path guiding (`--guiding on`): it changes the noise, not the image
//! (guided and unguided renders agree within standard errors, in clear
//! air and in fog); it lowers the noise where bounces must find a small
//! bright patch; and it is exact in the ways renders must be: the same on
//! any number of threads, resumed from a checkpoint, and split into
//! shards of rows.

mod common;

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;
use std::time::Duration;

use common::{agree, inline, scene};
use scotopia_render::film::{Checkpoint, Film};
use scotopia_render::integrator::{
    render, render_with, Checkpointing, Guiding, Hooks, Quantity, RenderError, RenderOptions,
    Shard, Tracer,
};
use scotopia_render::scene::Scene;

fn options(spp: u32, seed: u32, guiding: Guiding) -> RenderOptions {
    RenderOptions {
        spp: Some(spp),
        seed,
        guiding,
        ..RenderOptions::default()
    }
}

fn film(scene: &Scene, options: &RenderOptions) -> Film {
    render(scene, options, &AtomicBool::new(false), &|_, _| {})
        .unwrap()
        .film
}

/// A floor that sees no lamp: a spot light 50 cm under a high ceiling
/// shines up in a 30° cone, so the floor is lit only by the bright disc
/// of ceiling it lights, 4 m up. A cosine-sampled bounce from the floor
/// seldom finds it; the guide learns where it is.
const HIDDEN_LAMP: &str = r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="3"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="40"/>
        <transform name="to_world"><lookat origin="0, 1.5, 2" target="0, 0, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
        <film type="hdrfilm">
            <integer name="width" value="96"/><integer name="height" value="72"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><scale value="0.6"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><float name="reflectance" value="0.5"/></bsdf>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="4"/><rotate x="1" angle="90"/><translate y="4"/></transform>
        <bsdf type="diffuse"><float name="reflectance" value="0.8"/></bsdf>
    </shape>
    <emitter type="spot">
        <transform name="to_world"><lookat origin="1, 3.5, -1" target="1, 4, -1" up="0, 0, 1"/></transform>
        <float name="cutoff_angle" value="30"/>
        <float name="beam_width" value="25"/>
        <spectrum name="intensity" value="1000"/>
    </emitter>
</scene>
"#;

/// A lamp in haze that scatters alike in every direction, over a floor:
/// guided phase sampling (the foggy street's forward phase function is
/// not guided, `integrator/guided.rs`).
const ISOTROPIC_HAZE: &str = r#"<scene version="3.0.0">
    <integrator type="volpath"><integer name="max_depth" value="6"/></integrator>
    <medium type="homogeneous" id="haze">
        <float name="sigma_t" value="0.4"/>
        <float name="albedo" value="0.9"/>
        <phase type="isotropic"/>
    </medium>
    <sensor type="perspective">
        <float name="fov" value="60"/>
        <transform name="to_world"><lookat origin="0, 1, 4" target="0, 0.8, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
        <film type="hdrfilm">
            <integer name="width" value="24"/><integer name="height" value="16"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <shape type="cube">
        <transform name="to_world"><scale x="2" y="1.5" z="2"/><translate y="1.5"/></transform>
        <bsdf type="null"/>
        <ref name="interior" id="haze"/>
    </shape>
    <shape type="rectangle">
        <transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><float name="reflectance" value="0.5"/></bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" x="0.5" y="1.6" z="-0.5"/>
        <float name="radius" value="0.1"/>
        <emitter type="area"><spectrum name="radiance" value="50"/></emitter>
    </shape>
</scene>
"#;

/// A beam: an 8 mm disk lamp at the back of a blackened tube, 20 cm long
/// and 2 cm wide, shines through a glass ball onto a wall. Light paths
/// that leave the lamp as it emits mostly end in the tube; the guide
/// learns to send them out of its mouth, where they make the ball's
/// caustic on the wall (the prism's lamp, `scenes/prism.xml`).
const TUBE_LAMP: &str = r#"<scene version="3.0.0">
    <integrator type="bdpt"><integer name="max_depth" value="6"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="45"/>
        <transform name="to_world"><lookat origin="0, 0.3, 1.4" target="0, 0.25, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
        <film type="hdrfilm">
            <integer name="width" value="64"/><integer name="height" value="48"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <emitter type="constant"><spectrum name="radiance" value="0.02"/></emitter>
    <shape type="rectangle">
        <transform name="to_world"><scale value="0.8"/><translate y="0.3" z="-0.4"/></transform>
        <bsdf type="diffuse"><float name="reflectance" value="0.8"/></bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" x="0" y="0.3" z="0"/>
        <float name="radius" value="0.08"/>
        <bsdf type="dielectric"/>
    </shape>
    <shape type="disk">
        <transform name="to_world">
            <scale value="0.004"/>
            <lookat origin="-0.5, 0.3, 0.5" target="0, 0.3, 0" up="0, 1, 0"/>
        </transform>
        <emitter type="area"><spectrum name="radiance" value="20000"/></emitter>
    </shape>
    <shape type="cylinder">
        <point name="p0" x="-0.5" y="0.3" z="0.5"/>
        <point name="p1" x="-0.359" y="0.3" z="0.359"/>
        <float name="radius" value="0.01"/>
        <bsdf type="twosided"><bsdf type="diffuse"><float name="reflectance" value="0.02"/></bsdf></bsdf>
    </shape>
</scene>
"#;

/// Point-like lamps (a spot and a point light) and a directional light
/// over a glass ball, for the bidirectional tracer: guided emission from
/// lights whose position is a delta distribution (the directional light
/// is not guided).
const POINT_LAMPS: &str = r#"<scene version="3.0.0">
    <integrator type="bdpt"><integer name="max_depth" value="5"/></integrator>
    <sensor type="perspective">
        <float name="fov" value="50"/>
        <transform name="to_world"><lookat origin="0, 1.5, 3" target="0, 0.5, 0" up="0, 1, 0"/></transform>
        <sampler type="independent"><integer name="sample_count" value="16"/></sampler>
        <film type="hdrfilm">
            <integer name="width" value="32"/><integer name="height" value="24"/>
            <rfilter type="box"/>
        </film>
    </sensor>
    <shape type="rectangle">
        <transform name="to_world"><scale value="3"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="diffuse"><float name="reflectance" value="0.5"/></bsdf>
    </shape>
    <shape type="sphere">
        <point name="center" x="0" y="0.4" z="0"/><float name="radius" value="0.3"/>
        <bsdf type="dielectric"/>
    </shape>
    <emitter type="spot">
        <transform name="to_world"><lookat origin="1, 2, 0" target="0, 0, 0" up="0, 1, 0"/></transform>
        <float name="cutoff_angle" value="15"/>
        <spectrum name="intensity" value="100"/>
    </emitter>
    <emitter type="point"><point name="position" x="-1" y="2" z="1"/><spectrum name="intensity" value="20"/></emitter>
    <emitter type="directional">
        <vector name="direction" x="0" y="-1" z="-0.3"/><spectrum name="irradiance" value="0.5"/>
    </emitter>
</scene>
"#;

/// Also the scene of the tests of determinism: its cells guide, where
/// the Cornell box's light is too flat for guiding to pay
/// (`guiding::MAX_GAIN`).
fn hidden_lamp() -> Scene {
    inline("hidden-lamp", HIDDEN_LAMP)
}

/// The Cornell box at 48 × 48, whose guide its probe declines, the field
/// worth about 0.02 (`guiding::STOP`): the tests of determinism run
/// across the decision too.
fn stopping() -> Scene {
    scene("cornell-box.xml", &[("res", "48")])
}

/// Relative MSE of Y against `reference`, each pixel over its own level,
/// over the pixels the reference sees lit (above 5 % of its mean: the
/// floor, not the black around it, where a relative error means nothing).
fn rel_mse(image: &[[f32; 4]], reference: &[[f32; 4]]) -> f64 {
    let n = reference.len() as f64;
    let mean = reference.iter().map(|p| p[1] as f64).sum::<f64>() / n;
    let lit: Vec<(f64, f64)> = image
        .iter()
        .zip(reference)
        .map(|(a, r)| (a[1] as f64, r[1] as f64))
        .filter(|&(_, r)| r > 0.05 * mean)
        .collect();
    lit.iter().map(|(a, r)| ((a - r) / r).powi(2)).sum::<f64>() / lit.len() as f64
}

/// A bundled scene, its parameters and samples per pixel.
type Case<'a> = (&'a str, &'a [(&'a str, &'a str)], u32);

#[test]
fn guided_and_unguided_renders_agree() {
    let cases: [Case; 4] = [
        ("cornell-box.xml", &[("res", "16")], 1024),
        (
            "night-street.xml",
            &[("width", "24"), ("height", "16")],
            512,
        ),
        // The volume path tracer: guided phase sampling in the fog.
        (
            "foggy-street.xml",
            &[("width", "24"), ("height", "16")],
            512,
        ),
        // The bidirectional tracer (the scene's own): guided emission
        // through a dispersing prism.
        ("prism.xml", &[("width", "24"), ("height", "16")], 256),
    ];
    for (name, params, spp) in cases {
        let s = scene(name, params);
        let off = film(&s, &options(spp, 1, Guiding::Off)).xyzv();
        let on = film(&s, &options(spp, 2, Guiding::On)).xyzv();
        agree(&format!("{name}, guided"), &on, &off);
    }
    for (name, s) in [
        ("hidden lamp", hidden_lamp()),
        ("isotropic haze", inline("haze", ISOTROPIC_HAZE)),
        // The bidirectional tracer: guided emission, from an area light
        // and from point-like lights.
        ("tube lamp", inline("tube", TUBE_LAMP)),
        ("point lamps", inline("points", POINT_LAMPS)),
    ] {
        let off = film(&s, &options(1024, 1, Guiding::Off)).xyzv();
        let on = film(&s, &options(1024, 2, Guiding::On)).xyzv();
        agree(&format!("{name}, guided"), &on, &off);
    }
}

#[test]
fn where_the_probe_finds_guiding_not_worth_it_the_image_is_the_unguided_one() {
    // The Cornell box's light is too flat for guiding to pay: the probe
    // (`learn.rs`) declines before the image's first sample, so every
    // sample is the unguided render's and weighs 1.
    let s = stopping();
    let on = render(
        &s,
        &options(20, 4, Guiding::On),
        &AtomicBool::new(false),
        &|_, _| {},
    )
    .unwrap();
    let off = film(&s, &options(20, 4, Guiding::Off));
    let guide = on.guide.expect("guiding was on");
    assert!(guide.stopped && guide.learned_spp == 0, "{guide:?}");
    assert!(guide.worth < 0.05, "{guide:?}");
    assert!(on.film == off, "the declined guide changed the image");
}

/// relMSE of Y against `reference` of `spp`-spp renders, the mean over
/// seeds 1 to 4 (single seeds' figures spread widely).
fn mean_rel_mse(s: &Scene, reference: &[[f32; 4]], spp: u32, guiding: Guiding) -> f64 {
    (1..=4)
        .map(|seed| rel_mse(&film(s, &options(spp, seed, guiding)).xyzv(), reference))
        .sum::<f64>()
        / 4.0
}

#[test]
fn the_guide_finds_a_hidden_lamp_and_lowers_the_noise() {
    // The image keeps the guide's 16 learning samples, whose first ones
    // weigh little (`learn.rs`), and single seeds' ratios spread, so the
    // mean of four, at about equal time (equal spp).
    let s = hidden_lamp();
    let reference = film(&s, &options(4096, 100, Guiding::Off)).xyzv();
    let (off, on) = (
        mean_rel_mse(&s, &reference, 128, Guiding::Off),
        mean_rel_mse(&s, &reference, 128, Guiding::On),
    );
    eprintln!("hidden lamp, 128 spp, 4 seeds: relMSE of Y {off:.4} unguided, {on:.4} guided");
    assert!(on < 0.25 * off, "guided {on}, unguided {off}");
}

#[test]
fn guided_emission_lights_the_caustic_of_a_lamp_in_a_tube() {
    // The mean of four seeds, as for the hidden lamp.
    let s = inline("tube-noise", TUBE_LAMP);
    let reference = film(&s, &options(1024, 100, Guiding::On)).xyzv();
    let (off, on) = (
        mean_rel_mse(&s, &reference, 64, Guiding::Off),
        mean_rel_mse(&s, &reference, 64, Guiding::On),
    );
    eprintln!("tube lamp, 64 spp, 4 seeds: relMSE of Y {off:.4} unguided, {on:.4} guided");
    assert!(on < 0.25 * off, "guided {on}, unguided {off}");
}

/// `scene` rendered with `o` on `threads` threads.
fn on_threads(scene: &Scene, o: &RenderOptions, threads: usize) -> Film {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    pool.install(|| film(scene, o))
}

#[test]
fn the_guide_is_the_same_on_any_number_of_threads() {
    // The path tracer, and the bidirectional tracer's guided emission,
    // whose light paths splat.
    for (name, s, spp) in [
        ("hidden lamp", hidden_lamp(), 16),
        ("tube lamp", inline("tube-threads", TUBE_LAMP), 20),
    ] {
        let o = options(spp, 5, Guiding::On);
        assert!(
            on_threads(&s, &o, 1) == on_threads(&s, &o, 3),
            "{name}: the image depends on the thread count"
        );
        // And guiding changed the samples.
        assert!(
            on_threads(&s, &o, 2) != film(&s, &options(spp, 5, Guiding::Off)),
            "{name}: guiding changed nothing"
        );
    }
}

#[test]
fn a_resumed_guided_render_is_bit_identical_to_an_uninterrupted_one() {
    // Fog too: guided phase sampling.
    let small = [("width", "16"), ("height", "12")];
    // And the bidirectional tracer's guided emission.
    for (name, stop_at) in [
        ("hidden lamp", 3),
        ("hidden lamp", 20),
        ("foggy-street.xml", 5),
        ("tube lamp", 6),
        ("stopping", 1),
        ("stopping", 6),
    ] {
        let s = match name {
            "tube lamp" => inline("tube-resume", TUBE_LAMP),
            "hidden lamp" => hidden_lamp(),
            "stopping" => stopping(),
            _ => scene(name, &small),
        };
        let opts = RenderOptions {
            bands: Some(4),
            ..options(40, 3, Guiding::On)
        };
        let whole = render(&s, &opts, &AtomicBool::new(false), &|_, _| {}).unwrap();
        let cancel = AtomicBool::new(false);
        let last = Mutex::new(None);
        let save = |c: &Checkpoint| {
            *last.lock().unwrap() = Some(c.clone());
            Ok(())
        };
        let stop = |done: u32, _: u32| {
            if done >= stop_at {
                cancel.store(true, Ordering::Relaxed);
            }
        };
        let first = render_with(
            &s,
            &opts,
            Hooks {
                progress: Some(&stop),
                checkpoints: Some(Checkpointing {
                    key: 7,
                    resume: None,
                    every: Duration::ZERO,
                    save: &save,
                }),
                ..Hooks::new(&cancel)
            },
        )
        .unwrap();
        assert!(first.cancelled && first.spp < 40, "{name}: {}", first.spp);
        let saved = last.lock().unwrap().take().unwrap();
        let resumed = render_with(
            &s,
            &opts,
            Hooks {
                checkpoints: Some(Checkpointing {
                    key: 7,
                    resume: Some(saved),
                    every: Duration::from_secs(3600),
                    save: &|_| Ok(()),
                }),
                ..Hooks::new(&AtomicBool::new(false))
            },
        )
        .unwrap();
        assert!(
            resumed.film == whole.film,
            "{name}, stopped at {}: the resumed film differs",
            first.spp
        );
        assert_eq!(resumed.rays, whole.rays, "{name}");
    }
}

#[test]
fn guided_shards_of_rows_are_the_rows_of_the_whole() {
    for (s, rows) in [
        (hidden_lamp(), [0..5u32, 5..72]),
        (stopping(), [0..20, 20..48]),
    ] {
        shards_of_rows(&s, rows);
    }
}

fn shards_of_rows(s: &Scene, shards: [std::ops::Range<u32>; 2]) {
    let o = options(24, 9, Guiding::On);
    let whole = film(s, &o);
    let w = whole.width as usize;
    for rows in shards {
        let part = film(
            s,
            &RenderOptions {
                shard: Some(Shard {
                    samples: 0..24,
                    rows: Some(rows.clone()),
                }),
                ..o.clone()
            },
        );
        for y in rows {
            let r = y as usize * w..(y as usize + 1) * w;
            assert!(part.pixels[r.clone()] == whole.pixels[r], "row {y}");
        }
    }
}

#[test]
fn guided_shards_of_samples_add_up_to_the_whole() {
    // A shard of later samples uses the field the whole render learned;
    // so does the bidirectional tracer's (whose light paths splat on any
    // row, so its shards are of samples).
    // And across the stop of a guide not worth its cost.
    for (s, cut) in [
        (hidden_lamp(), 10),
        (inline("tube-shards", TUBE_LAMP), 10),
        (stopping(), 3),
    ] {
        let o = options(24, 9, Guiding::On);
        let whole = film(&s, &o);
        let shard = |samples| {
            let shard = Some(Shard {
                samples,
                rows: None,
            });
            film(&s, &RenderOptions { shard, ..o.clone() })
        };
        let (early, late) = (shard(0..cut), shard(cut..24));
        assert_sums(&early, &late, &whole);
    }
}

/// `a` + `b` is `whole` within f64 rounding.
fn assert_sums(a: &Film, b: &Film, whole: &Film) {
    for ((a, b), c) in a.pixels.iter().zip(&b.pixels).zip(&whole.pixels) {
        for k in 0..4 {
            let sum = a.xyzv[k] + b.xyzv[k];
            assert!(
                (sum - c.xyzv[k]).abs() <= 1e-9 * c.xyzv[k].abs().max(1e-30),
                "{sum} vs {}",
                c.xyzv[k]
            );
        }
    }
}

#[test]
fn guiding_is_refused_where_it_does_not_run() {
    let s = scene("cornell-box.xml", &[("res", "8")]);
    let cases = [
        RenderOptions {
            tracer: Tracer::Wavefront,
            ..options(4, 0, Guiding::On)
        },
        RenderOptions {
            quantity: Quantity::Illuminance,
            ..options(4, 0, Guiding::On)
        },
    ];
    for o in cases {
        let e = render(&s, &o, &AtomicBool::new(false), &|_, _| {}).unwrap_err();
        assert!(matches!(e, RenderError::Guiding(_)), "{e}");
        assert!(e.to_string().contains("--guiding off"), "{e}");
    }
}

//! The example street (scenes/ies-street.xml): it loads, and under each
//! lamp the road receives what the photometric file says, I cos γ / d²
//! summed over the lamps, with interreflection adding only a little.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use scotopia_render::integrator::{measure, Measured, Receiver, RenderOptions};
use scotopia_render::light::Light;
use scotopia_render::math::Vec3;
use scotopia_scene::load_scene;
use scotopia_scene::luminaire::{read_luminaire, Photometry};
use scotopia_scene::mitsuba::Parameters;

fn scenes() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes")
}

fn street(max_depth: Option<&str>) -> scotopia_render::scene::Scene {
    let mut params = Parameters::new();
    if let Some(d) = max_depth {
        params.insert("max_depth".into(), d.into());
    }
    load_scene(&scenes().join("ies-street.xml"), &params).unwrap()
}

/// The lamps' photometric centres (the scene's comment): 8 m up at
/// x = 2.7, z = 30, 0, −30, −60.
const LAMPS: [[f32; 3]; 4] = [
    [2.7, 8.0, 30.0],
    [2.7, 8.0, 0.0],
    [2.7, 8.0, -30.0],
    [2.7, 8.0, -60.0],
];
/// The lens under each head: 0.4 × 0.2 m of 50 cd/m², facing down,
/// 5 mm above the lamp.
const LENS_CD: f64 = 50.0 * 0.4 * 0.2;

#[test]
fn the_street_loads_without_warnings() {
    let s = street(None);
    assert!(s.warnings.is_empty(), "{:?}", s.warnings);
    assert_eq!(s.geometry.shapes.len(), 37);
    // Four IES lamps, four lenses, the sky.
    assert_eq!(s.lights.len(), 9);
    // The file is the 10 000 lm luminaire its script aims at (its flux
    // computed by the script's midpoint rule on the formula, here from
    // the table's interpolant).
    let file = read_luminaire(scenes().join("lamps/street-type2.ies")).unwrap();
    let flux = file.total_flux_lm();
    assert!((flux / 10_000.0 - 1.0).abs() < 0.01, "{flux} lm");
    let extent = scotopia_render::light::SceneExtent {
        shapes: &[],
        center: Vec3::ZERO,
        radius: 1.0,
        casters: &[],
    };
    let lumens: Vec<f64> = s
        .lights
        .iter()
        .filter(|l| !matches!(l, Light::Area(_)))
        .map(|l| l.power(&extent).lumens)
        .filter(|&lm| lm > 1000.0)
        .collect();
    assert_eq!(lumens.len(), 4, "{lumens:?}");
    for lm in lumens {
        assert!(
            (lm / flux - 1.0).abs() < 2e-3,
            "{lm} lm vs the file's {flux}"
        );
    }
}

/// The file's I(γ, C) towards `dir` (a unit vector) from a lamp of the
/// street: its frame (the scene's comment) has the nadir at −y, C 0°
/// towards −x and C 90° towards −z.
fn intensity(file: &Photometry, dir: Vec3) -> f64 {
    let gamma = (-dir.y).clamp(-1.0, 1.0).acos().to_degrees();
    let c = (-dir.z).atan2(-dir.x).to_degrees();
    file.intensity(gamma, c) as f64
}

/// Illuminance at `p` on a surface facing `n` from the four lamps as the
/// file gives them (and the lenses, Lambertian, facing down), unshadowed.
fn expected_direct(file: &Photometry, p: Vec3, n: Vec3) -> f64 {
    LAMPS
        .iter()
        .map(|&[x, y, z]| {
            let d = Vec3::new(p.x - x, p.y - y, p.z - z);
            let dir = d.normalize();
            let incidence = -dir.dot(n) as f64;
            if incidence <= 0.0 || dir.y >= 0.0 {
                return 0.0;
            }
            let i = intensity(file, dir) + LENS_CD * (-dir.y as f64);
            i * incidence / d.length_squared() as f64
        })
        .sum()
}

fn run(s: &scotopia_render::scene::Scene, rs: &[Receiver], spp: u32) -> Vec<Measured> {
    let options = RenderOptions {
        spp: Some(spp),
        seed: 11,
        ..RenderOptions::default()
    };
    measure(s, rs, &options, &AtomicBool::new(false), &|_, _| {}).unwrap()
}

#[test]
fn under_a_lamp_the_road_receives_the_files_intensity_over_the_height_squared() {
    let file = read_luminaire(scenes().join("lamps/street-type2.ies")).unwrap();
    let up = Vec3::new(0.0, 1.0, 0.0);
    // Below the lamps at z = 0 and −30, on the road.
    let rs: Vec<Receiver> = LAMPS[1..3]
        .iter()
        .map(|&[x, _, z]| Receiver {
            p: Vec3::new(x, 0.0, z),
            n: up,
        })
        .collect();
    // Direct light only (max_depth 1: the receiver's segment to a light),
    // against Σ I(γ, C) cos γ / d² from the file, within 4 standard
    // errors + 0.5 % (as tests/measure.rs). The lamp overhead gives
    // I(0°)/h² = 1910 cd / 64 m² = 29.8 lx, each neighbour 30 m away
    // (γ 75°, in its beam) 0.77 lx, the lenses 0.06 lx; the sky's
    // 0.001 cd/m² adds at most π × 0.001 = 0.003 lx, inside the 0.5 %.
    let nadir = file.intensity(0.0, 0.0) as f64 / 64.0;
    assert!((nadir - 1910.0 / 64.0).abs() < 0.01, "I(0)/h² = {nadir}");
    let direct = street(Some("1"));
    let measured = run(&direct, &rs, 1024);
    for (r, m) in rs.iter().zip(&measured) {
        let expected = expected_direct(&file, r.p, up);
        let tol = 4.0 * m.e_se + 5e-3 * expected;
        assert!(
            (m.e - expected).abs() <= tol,
            "direct at z = {}: E = {} ± {} lx, expected {expected} (I(0)/h² alone {nadir})",
            r.p.z,
            m.e,
            m.e_se
        );
        // A 4000 K LED's S/P (README: white LED 4000 K, 1.66).
        assert!((m.sp() - 1.66).abs() < 0.05, "S/P {}", m.sp());
    }

    // With the scene's own depth, interreflection only adds, and not
    // much. Above a road receiver's horizon are the house fronts (x = ±8,
    // up to 13 m high; the kerb's 15 cm face at 0.8 m subtends < 0.01);
    // their cosine-weighted view factor from x = 2.7 is at most that of
    // infinite walls, ½(1 − a/√(a² + H²)): 0.31 (right, a = 5.3 m) and
    // 0.18 (left, a = 10.7 m). They are lit directly by at most the
    // largest E on a 0.5 m × 1 m grid over them (computed below from the
    // file: ≈ 8 lx right, ≈ 12 lx left); with reflectance ≤ 0.55 a first
    // bounce adds at most B₁ = 0.55 (0.31 E_right + 0.18 E_left) ≈ 2.6 lx.
    // Each further bounce passes through another reflectance ≤ 0.55 into
    // view factors summing to ≤ 1, so all bounces add ≤ B₁/(1 − 0.55)
    // ≈ 5.9 lx, 19 % of the direct light (measured: 0.85 lx, 2.7 %).
    let facade_max = |x: f32, n: Vec3| {
        (0..=26)
            .flat_map(|iy| (-60..=30).map(move |z| Vec3::new(x, 0.5 * iy as f32, z as f32)))
            .map(|p| expected_direct(&file, p, n))
            .fold(0.0, f64::max)
    };
    let (right, left) = (
        facade_max(8.0, Vec3::new(-1.0, 0.0, 0.0)),
        facade_max(-8.0, Vec3::new(1.0, 0.0, 0.0)),
    );
    let allowance = 0.55 * (0.31 * right + 0.18 * left) / (1.0 - 0.55);
    let full = street(None);
    for ((r, d), m) in rs.iter().zip(&measured).zip(run(&full, &rs, 1024)) {
        let added = m.e - d.e;
        let se = (m.e_se * m.e_se + d.e_se * d.e_se).sqrt();
        assert!(
            added >= -4.0 * se && added <= allowance + 4.0 * se,
            "interreflection at z = {}: {added} lx over the direct {} (± {se}; allowance {allowance})",
            r.p.z,
            d.e
        );
    }
}

#[test]
fn the_wavefront_tracer_renders_the_street_as_the_scalar_one_does() {
    // As tests/wavefront.rs does for the other bundled scenes: the only
    // one with IES lamps, so their sampling in the wavefront tracer.
    use scotopia_render::integrator::{render, Quantity, Tracer};
    use scotopia_scene::{load_scene_with, LoadOptions, Resolution};
    let load = LoadOptions {
        resolution: Some(Resolution::parse("20").unwrap()),
        ..LoadOptions::default()
    };
    let s = load_scene_with(&scenes().join("ies-street.xml"), &Parameters::new(), &load).unwrap();
    let render_with = |tracer: Tracer, quantity: Quantity| {
        let o = RenderOptions {
            spp: Some(3),
            seed: 7,
            tracer,
            quantity,
            ..RenderOptions::default()
        };
        render(&s, &o, &AtomicBool::new(false), &|_, _| {})
    };
    // Illuminance is the scalar path tracer's receivers: the wavefront
    // tracer says it cannot, rather than quietly handing over.
    let e = render_with(Tracer::Wavefront, Quantity::Illuminance).unwrap_err();
    assert!(
        e.to_string().contains("illuminance") && e.to_string().contains("scalar"),
        "{e}"
    );
    {
        let quantity = Quantity::Radiance;
        let image = |tracer: Tracer| render_with(tracer, quantity).unwrap();
        let (scalar, wavefront) = (image(Tracer::Scalar), image(Tracer::Wavefront));
        assert!(scalar.rays > 0);
        // (Not assert_eq: the films' Debug text would flood the report.)
        assert!(scalar.film == wavefront.film, "{quantity:?}: films differ");
        assert_eq!(
            (scalar.spp, scalar.nonfinite, scalar.rays),
            (wavefront.spp, wavefront.nonfinite, wavefront.rays),
            "{quantity:?}"
        );
    }
}

//! Light through participating media (issue 25) against analytic answers
//! and quadrature, measured at virtual receivers (`measure`, which sits in
//! the sensor's medium). Tolerances: 4 standard errors plus 0.5 %.

mod common;

use std::sync::atomic::AtomicBool;

use common::{assert_close, vol};
use scotopia_color::photometry::spectrum_to_xyzv;
use scotopia_color::spectrum::Tabulated;
use scotopia_color::Spectrum;
use scotopia_render::integrator::{measure, Measured, Receiver, RenderOptions};
use scotopia_render::math::Vec3;
use scotopia_render::wavelength::WavelengthStrategy;
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

fn scene(name: &str, body: &str) -> scotopia_render::scene::Scene {
    let dir = std::env::temp_dir().join(format!("scotopia-media-tr-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let f = dir.join(format!("{name}.xml"));
    std::fs::write(&f, format!(r#"<scene version="3.0.0">{body}</scene>"#)).unwrap();
    load_scene(&f, &Parameters::new()).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn run(
    s: &scotopia_render::scene::Scene,
    r: Receiver,
    spp: u32,
    strategy: WavelengthStrategy,
) -> Measured {
    let options = RenderOptions {
        spp: Some(spp),
        seed: 11,
        strategy,
        ..RenderOptions::default()
    };
    measure(s, &[r], &options, &AtomicBool::new(false), &|_, _| {}).unwrap()[0]
}

/// The illuminance (lx) of a spectral irradiance given per nm on 400–700.
fn lux(irradiance: impl Fn(f64) -> f64) -> f64 {
    let lambda: Vec<f32> = (400..=700).map(|l| l as f32).collect();
    let value = lambda
        .iter()
        .map(|&l| irradiance(l as f64) as f32)
        .collect();
    spectrum_to_xyzv(&Spectrum::tabulated(Tabulated::new(lambda, value).unwrap())).y
}

/// The test media's σ_t: 0.8 at 400 nm falling linearly to 0.2 at 700 nm
/// (haze's rise towards the blue), per metre.
fn sigma(lambda: f64) -> f64 {
    0.8 + (lambda - 400.0) / 300.0 * (0.2 - 0.8)
}
const SIGMA: &str = r#"<spectrum name="sigma_t" value="400:0.8, 700:0.2"/>"#;

const UP: Receiver = Receiver {
    p: Vec3::new(0.0, 0.0, 0.0),
    n: Vec3::new(0.0, 1.0, 0.0),
};

/// ∫₀¹ μ e^{−τ/μ} dμ = E₃(τ), by the midpoint rule.
fn e3(tau: f64) -> f64 {
    let n = 20_000;
    (0..n)
        .map(|i| {
            let mu = (i as f64 + 0.5) / n as f64;
            mu * (-tau / mu).exp()
        })
        .sum::<f64>()
        / n as f64
}

#[test]
fn an_absorbing_slab_under_a_uniform_sky_follows_beer_lambert_for_every_wavelength_strategy() {
    // A slab 1 m thick (null boundaries, albedo 0) between a receiver and a
    // uniform sky of radiance 1 W/(m² sr nm): per wavelength the receiver
    // gets ∫ cos θ e^{−τ/cos θ} dω = 2π E₃(τ) with τ = σ_t(λ)·1 m. Rays
    // drawn from the receiver cross it with the cluster's MIS; shadow rays
    // towards the sky take Beer–Lambert's transmittance.
    let s = scene(
        "slab",
        &format!(
            r#"<integrator type="volpath"/><sensor type="perspective"/>
            <emitter type="constant"><spectrum name="radiance" value="400:1, 700:1"/></emitter>
            <medium type="homogeneous" id="slab">{SIGMA}<float name="albedo" value="0"/></medium>
            <shape type="cube"><bsdf type="null"/><ref name="interior" id="slab"/>
              <transform name="to_world"><scale x="2000" y="0.5" z="2000"/><translate y="1.5"/></transform></shape>"#
        ),
    );
    let expected = lux(|l| 2.0 * std::f64::consts::PI * e3(sigma(l)));
    for strategy in WavelengthStrategy::ALL {
        let m = run(&s, UP, 1 << 15, strategy);
        assert_close(strategy.name(), &m, expected);
    }
}

#[test]
fn a_camera_in_a_scattering_sphere_without_absorption_sees_the_sky_unchanged() {
    // The volumetric furnace: albedo 1, σ_t varying fourfold over the
    // spectrum, forward-scattering; whatever the paths do inside the
    // sphere, the light they bring is the sky's: E = π L.
    let s = scene(
        "furnace",
        &format!(
            r#"<integrator type="volpath"/>
            <emitter type="constant"><spectrum name="radiance" value="400:1, 700:1"/></emitter>
            <medium type="homogeneous" id="fog">{SIGMA}<float name="scale" value="2"/><float name="albedo" value="1"/>
              <phase type="hg"><float name="g" value="0.6"/></phase></medium>
            <sensor type="perspective"><ref id="fog"/></sensor>
            <shape type="sphere"><float name="radius" value="2"/><bsdf type="null"/><ref name="interior" id="fog"/></shape>"#
        ),
    );
    let expected = lux(|_| std::f64::consts::PI);
    for strategy in WavelengthStrategy::ALL {
        let m = run(&s, UP, 1 << 14, strategy);
        assert_close(strategy.name(), &m, expected);
    }
    // The same sphere absorbing only: every way out is 2 m long, so
    // E = π L e^{−2 σ_t · 2 m}.
    let s = scene(
        "absorbing",
        &format!(
            r#"<integrator type="volpath"/>
            <emitter type="constant"><spectrum name="radiance" value="400:1, 700:1"/></emitter>
            <medium type="homogeneous" id="fog">{SIGMA}<float name="scale" value="2"/><float name="albedo" value="0"/></medium>
            <sensor type="perspective"><ref id="fog"/></sensor>
            <shape type="sphere"><float name="radius" value="2"/><bsdf type="null"/><ref name="interior" id="fog"/></shape>"#
        ),
    );
    let expected = lux(|l| std::f64::consts::PI * (-4.0 * sigma(l)).exp());
    let m = run(&s, UP, 1 << 14, WavelengthStrategy::Swc);
    assert_close("absorbing", &m, expected);
}

#[test]
fn single_scattering_from_a_point_light_matches_quadrature() {
    // A receiver facing up, a point light 2 m below it, in an unbounded
    // medium (σ_t 0.3/m, albedo 0.8, HG g = 0.5): the receiver sees the
    // lamp only by light scattered above its plane. With max_depth 2 that
    // is single scattering:
    // E = ∫_hemisphere cos θ ∫₀^∞ σ_s e^{−σ_t r} p(μ) I e^{−σ_t r₁}/r₁² dr dω,
    // with r₁ the distance from the lamp to the point r·ω and μ the cosine
    // of the scattering angle.
    let (st, albedo, g, i) = (0.3f64, 0.8f64, 0.5f64, 100.0f64);
    let s = scene(
        "single",
        r#"<integrator type="volpath"><integer name="max_depth" value="2"/></integrator>
        <medium type="homogeneous" id="m"><float name="sigma_t" value="0.3"/><float name="albedo" value="0.8"/>
          <phase type="hg"><float name="g" value="0.5"/></phase></medium>
        <sensor type="perspective"><ref id="m"/></sensor>
        <emitter type="point"><point name="position" x="0" y="-2" z="0"/>
          <spectrum name="intensity" value="400:100, 700:100"/></emitter>"#,
    );
    let hg = |mu: f64| {
        (1.0 - g * g) / (4.0 * std::f64::consts::PI * (1.0 + g * g - 2.0 * g * mu).powf(1.5))
    };
    // θ from the receiver's normal; r by r = −ln(1 − u)/σ_t.
    let (nt, nu) = (600, 3000);
    let mut sum = 0.0;
    for a in 0..nt {
        let theta = (a as f64 + 0.5) / nt as f64 * std::f64::consts::FRAC_PI_2;
        let (sin, cos) = theta.sin_cos();
        let mut radial = 0.0;
        for b in 0..nu {
            let u = (b as f64 + 0.5) / nu as f64;
            let r = -(1.0 - u).ln() / st;
            // The point (r sin θ, r cos θ); the lamp at (0, −2).
            let (x, y) = (r * sin, r * cos);
            let r1 = (x * x + (y + 2.0) * (y + 2.0)).sqrt();
            // Light travels lamp → point → receiver: μ = d_in · d_out.
            let mu = (x * -sin + (y + 2.0) * -cos) / r1;
            // e^{−σ_t r} cancels against the density of r.
            radial += albedo * hg(mu) * i * (-st * r1).exp() / (r1 * r1);
        }
        sum += cos * sin * radial / nu as f64;
    }
    let per_nm = 2.0 * std::f64::consts::PI * sum * std::f64::consts::FRAC_PI_2 / nt as f64;
    let expected = lux(|_| per_nm);
    let m = run(&s, UP, 1 << 15, WavelengthStrategy::Swc);
    assert_close("single scattering", &m, expected);
}

#[test]
fn the_path_integrator_leaves_media_out_with_a_warning() {
    let s = scene(
        "path",
        &format!(
            r#"<emitter type="constant"><spectrum name="radiance" value="400:1, 700:1"/></emitter>
            <medium type="homogeneous" id="slab">{SIGMA}<float name="albedo" value="0"/></medium>
            <sensor type="perspective"/>
            <shape type="sphere"><float name="radius" value="5"/><bsdf type="null"/><ref name="interior" id="slab"/></shape>"#
        ),
    );
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("media are not rendered")),
        "{:?}",
        s.warnings
    );
    // Mitsuba's path: the null sphere is a bounce, the sky comes through.
    let m = run(&s, UP, 256, WavelengthStrategy::Swc);
    assert_close("clear", &m, lux(|_| std::f64::consts::PI));
}

#[test]
fn dispersion_and_fluorescence_in_a_chromatic_fog_give_every_strategy_the_same_answer() {
    // A receiver in fog whose σ_t varies fourfold over the spectrum, under
    // a white sky, with a dispersive glass ball and a fluorescent ceiling
    // (UV in, blue out) in the fog: paths cross the fog (the cluster's MIS
    // ratios grow), then refract (the cluster collapses to one wavelength,
    // whose own estimate must take over) or re-emit at another wavelength.
    // No closed form; the three strategies are independent unbiased
    // estimators and must agree (single traces one wavelength and needs
    // no MIS at all).
    let s = scene(
        "dispersive",
        &format!(
            r#"<integrator type="volpath"/>
            <emitter type="constant"><spectrum name="radiance" value="360:1, 830:1"/></emitter>
            <medium type="homogeneous" id="fog">{SIGMA}<float name="albedo" value="0.9"/></medium>
            <sensor type="perspective"><ref id="fog"/></sensor>
            <shape type="sphere"><float name="radius" value="3"/><bsdf type="null"/><ref name="interior" id="fog"/></shape>
            <shape type="sphere"><point name="center" x="0.4" y="1.2" z="0"/><float name="radius" value="0.5"/>
              <bsdf type="dielectric"><string name="int_ior" value="bk7"/></bsdf></shape>
            <shape type="disk"><transform name="to_world"><scale value="1.2"/><rotate x="1" angle="90"/><translate x="-1" y="2"/></transform>
              <bsdf type="fluorescent">
                <spectrum name="reflectance" value="360:0.6, 410:0.85, 830:0.85"/>
                <spectrum name="excitation" value="360:0.35, 380:0.25, 400:0.05, 410:0"/>
                <spectrum name="emission" value="400:0, 440:1, 470:0.6, 520:0"/>
                <float name="quantum_yield" value="0.8"/>
              </bsdf></shape>"#
        ),
    );
    let results: Vec<(WavelengthStrategy, Measured)> = WavelengthStrategy::ALL
        .iter()
        .map(|&st| (st, run(&s, UP, 1 << 15, st)))
        .collect();
    let (a, ma) = &results[0];
    for (b, mb) in &results[1..] {
        let se = (ma.e_se * ma.e_se + mb.e_se * mb.e_se).sqrt();
        eprintln!(
            "{}: {} ± {}; {}: {} ± {}",
            a.name(),
            ma.e,
            ma.e_se,
            b.name(),
            mb.e,
            mb.e_se
        );
        assert!(
            (ma.e - mb.e).abs() <= 4.0 * se,
            "{} {} vs {} {} (combined SE {se})",
            a.name(),
            ma.e,
            b.name(),
            mb.e
        );
    }
}

#[test]
fn a_graded_grid_slab_follows_beer_lambert_through_its_optical_depth() {
    // The slab of the first test as a heterogeneous medium: σ_t varies
    // with height only (a grid 2 × 8 × 2, values at the cell centres,
    // linear between them and constant beyond, as trilinear lookups
    // clamp), so a ray at θ from the vertical meets τ / cos θ, and the
    // receiver gets 2π E₃(τ) for τ = ∫ σ_t dy. Delta tracking draws the
    // paths, ratio tracking attenuates the shadow rays.
    let (a, b) = (0.2f64, 1.2f64);
    let value = |j: usize| a + b * (j as f64 + 0.5) / 8.0;
    let dir = std::env::temp_dir().join(format!("scotopia-media-tr-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let grid: Vec<u8> = {
        // `vol` writes cubes: 8³ cells, the value by y alone.
        vol(8, 1, |_, y, _| vec![value(y) as f32])
    };
    std::fs::write(dir.join("graded.vol"), grid).unwrap();
    let s = scene(
        "graded",
        r#"<integrator type="volpath"/><sensor type="perspective"/>
        <emitter type="constant"><spectrum name="radiance" value="400:1, 700:1"/></emitter>
        <medium type="heterogeneous" id="slab"><float name="albedo" value="0"/>
          <volume type="gridvolume" name="sigma_t"><string name="filename" value="graded.vol"/>
            <transform name="to_world"><scale x="4000" y="1" z="4000"/><translate x="-2000" y="1" z="-2000"/></transform>
          </volume></medium>
        <shape type="cube"><bsdf type="null"/><ref name="interior" id="slab"/>
          <transform name="to_world"><scale x="2000" y="0.5" z="2000"/><translate y="1.5"/></transform></shape>"#,
    );
    // Linear between the first and last centres, constant in the end
    // sixteenths.
    let (lo, hi) = (0.5 / 8.0, 7.5 / 8.0);
    let tau = (a * (hi - lo) + 0.5 * b * (hi * hi - lo * lo)) + lo * (value(0) + value(7));
    let expected = lux(|_| 2.0 * std::f64::consts::PI * e3(tau));
    for strategy in [WavelengthStrategy::Swc, WavelengthStrategy::Single] {
        let m = run(&s, UP, 1 << 15, strategy);
        assert_close(strategy.name(), &m, expected);
    }
}

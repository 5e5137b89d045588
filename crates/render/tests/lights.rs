//! Lights against analytic irradiance and power.

mod common;

use common::Rng;
use scotopia_color::{SampledWavelengths, Spectrum};
use scotopia_render::geometry::{Planar, PlanarKind, Shape, Sphere, TriangleMesh};
use scotopia_render::light::{AreaLight, ConstantLight, Light, PointLight, SceneExtent, SpotLight};
use scotopia_render::math::{Transform, Vec3};

fn wl() -> SampledWavelengths<4> {
    SampledWavelengths::sample_uniform(0.5)
}

/// Monte Carlo irradiance at `p` with normal `n` from `light`: mean of
/// L cos θ / pdf, and its standard error.
fn irradiance(light: &Light, scene: &SceneExtent, p: Vec3, n: Vec3, samples: usize) -> (f64, f64) {
    let w = wl();
    let mut rng = Rng(42);
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    for _ in 0..samples {
        let v = light
            .sample_li(scene, &w, p, rng.next(), rng.pair())
            .map_or(0.0, |s| {
                (s.radiance[0] * s.wi.dot(n).max(0.0) / s.pdf) as f64
            });
        sum += v;
        sum2 += v * v;
    }
    let mean = sum / samples as f64;
    (
        mean,
        ((sum2 / samples as f64 - mean * mean).max(0.0) / samples as f64).sqrt(),
    )
}

fn scene(shapes: &[Shape]) -> SceneExtent<'_> {
    SceneExtent {
        shapes,
        center: Vec3::ZERO,
        radius: 10.0,
    }
}

#[test]
fn disk_light_on_axis() {
    // A disk of radius r at height h facing down: E = π L r² / (h² + r²).
    let (r, h, l) = (0.5f32, 2.0f32, 3.0f32);
    let t = Transform::translate(Vec3::new(0.0, 0.0, h))
        .then_after(&Transform::scale(Vec3::new(r, r, -1.0)).unwrap());
    let shapes = vec![Shape::Planar(Box::new(Planar::new(PlanarKind::Disk, t)))];
    let light = Light::Area(AreaLight::new(0, &shapes[0], Spectrum::Constant(l)));
    let (e, se) = irradiance(
        &light,
        &scene(&shapes),
        Vec3::ZERO,
        Vec3::new(0.0, 0.0, 1.0),
        200_000,
    );
    let expected = std::f64::consts::PI * (l * r * r / (h * h + r * r)) as f64;
    assert!(
        (e - expected).abs() < 4.0 * se + 1e-9,
        "{e} ± {se} vs {expected}"
    );
    // Power: π A L.
    let p = light.power(&scene(&shapes));
    let area = std::f64::consts::PI * (r * r) as f64;
    assert!((p.watts - std::f64::consts::PI * area * l as f64 * 470.0).abs() < 1e-3 * p.watts);
}

#[test]
fn sphere_and_mesh_lights() {
    // A sphere of radius r at distance d: E = π L (r/d)² facing it.
    let (r, d, l) = (0.4f32, 3.0f32, 2.0f32);
    let shapes = vec![Shape::Sphere(Sphere {
        center: Vec3::new(0.0, 0.0, d),
        radius: r,
    })];
    let light = Light::Area(AreaLight::new(0, &shapes[0], Spectrum::Constant(l)));
    let (e, se) = irradiance(
        &light,
        &scene(&shapes),
        Vec3::ZERO,
        Vec3::new(0.0, 0.0, 1.0),
        400_000,
    );
    let expected = std::f64::consts::PI * (l * r * r / (d * d)) as f64;
    assert!((e - expected).abs() < 4.0 * se, "{e} ± {se} vs {expected}");

    // A square of two triangles (side 1, facing down at height 1) equals the
    // same square as a rectangle.
    let pos = vec![
        Vec3::new(-0.5, -0.5, 1.0),
        Vec3::new(0.5, -0.5, 1.0),
        Vec3::new(0.5, 0.5, 1.0),
        Vec3::new(-0.5, 0.5, 1.0),
    ];
    let mesh = TriangleMesh::new(
        pos,
        None,
        None,
        vec![[0, 2, 1], [0, 3, 2]],
        &Transform::IDENTITY,
    )
    .unwrap();
    let rect = Planar::new(
        PlanarKind::Rectangle,
        Transform::translate(Vec3::new(0.0, 0.0, 1.0))
            .then_after(&Transform::scale(Vec3::new(0.5, 0.5, -1.0)).unwrap()),
    );
    let shapes = vec![Shape::Mesh(mesh), Shape::Planar(Box::new(rect))];
    let s = scene(&shapes);
    let a = Light::Area(AreaLight::new(0, &shapes[0], Spectrum::Constant(1.0)));
    let b = Light::Area(AreaLight::new(1, &shapes[1], Spectrum::Constant(1.0)));
    let p = Vec3::new(0.2, -0.1, 0.0);
    let (ea, sa) = irradiance(&a, &s, p, Vec3::new(0.0, 0.0, 1.0), 200_000);
    let (eb, sb) = irradiance(&b, &s, p, Vec3::new(0.0, 0.0, 1.0), 200_000);
    assert!(
        (ea - eb).abs() < 4.0 * (sa * sa + sb * sb).sqrt(),
        "{ea} vs {eb}"
    );
    // Lit only from the front.
    let (back, _) = irradiance(
        &a,
        &s,
        Vec3::new(0.0, 0.0, 2.0),
        Vec3::new(0.0, 0.0, -1.0),
        1000,
    );
    assert_eq!(back, 0.0);
}

#[test]
fn area_light_pdf_matches_its_samples() {
    let t = Transform::translate(Vec3::new(0.3, 0.0, 2.0));
    let shapes = vec![Shape::Planar(Box::new(Planar::new(
        PlanarKind::Rectangle,
        t,
    )))];
    let Shape::Planar(pl) = &shapes[0] else {
        unreachable!()
    };
    let n = pl.normal();
    let light = AreaLight::new(0, &shapes[0], Spectrum::Constant(1.0));
    let p = Vec3::new(0.0, 0.0, 4.0);
    let mut rng = Rng(1);
    for _ in 0..100 {
        let s = light
            .sample_li(&shapes, &wl(), p, rng.next(), rng.pair())
            .unwrap();
        let hit = p + s.wi * s.distance;
        assert!((light.pdf_li(p, hit, n) - s.pdf).abs() < 1e-3 * s.pdf);
    }
}

#[test]
fn point_spot_and_environment() {
    let w = wl();
    let shapes = vec![];
    let s = scene(&shapes);
    let point = Light::Point(PointLight {
        position: Vec3::new(0.0, 0.0, 2.0),
        intensity: Spectrum::Constant(8.0),
    });
    let ls = point
        .sample_li(&s, &w, Vec3::ZERO, 0.5, [0.5, 0.5])
        .unwrap();
    assert!(ls.delta && (ls.radiance[0] - 2.0).abs() < 1e-6 && ls.distance == 2.0);
    assert!((point.power(&s).watts - 4.0 * std::f64::consts::PI * 8.0 * 470.0).abs() < 1e-6 * 4e4);

    // A hard-edged spot (beam width = cutoff) emits 2π(1 − cos θ_c) ∫I.
    let spot = SpotLight::new(
        Vec3::ZERO,
        Vec3::new(0.0, 0.0, -1.0),
        Spectrum::Constant(1.0),
        30.0,
        30.0,
    );
    let solid = 2.0 * std::f64::consts::PI * (1.0 - 30f64.to_radians().cos());
    assert!((spot.power().watts / 470.0 - solid).abs() < 1e-5);
    assert_eq!(spot.falloff(1.0), 1.0);
    assert_eq!(spot.falloff(40f32.to_radians().cos()), 0.0);
    // With a ramp, the power matches numerical integration of the falloff.
    let soft = SpotLight::new(
        Vec3::ZERO,
        Vec3::new(0.0, 0.0, -1.0),
        Spectrum::Constant(1.0),
        30.0,
        15.0,
    );
    let n = 100_000;
    let numeric: f64 = (0..n)
        .map(|i| {
            let th = (i as f64 + 0.5) / n as f64 * std::f64::consts::PI;
            soft.falloff(th.cos() as f32) as f64 * th.sin() * std::f64::consts::PI / n as f64
        })
        .sum::<f64>()
        * 2.0
        * std::f64::consts::PI;
    assert!(
        (soft.power().watts / 470.0 - numeric).abs() < 1e-4,
        "{} vs {numeric}",
        soft.power().watts / 470.0
    );

    // A constant environment of radiance L gives E = π L on any plane.
    let env = Light::Constant(ConstantLight {
        radiance: Spectrum::Constant(1.5),
    });
    let (e, se) = irradiance(&env, &s, Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), 200_000);
    assert!(
        (e - std::f64::consts::PI * 1.5).abs() < 4.0 * se,
        "{e} ± {se}"
    );
}

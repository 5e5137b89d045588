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
        casters: &[],
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
    let shapes = vec![Shape::Sphere(Sphere::new(Vec3::new(0.0, 0.0, d), r))];
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

mod envmap {
    use super::common::{chi2_p_value, Rng};
    use super::*;
    use scotopia_color::{rgb_to_spectrum, RgbSpace, SpectrumKind, UpsampleMethod};
    use scotopia_render::light::EnvMapLight;

    /// A sky: dim blue gradient, a warm "sun" texel `sun` times brighter
    /// than the sky, a dark ground.
    fn sky(w: usize, h: usize, sun: f32) -> Vec<[f32; 3]> {
        let mut px = vec![[0.0; 3]; w * h];
        for y in 0..h {
            for x in 0..w {
                px[y * w + x] = if y < h / 2 {
                    let t = y as f32 / h as f32;
                    [0.2 + t, 0.3 + t, 0.9]
                } else {
                    [0.05, 0.04, 0.03]
                };
            }
        }
        px[(h / 5) * w + w / 3] = [1.0, 0.9, 0.6].map(|v| v * sun);
        px
    }

    fn rotated(sun: f32, world_from_light: Transform) -> EnvMapLight {
        EnvMapLight::new(
            32,
            16,
            &sky(32, 16, sun),
            RgbSpace::Srgb,
            2.0,
            world_from_light,
        )
        .unwrap()
    }

    #[test]
    fn a_uniform_map_is_a_constant_environment() {
        let rgb = [0.7, 0.5, 0.3];
        let env =
            EnvMapLight::new(8, 4, &[rgb; 32], RgbSpace::Srgb, 1.5, Transform::IDENTITY).unwrap();
        let s = rgb_to_spectrum(
            rgb,
            RgbSpace::Srgb,
            UpsampleMethod::Jakob2019,
            SpectrumKind::Illuminant,
        )
        .unwrap()
        .scaled(1.5);
        let constant = Light::Constant(ConstantLight {
            radiance: s.clone(),
        });
        let w = wl();
        let want = s.sample(&w);
        let mut rng = Rng(3);
        for _ in 0..100 {
            let d = scotopia_render::sampling::warp::square_to_uniform_sphere(rng.pair());
            let got = env.radiance(&w, d);
            for k in 0..4 {
                assert!(
                    (got[k] - want[k]).abs() < 1e-4 * want[k],
                    "{got:?} {want:?}"
                );
            }
        }
        let shapes: Vec<Shape> = vec![];
        let (a, b) = (
            Light::EnvMap(Box::new(env)).power(&scene(&shapes)),
            constant.power(&scene(&shapes)),
        );
        assert!((a.watts - b.watts).abs() < 2e-3 * b.watts, "{a:?} {b:?}");
        assert!((a.lumens - b.lumens).abs() < 2e-3 * b.lumens, "{a:?} {b:?}");
    }

    /// (u, v) of a direction in the light's frame, by Mitsuba's mapping.
    fn uv(d: Vec3) -> [f32; 2] {
        let u = d.x.atan2(-d.z) / (2.0 * std::f32::consts::PI);
        [
            u - u.floor(),
            d.y.clamp(-1.0, 1.0).acos() / std::f32::consts::PI,
        ]
    }

    #[test]
    fn sampling_matches_pdf_chi_square() {
        // Chi-square in the map's own (u, v) with bins aligned to the cells
        // the density is constant on (2 × 3 cells of the 32 × 15 between
        // texel centres), so expected counts are exact: pdf_li at a cell's
        // centre times its solid angle. A direction-binned test would have
        // to integrate this discontinuous density numerically.
        let (w, h) = (32usize, 16usize);
        let t = Transform::rotate(Vec3::new(1.0, 1.0, 0.0), 70.0).unwrap();
        for (i, (sun, frame)) in [(1.0, Transform::IDENTITY), (400.0, t)]
            .into_iter()
            .enumerate()
        {
            let light = rotated(sun, frame);
            let back = frame.inverse();
            let (bu, bv) = (w / 2, (h - 1) / 3);
            let bin = |[u, v]: [f32; 2]| {
                let s = (u - 0.5 / w as f32).rem_euclid(1.0);
                let x = ((s * w as f32) as usize).min(w - 1) / 2;
                let y = ((v * (h - 1) as f32) as usize).min(h - 2) / 3;
                y * bu + x
            };
            let n = 200_000;
            let mut observed = vec![0.0; bu * bv];
            let mut mismatched = 0;
            let mut rng = Rng(20 + i as u64);
            let wl = wl();
            for _ in 0..n {
                let s = light.sample_li(&wl, rng.pair()).expect("a sample");
                observed[bin(uv(back.vector(s.wi)))] += 1.0;
                // Round trips through a direction may cross a cell edge by
                // a rounding error; such samples must stay rare.
                if (s.pdf - light.pdf_li(s.wi)).abs() > 1e-3 * s.pdf {
                    mismatched += 1;
                }
            }
            assert!(
                mismatched < n / 1000,
                "case {i}: {mismatched} pdf mismatches"
            );
            let mut expected = vec![0.0; bu * bv];
            for cy in 0..h - 1 {
                for cx in 0..w {
                    let (u, v) = (
                        (cx as f32 + 1.0) / w as f32,
                        (cy as f32 + 0.5) / (h - 1) as f32,
                    );
                    let (th, ph) = (v * std::f32::consts::PI, u * 2.0 * std::f32::consts::PI);
                    let local = Vec3::new(th.sin() * ph.sin(), th.cos(), -th.sin() * ph.cos());
                    // pdf_uv = pdf_ω · 2π² sin θ, constant over the cell.
                    let pdf_uv = light.pdf_li(frame.vector(local)) as f64
                        * 2.0
                        * std::f64::consts::PI.powi(2)
                        * th.sin() as f64;
                    expected[bin([u, v])] += pdf_uv / (w * (h - 1)) as f64 * n as f64;
                }
            }
            let p = chi2_p_value(&observed, &expected);
            assert!(p > 0.01 / 2.0, "case {i}: p = {p:e}");
        }
    }

    #[test]
    fn importance_sampled_irradiance_matches_uniform_sampling() {
        // Two independent estimators of ∫ L cos θ dω at an upward normal.
        let t = Transform::rotate(Vec3::new(1.0, 1.0, 0.0), 40.0).unwrap();
        let light = rotated(400.0, t);
        let w = wl();
        let n = Vec3::new(0.0, 1.0, 0.0);
        let stats = |f: &mut dyn FnMut(&mut Rng) -> f64, seed| {
            let mut rng = Rng(seed);
            let count = 400_000;
            let (mut s, mut s2) = (0.0, 0.0);
            for _ in 0..count {
                let v = f(&mut rng);
                s += v;
                s2 += v * v;
            }
            let m = s / count as f64;
            (m, ((s2 / count as f64 - m * m) / count as f64).sqrt())
        };
        let (a, sa) = stats(
            &mut |r| {
                light.sample_li(&w, r.pair()).map_or(0.0, |s| {
                    (s.radiance[1] * s.wi.dot(n).max(0.0) / s.pdf) as f64
                })
            },
            5,
        );
        let (b, sb) = stats(
            &mut |r| {
                let d = scotopia_render::sampling::warp::square_to_uniform_sphere(r.pair());
                (light.radiance(&w, d)[1] * d.dot(n).max(0.0)) as f64 * 4.0 * std::f64::consts::PI
            },
            6,
        );
        let se = (sa * sa + sb * sb).sqrt();
        assert!((a - b).abs() < 4.0 * se, "{a} ± {sa} vs {b} ± {sb}");
        // Importance sampling pays: its error is far smaller.
        assert!(sa < 0.5 * sb, "{sa} vs {sb}");
    }

    #[test]
    fn mapping_and_interpolation_follow_mitsuba() {
        // One lit texel (x 2, y 1) of an 8×4 map. Mitsuba 3.9.1 (scalar_rgb)
        // returns 0.975 of the texel's value at (u, v) = (0.3125, 0.325), the
        // texel's centre in u and 0.025 past its row in v (rows at y/(H−1)).
        let mut px = vec![[0.0; 3]; 32];
        px[8 + 2] = [1.0, 1.0, 1.0];
        let env = EnvMapLight::new(8, 4, &px, RgbSpace::Srgb, 1.0, Transform::IDENTITY).unwrap();
        let dir = |u: f32, v: f32| {
            let (t, p) = (v * std::f32::consts::PI, u * 2.0 * std::f32::consts::PI);
            Vec3::new(t.sin() * p.sin(), t.cos(), -t.sin() * p.cos())
        };
        let w = wl();
        let peak = env.radiance(&w, dir(0.3125, 1.0 / 3.0))[0];
        assert!(peak > 0.0);
        let r = env.radiance(&w, dir(0.3125, 0.325))[0] / peak;
        assert!((r - 0.975).abs() < 1e-3, "{r}");
        let r = env.radiance(&w, dir(0.3125 + 0.5 / 8.0, 1.0 / 3.0))[0] / peak;
        assert!((r - 0.5).abs() < 1e-3, "{r}");
        assert_eq!(env.radiance(&w, dir(0.8, 0.9))[0], 0.0);
        // A black map has no power and gives no samples.
        let black = EnvMapLight::new(
            4,
            2,
            &[[0.0; 3]; 8],
            RgbSpace::Srgb,
            1.0,
            Transform::IDENTITY,
        )
        .unwrap();
        assert!(black.sample_li(&w, [0.5, 0.5]).is_none());
        assert_eq!(black.power(1.0).watts, 0.0);
    }
}

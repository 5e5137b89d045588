//! Area lights with a textured radiance: the irradiance next-event
//! estimation finds (points sampled on the light, radiance at their uv)
//! equals the one found by sampling directions and looking the radiance up
//! where the rays hit (what BSDF sampling does), on every shape type; and
//! the light's power is π A times its mean radiance.

mod common;

use std::sync::Arc;

use common::Rng;
use scotopia_color::{SampledWavelengths, Spectrum};
use scotopia_render::geometry::{
    Cylinder, Hit, Planar, PlanarKind, RayShear, Shape, Sphere, TriangleMesh,
};
use scotopia_render::light::{AreaLight, Light, SceneExtent};
use scotopia_render::math::{Frame, Ray, Transform, Vec3};
use scotopia_render::sampling::warp::square_to_cosine_hemisphere;
use scotopia_render::texture::{Checkerboard, Texture, UvTransform};

/// Radiance 1 and 6 on a checkerboard of 2.5 × 2.5 squares per unit of uv.
fn checkerboard() -> Texture {
    Texture::Checkerboard(Arc::new(Checkerboard {
        color0: Texture::constant(1.0),
        color1: Texture::constant(6.0),
        to_uv: UvTransform([2.5, 0.0, 0.0, 0.0, 2.5, 0.0]),
    }))
}

fn wl() -> SampledWavelengths<4> {
    SampledWavelengths::new([450.0, 520.0, 600.0, 680.0], [1.0; 4])
}

/// Mean and standard error of `n` draws of `f`.
fn estimate(n: usize, mut f: impl FnMut() -> f64) -> (f64, f64) {
    let (mut sum, mut sum2) = (0.0, 0.0);
    for _ in 0..n {
        let v = f();
        sum += v;
        sum2 += v * v;
    }
    let mean = sum / n as f64;
    (
        mean,
        ((sum2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt(),
    )
}

/// Irradiance at `p` (normal +z) by next-event estimation.
fn by_light_samples(light: &Light, shapes: &[Shape], p: Vec3, n: usize) -> (f64, f64) {
    let scene = SceneExtent {
        shapes,
        center: Vec3::ZERO,
        radius: 10.0,
        casters: &[],
    };
    let mut rng = Rng(7);
    estimate(n, || {
        light
            .sample_li(&scene, &wl(), p, rng.next(), rng.pair())
            .map_or(0.0, |s| (s.radiance[0] * s.wi.z.max(0.0) / s.pdf) as f64)
    })
}

/// Irradiance at `p` (normal +z) by cosine-weighted directions: π times
/// the mean radiance the rays find where they hit the light.
fn by_directions(light: &AreaLight, shape: &Shape, p: Vec3, n: usize) -> (f64, f64) {
    let mut rng = Rng(8);
    estimate(n, || {
        let ray = Ray::new(p, square_to_cosine_hemisphere(rng.pair()));
        let shear = RayShear::new(&ray);
        let nearest = (0..shape.primitive_count())
            .filter_map(|i| {
                shape
                    .intersect(i, &ray, &shear, f32::INFINITY)
                    .map(|h| (i, h))
            })
            .min_by(|a, b| a.1 .0.total_cmp(&b.1 .0));
        nearest.map_or(0.0, |(prim, (t, uv))| {
            let hit = Hit {
                t,
                shape: 0,
                prim: prim as u32,
                uv,
                instance: None,
            };
            let s = shape.surface(&hit, &ray);
            let l = light.radiance(&wl(), s.uv, s.n_geometric, -ray.d);
            std::f64::consts::PI * l[0] as f64
        })
    })
}

/// The shapes, each with a texture whose placement on it matters to the
/// receiver.
fn shapes() -> Vec<(&'static str, Shape, Texture)> {
    // Above the receiver, facing down (or round, for the sphere and tube).
    let above = Transform::translate(Vec3::new(0.4, -0.3, 1.5))
        .then_after(&Transform::rotate(Vec3::new(1.0, 0.3, 0.0), 160.0).unwrap())
        .then_after(&Transform::scale(Vec3::new(1.2, 0.8, 1.0)).unwrap());
    let quad = TriangleMesh::new(
        vec![
            Vec3::new(-1.0, -1.0, 0.0),
            Vec3::new(1.0, -1.0, 0.0),
            Vec3::new(1.0, 1.0, 0.0),
            Vec3::new(-1.0, 1.0, 0.0),
        ],
        None,
        Some(vec![[0.1, 0.0], [0.9, 0.2], [1.0, 0.8], [0.0, 1.0]]),
        vec![[0, 1, 2], [0, 2, 3]],
        &above,
    )
    .unwrap();
    let frame = Frame::from_normal(Vec3::new(0.3, -0.5, 0.8).normalize());
    vec![
        ("mesh", Shape::Mesh(quad), checkerboard()),
        (
            "rectangle",
            Shape::Planar(Box::new(Planar::new(PlanarKind::Rectangle, above))),
            checkerboard(),
        ),
        (
            "disk",
            Shape::Planar(Box::new(Planar::new(PlanarKind::Disk, above))),
            checkerboard(),
        ),
        (
            "sphere",
            Shape::Sphere(Sphere::oriented(Vec3::new(0.3, 0.2, 1.6), 0.7, frame)),
            checkerboard(),
        ),
        (
            "cylinder",
            Shape::Cylinder(Box::new(
                Cylinder::new(
                    Vec3::new(0.0, 0.0, 1.2),
                    Vec3::new(2.0, 0.5, 1.4),
                    0.4,
                    &Transform::IDENTITY,
                    false,
                )
                .unwrap(),
            )),
            // 1 on the half of the tube nearer p0 (v < ½), 6 beyond.
            Texture::Checkerboard(Arc::new(Checkerboard {
                color0: Texture::constant(1.0),
                color1: Texture::constant(6.0),
                to_uv: UvTransform([0.0, 0.0, 0.25, 0.0, 1.0, 0.0]),
            })),
        ),
    ]
}

#[test]
fn light_samples_and_directions_find_the_same_textured_irradiance() {
    let p = Vec3::new(0.1, 0.05, 0.0);
    for (name, shape, texture) in shapes() {
        let shapes = vec![shape];
        let area = AreaLight::new(0, &shapes[0], texture);
        let light = Light::Area(area.clone());
        let (e_nee, se_nee) = by_light_samples(&light, &shapes, p, 200_000);
        let (e_dir, se_dir) = by_directions(&area, &shapes[0], p, 200_000);
        let se = (se_nee * se_nee + se_dir * se_dir).sqrt();
        assert!(
            (e_nee - e_dir).abs() < 4.0 * se,
            "{name}: light samples {e_nee} ± {se_nee}, directions {e_dir} ± {se_dir}"
        );
        // The texture matters here: a uniform light of the mean radiance
        // gives a different irradiance (so the test can fail).
        let mean = area.mean_radiance().eval(550.0);
        let uniform = Light::Area(AreaLight::new(0, &shapes[0], Spectrum::Constant(mean)));
        let (e_uniform, se_uniform) = by_light_samples(&uniform, &shapes, p, 200_000);
        assert!(
            (e_nee - e_uniform).abs() > 4.0 * (se_nee * se_nee + se_uniform * se_uniform).sqrt(),
            "{name}: textured {e_nee} ± {se_nee}, uniform {e_uniform} ± {se_uniform}"
        );
    }
}

#[test]
fn power_and_spectrum_follow_the_mean_radiance_over_the_area() {
    // A rectangle's uv is affine in its area: half of a 1|6 checkerboard
    // of whole squares (to_uv scale 2) has each value, mean 3.5.
    let shape = Shape::Planar(Box::new(Planar::new(
        PlanarKind::Rectangle,
        Transform::scale(Vec3::new(2.0, 0.5, 1.0)).unwrap(),
    )));
    let texture = Texture::Checkerboard(Arc::new(Checkerboard {
        color0: Texture::constant(1.0),
        color1: Texture::constant(6.0),
        to_uv: UvTransform([2.0, 0.0, 0.0, 0.0, 2.0, 0.0]),
    }));
    let area = AreaLight::new(0, &shape, texture);
    for l in [400.0, 555.0, 700.0] {
        let m = area.mean_radiance().eval(l);
        // 4096 lattice points: each half holds its share to ~1/64.
        assert!((m - 3.5).abs() < 0.1, "mean {m} at {l} nm");
    }
    let uniform = AreaLight::new(0, &shape, Spectrum::Constant(3.5));
    let (p, q) = (area.power(), uniform.power());
    assert!((p.watts / q.watts - 1.0).abs() < 0.03, "{p:?} vs {q:?}");
    // On a sphere the area weighting is sin θ (v = θ/π): a band of 4
    // where v ∈ (¼, ¾) and 0 elsewhere covers half of uv but cos 45° of
    // the area, so its mean is 4 cos 45° ≈ 2.83, not 2.
    let sphere = Shape::Sphere(Sphere::new(Vec3::ZERO, 1.0));
    let band = Texture::Checkerboard(Arc::new(Checkerboard {
        color0: Texture::constant(4.0),
        color1: Texture::constant(0.0),
        // (u, v) ↦ (¾, v + ¼): the first colour where v + ¼ mod 1 > ½.
        to_uv: UvTransform([0.0, 0.0, 0.75, 0.0, 1.0, 0.25]),
    }));
    let m = AreaLight::new(0, &sphere, band).mean_radiance().eval(555.0);
    let want = 4.0 * std::f32::consts::FRAC_1_SQRT_2;
    assert!((m - want).abs() < 0.05, "sphere mean {m}, want {want}");
}

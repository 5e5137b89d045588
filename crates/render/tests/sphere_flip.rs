//! Spheres with `flip_normals`: normals inwards, and as an area light
//! they light their inside only.

mod common;

use common::Rng;
use scotopia_color::{SampledWavelengths, Spectrum};
use scotopia_render::geometry::{Hit, RayShear, Shape, Sphere};
use scotopia_render::light::{AreaLight, Light, SceneExtent};
use scotopia_render::math::{Ray, Vec3};

#[test]
fn a_flipped_sphere_faces_and_emits_inwards() {
    let sphere = Sphere::new(Vec3::new(1.0, 2.0, 3.0), 2.0).with_flipped_normals(true);
    let shapes = vec![Shape::Sphere(sphere)];
    // From inside, the hit's normal points back at the centre.
    let ray = Ray::new(sphere.center, Vec3::new(0.0, 0.0, 1.0));
    let (t, uv) = shapes[0]
        .intersect(0, &ray, &RayShear::new(&ray), f32::INFINITY)
        .unwrap();
    let s = shapes[0].surface(
        &Hit {
            t,
            shape: 0,
            prim: 0,
            uv,
            instance: None,
        },
        &ray,
    );
    assert!((t - 2.0).abs() < 1e-5 && s.n_geometric.z < -0.9999, "{s:?}");
    // At the centre, a receiver sees L over its hemisphere: E = π L.
    let l = 2.5f32;
    let light = Light::Area(AreaLight::new(0, &shapes[0], Spectrum::Constant(l)));
    let extent = SceneExtent {
        shapes: &shapes,
        center: sphere.center,
        radius: 10.0,
        casters: &[],
    };
    let w = SampledWavelengths::<4>::sample_uniform(0.5);
    let normal = Vec3::new(0.6, 0.0, 0.8);
    let mut rng = Rng(9);
    let n = 100_000;
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let v = light
            .sample_li(&extent, &w, sphere.center, rng.next(), rng.pair())
            .map_or(0.0, |s| {
                (s.radiance[0] * s.wi.dot(normal).max(0.0) / s.pdf) as f64
            });
        sum += v;
        sum2 += v * v;
    }
    let mean = sum / n as f64;
    let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
    let want = std::f64::consts::PI * l as f64;
    assert!((mean - want).abs() < 4.0 * se, "{mean} ± {se} vs {want}");
    // From outside nothing it emits reaches the point.
    let outside = sphere.center + Vec3::new(5.0, 0.0, 0.0);
    for _ in 0..1000 {
        let s = light.sample_li(&extent, &w, outside, rng.next(), rng.pair());
        assert!(
            s.is_none_or(|s| s.radiance[0] == 0.0 || s.pdf == 0.0),
            "{s:?}"
        );
    }
}

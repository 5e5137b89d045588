//! Surfaces light passes through: a `null` plane changes nothing in
//! either tracer's image; a `mask` of opacity o in front of a light lets
//! 1 − o of it through. And a normal-mapped floor, whose BSDF is not
//! reciprocal, renders alike in the path tracer and the bidirectional
//! one (which reads it in the adjoint direction). Each check is a z-test on the per-pixel
//! differences between two renders, so the image's own structure cancels
//! and the standard error is the noise alone.

use std::sync::atomic::AtomicBool;

use scotopia_color::{cie, Spectrum};
use scotopia_render::accel::Aggregate;
use std::sync::Arc;

use scotopia_render::bsdf::{Bsdf, Diffuse, Mask, NormalMap, Null};
use scotopia_render::camera::{Camera, FovAxis};
use scotopia_render::geometry::{Planar, PlanarKind, Shape};
use scotopia_render::integrator::{render, BdptStrategy, RenderOptions};
use scotopia_render::light::{AreaLight, Light};
use scotopia_render::math::{Transform, Vec3};
use scotopia_render::scene::{Filter, IntegratorKind, IntegratorSettings, Scene};
use scotopia_render::texture::{FloatTexture, RgbBitmap, Texture};

/// Standard errors a difference may lie from zero (two-sided p ≈ 6e-5).
const Z: f64 = 4.0;

fn camera(origin: Vec3, target: Vec3, up: Vec3, fov: f32) -> Camera {
    let t = Transform::look_at(origin, target, up).unwrap();
    Camera::new(t, 8, 8, fov, FovAxis::X, 1e-3, 1e4, 0.0, 1.0).unwrap()
}

/// A rectangle of half-sides `half` centred at `centre`, its normal +z
/// (or −z when `down`).
fn rectangle(centre: Vec3, half: f32, down: bool) -> Shape {
    let flip = if down {
        Transform::rotate(Vec3::new(1.0, 0.0, 0.0), 180.0).unwrap()
    } else {
        Transform::IDENTITY
    };
    let t = Transform::translate(centre)
        .then_after(&flip)
        .then_after(&Transform::scale(Vec3::new(half, half, 1.0)).unwrap());
    Shape::Planar(Box::new(Planar::new(PlanarKind::Rectangle, t)))
}

fn radiance() -> Spectrum {
    cie::illuminant("d65").unwrap().scaled(0.02)
}

/// A grey floor (z = 0) lit by a square light at z = 2 facing down, seen
/// from the side (the light itself out of view), with `filter` (if any) as a wide plane at z = 1 between
/// them — every shadow ray from the floor to the light crosses it.
fn lit_floor(filter: Option<Bsdf>) -> Scene {
    let mut shapes = vec![
        rectangle(Vec3::ZERO, 2.0, false),
        rectangle(Vec3::new(0.0, 0.0, 2.0), 0.5, true),
    ];
    let mut materials = vec![
        Bsdf::Diffuse(Diffuse {
            reflectance: Texture::constant(0.5),
        }),
        Bsdf::Diffuse(Diffuse {
            reflectance: Texture::constant(0.0),
        }),
    ];
    if let Some(f) = filter {
        shapes.push(rectangle(Vec3::new(0.0, 0.0, 1.0), 2.0, false));
        materials.push(f);
    }
    let n = shapes.len();
    let light = Light::Area(AreaLight::new(1, &shapes[1], radiance()));
    Scene {
        meter: None,
        media: Vec::new(),
        shape_media: Vec::new(),
        camera_medium: None,
        camera: camera(
            Vec3::new(0.0, -3.0, 0.8),
            Vec3::ZERO,
            Vec3::new(0.0, 0.0, 1.0),
            50.0,
        ),
        filter: Filter::Box,
        samples_per_pixel: 1,
        integrator: IntegratorSettings {
            kind: IntegratorKind::Path,
            max_depth: -1,
            rr_depth: 5,
            aim_at_casters: true,
            media: false,
        },
        geometry: Aggregate::new(shapes),
        materials,
        shape_material: (0..n as u32).collect(),
        shape_light: (0..n).map(|i| (i == 1).then_some(0)).collect(),
        lights: vec![light],
        warnings: vec![],
    }
}

/// A square light at z = 1 facing down, filling the view of a camera at
/// the origin looking up, with `filter` (if any) at z = 0.5.
fn light_overhead(filter: Option<Bsdf>) -> Scene {
    let mut shapes = vec![rectangle(Vec3::new(0.0, 0.0, 1.0), 2.0, true)];
    let mut materials = vec![Bsdf::Diffuse(Diffuse {
        reflectance: Texture::constant(0.0),
    })];
    if let Some(f) = filter {
        shapes.push(rectangle(Vec3::new(0.0, 0.0, 0.5), 2.0, true));
        materials.push(f);
    }
    let n = shapes.len();
    let light = Light::Area(AreaLight::new(0, &shapes[0], radiance()));
    Scene {
        meter: None,
        media: Vec::new(),
        shape_media: Vec::new(),
        camera_medium: None,
        camera: camera(
            Vec3::ZERO,
            Vec3::new(0.0, 0.0, 1.0),
            Vec3::new(0.0, 1.0, 0.0),
            40.0,
        ),
        filter: Filter::Box,
        samples_per_pixel: 1,
        integrator: IntegratorSettings {
            kind: IntegratorKind::Path,
            max_depth: -1,
            rr_depth: 5,
            aim_at_casters: true,
            media: false,
        },
        geometry: Aggregate::new(shapes),
        materials,
        shape_material: (0..n as u32).collect(),
        shape_light: (0..n).map(|i| (i == 0).then_some(0)).collect(),
        lights: vec![light],
        warnings: vec![],
    }
}

/// Per-pixel luminance Y.
fn luminance(scene: &Scene, integrator: IntegratorKind, spp: u32, seed: u32) -> Vec<f64> {
    luminance_with(scene, integrator, None, spp, seed)
}

/// The same, with one bidirectional strategy alone if given.
fn luminance_with(
    scene: &Scene,
    integrator: IntegratorKind,
    only_strategy: Option<BdptStrategy>,
    spp: u32,
    seed: u32,
) -> Vec<f64> {
    let options = RenderOptions {
        spp: Some(spp),
        seed,
        integrator: Some(integrator),
        only_strategy,
        ..RenderOptions::default()
    };
    let r = render(scene, &options, &AtomicBool::new(false), &|_, _| {}).unwrap();
    assert_eq!((r.nonfinite, r.nonfinite_splats), (0, 0));
    r.film.xyzv().iter().map(|p| p[1] as f64).collect()
}

/// Mean and standard error of a − k·b over the pixels.
fn difference(a: &[f64], b: &[f64], k: f64) -> (f64, f64) {
    let d: Vec<f64> = a.iter().zip(b).map(|(x, y)| x - k * y).collect();
    let n = d.len() as f64;
    let m = d.iter().sum::<f64>() / n;
    let var = d.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

fn mean(v: &[f64]) -> f64 {
    v.iter().sum::<f64>() / v.len() as f64
}

fn null() -> Bsdf {
    Bsdf::Null(Null::default())
}

#[test]
fn a_null_plane_between_light_and_floor_changes_nothing() {
    for integrator in [IntegratorKind::Path, IntegratorKind::Bdpt] {
        let spp = 1024;
        let plain = luminance(&lit_floor(None), integrator, spp, 1);
        let through = luminance(&lit_floor(Some(null())), integrator, spp, 2);
        let (d, se) = difference(&through, &plain, 1.0);
        assert!(
            d.abs() <= Z * se,
            "{integrator:?}: {d} ± {se} (mean {})",
            mean(&plain)
        );
        // The test can fail: the noise is far below the light's share.
        assert!(se < 0.03 * mean(&plain), "{integrator:?}: {se}");
        // An opaque black plane in its place takes all the direct light.
        let blocked = luminance(
            &lit_floor(Some(Bsdf::Diffuse(Diffuse {
                reflectance: Texture::constant(0.0),
            }))),
            integrator,
            16,
            3,
        );
        assert!(
            mean(&blocked) < 0.01 * mean(&plain),
            "{integrator:?}: blocked {} vs {}",
            mean(&blocked),
            mean(&plain)
        );
    }
}

#[test]
fn a_light_seen_through_a_null_plane_is_unchanged() {
    let plain = luminance(&light_overhead(None), IntegratorKind::Path, 16, 1);
    let through = luminance(&light_overhead(Some(null())), IntegratorKind::Path, 16, 1);
    let (d, se) = difference(&through, &plain, 1.0);
    assert!(d.abs() <= Z * se + 1e-6 * mean(&plain), "{d} ± {se}");
}

#[test]
fn a_mask_of_opacity_three_tenths_transmits_seven_tenths() {
    let black = Bsdf::Diffuse(Diffuse {
        reflectance: Texture::constant(0.0),
    });
    let mask = Bsdf::Mask(Box::new(Mask {
        opacity: FloatTexture::Constant(0.3),
        inner: black,
    }));
    for integrator in [IntegratorKind::Path, IntegratorKind::Bdpt] {
        let plain = luminance(&light_overhead(None), integrator, 64, 1);
        let masked = luminance(&light_overhead(Some(mask.clone())), integrator, 64, 2);
        let (d, se) = difference(&masked, &plain, 0.7);
        assert!(
            d.abs() <= Z * se,
            "{integrator:?}: {d} ± {se} (light {})",
            mean(&plain)
        );
        // Sharp enough to tell 0.7 from 0.65 or 0.75.
        assert!(Z * se < 0.05 * mean(&plain), "{integrator:?}: {se}");
    }
}

#[test]
fn a_normal_mapped_floor_renders_alike_in_both_tracers() {
    // A normal tilted 25° towards +v (world +y, away from the camera:
    // a tilt along x would cancel between the image's halves), over a
    // grey floor.
    let t = 25.0f32.to_radians();
    let c = [0.5, (t.sin() + 1.0) / 2.0, (t.cos() + 1.0) / 2.0];
    let mut scene = lit_floor(None);
    scene.materials[0] = Bsdf::NormalMap(Box::new(NormalMap {
        normals: Arc::new(RgbBitmap::new(1, 1, vec![c]).unwrap()),
        inner: Bsdf::Diffuse(Diffuse {
            reflectance: Texture::constant(0.5),
        }),
        flip_invalid_normals: true,
        use_shadowing_function: true,
    }));
    let path = luminance(&scene, IntegratorKind::Path, 1024, 4);
    let bdpt = luminance(&scene, IntegratorKind::Bdpt, 1024, 5);
    let (d, se) = difference(&bdpt, &path, 1.0);
    assert!(d.abs() <= Z * se, "{d} ± {se} (mean {})", mean(&path));
    assert!(se < 0.03 * mean(&path), "{se}");
    // Light tracing alone (s = 2, t = 1) reads the map only in the
    // adjoint direction (without the shading-normal ratio the wrapper
    // applies for importance, it lands some 4 standard errors off; with
    // the flip decided by the light's side, at less than half the image).
    let traced = luminance_with(
        &scene,
        IntegratorKind::Bdpt,
        BdptStrategy::new(2, 1).ok(),
        1024,
        7,
    );
    let (d, se) = difference(&traced, &path, 1.0);
    assert!(
        d.abs() <= Z * se,
        "light tracing: {d} ± {se} (mean {})",
        mean(&path)
    );
    assert!(se < 0.03 * mean(&path), "{se}");
}

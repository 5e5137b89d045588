//! Furnace tests of the path tracer against analytic answers, for every
//! wavelength strategy: a white sphere vanishes under a uniform sky; a
//! coloured one shows ρ·L; inside an emitting diffuse sphere the camera
//! sees L_e / (1 − ρ).

use std::sync::atomic::AtomicBool;

use scotopia_color::photometry::spectrum_to_xyzv;
use scotopia_color::{cie, Spectrum, Tabulated};
use scotopia_render::accel::Aggregate;
use scotopia_render::bsdf::{Bsdf, Dielectric, Diffuse, Ior};
use scotopia_render::camera::{Camera, FovAxis};
use scotopia_render::geometry::{Shape, Sphere, TriangleMesh};
use scotopia_render::integrator::{render, RenderOptions};
use scotopia_render::light::{AreaLight, ConstantLight, Light};
use scotopia_render::math::{Transform, Vec3};
use scotopia_render::scene::{Filter, IntegratorSettings, Scene};
use scotopia_render::texture::Texture;
use scotopia_render::wavelength::WavelengthStrategy;

fn camera(origin: Vec3, target: Vec3, fov: f32) -> Camera {
    let t = Transform::look_at(origin, target, Vec3::new(0.0, 1.0, 0.0)).unwrap();
    Camera::new(t, 8, 8, fov, FovAxis::X, 1e-3, 1e4, 0.0, 1.0).unwrap()
}

fn scene(
    camera: Camera,
    shapes: Vec<Shape>,
    albedo: Spectrum,
    lights: Vec<Light>,
    light_of: Vec<Option<u32>>,
) -> Scene {
    let n = shapes.len();
    Scene {
        camera,
        filter: Filter::Box,
        samples_per_pixel: 64,
        integrator: IntegratorSettings {
            max_depth: -1,
            rr_depth: 5,
        },
        geometry: Aggregate::new(shapes),
        materials: vec![Bsdf::Diffuse(Diffuse {
            reflectance: Texture::Constant(albedo),
        })],
        shape_material: vec![0; n],
        shape_light: light_of,
        lights,
        warnings: vec![],
    }
}

/// Mean X, Y, Z, V′ over the pixels, and the standard error from the
/// spread of per-pixel means.
fn mean_and_se(scene: &Scene, strategy: WavelengthStrategy, spp: u32) -> [(f64, f64); 4] {
    let options = RenderOptions {
        spp: Some(spp),
        strategy,
        seed: 3,
        ..RenderOptions::default()
    };
    let r = render(scene, &options, &AtomicBool::new(false), &|_, _| {}).unwrap();
    assert_eq!(r.nonfinite, 0);
    let px = r.film.xyzv();
    let n = px.len() as f64;
    std::array::from_fn(|c| {
        let m = px.iter().map(|p| p[c] as f64).sum::<f64>() / n;
        let var = px.iter().map(|p| (p[c] as f64 - m).powi(2)).sum::<f64>() / (n - 1.0);
        (m, (var / n).sqrt())
    })
}

fn check(name: &str, got: [(f64, f64); 4], want: [f64; 4], slack: f64) {
    for c in 0..4 {
        let (m, se) = got[c];
        assert!(
            (m - want[c]).abs() <= 4.0 * se + slack * want[c],
            "{name}, channel {c}: {m} ± {se} vs {}",
            want[c]
        );
    }
}

fn xyzv(s: &Spectrum) -> [f64; 4] {
    let e = spectrum_to_xyzv(s);
    [e.x, e.y, e.z, e.v]
}

fn sky() -> Spectrum {
    cie::illuminant("d65").unwrap().scaled(0.01)
}

#[test]
fn a_white_sphere_vanishes_under_a_uniform_sky() {
    let sphere = Shape::Sphere(Sphere {
        center: Vec3::ZERO,
        radius: 1.0,
    });
    // The camera sees only the sphere.
    let cam = camera(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 10.0);
    let lights = vec![Light::Constant(ConstantLight { radiance: sky() })];
    let s = scene(
        cam,
        vec![sphere],
        Spectrum::Constant(1.0),
        lights,
        vec![None],
    );
    for strategy in WavelengthStrategy::ALL {
        // Every pixel is exactly the sky (up to roulette's noise).
        check(
            strategy.name(),
            mean_and_se(&s, strategy, 64),
            xyzv(&sky()),
            1e-3,
        );
    }
}

#[test]
fn a_coloured_sphere_shows_albedo_times_sky() {
    let albedo = Spectrum::tabulated(
        Tabulated::new(vec![400.0, 500.0, 600.0, 700.0], vec![0.1, 0.7, 0.3, 0.5]).unwrap(),
    );
    let sphere = Shape::Sphere(Sphere {
        center: Vec3::ZERO,
        radius: 1.0,
    });
    let cam = camera(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 10.0);
    // A convex sphere sees only the sky: one bounce, ρ·L exactly.
    let lights = vec![Light::Constant(ConstantLight { radiance: sky() })];
    let s = scene(cam, vec![sphere], albedo.clone(), lights, vec![None]);
    let product = Spectrum::tabulated(Tabulated::from_fn(360.0, 830.0, 1.0, |l| {
        albedo.eval(l) * sky().eval(l)
    }));
    for strategy in WavelengthStrategy::ALL {
        check(
            strategy.name(),
            mean_and_se(&s, strategy, 64),
            xyzv(&product),
            1e-3,
        );
    }
}

/// A cube [−1, 1]³ whose triangles face inwards.
fn inward_cube() -> Shape {
    let p: Vec<Vec3> = (0..8)
        .map(|i| {
            let c = |b: u32| if i & b != 0 { 1.0 } else { -1.0 };
            Vec3::new(c(1), c(2), c(4))
        })
        .collect();
    // Quads as corner indices, wound so the normal points into the cube.
    let quads = [
        [0, 1, 3, 2], // z = −1
        [4, 6, 7, 5], // z = +1
        [0, 4, 5, 1], // y = −1
        [2, 3, 7, 6], // y = +1
        [0, 2, 6, 4], // x = −1
        [1, 5, 7, 3], // x = +1
    ];
    let indices = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    Shape::Mesh(TriangleMesh::new(p, None, None, indices, &Transform::IDENTITY).unwrap())
}

#[test]
fn inside_an_emitting_enclosure_the_radiance_is_le_over_one_minus_rho() {
    // Every point of a closed diffuse enclosure that emits L_e and reflects
    // ρ sees L = L_e + ρ L, so L = L_e / (1 − ρ) everywhere.
    let le = cie::illuminant("a").unwrap().scaled(0.003);
    let rho = Spectrum::tabulated(
        Tabulated::new(vec![380.0, 550.0, 780.0], vec![0.3, 0.6, 0.45]).unwrap(),
    );
    let cube = inward_cube();
    if let Shape::Mesh(m) = &cube {
        // The inward winding: the −z face's normal is +z.
        let (a, b, c) = m.vertices(0);
        assert!((b - a).cross(c - a).z > 0.0);
    }
    let light = Light::Area(AreaLight::new(0, &cube, le.clone()));
    let cam = camera(Vec3::new(0.2, -0.1, 0.3), Vec3::new(0.5, 0.4, -1.0), 60.0);
    let s = scene(cam, vec![cube], rho.clone(), vec![light], vec![Some(0)]);
    let want = Spectrum::tabulated(Tabulated::from_fn(360.0, 830.0, 1.0, |l| {
        le.eval(l) / (1.0 - rho.eval(l))
    }));
    for strategy in WavelengthStrategy::ALL {
        check(
            strategy.name(),
            mean_and_se(&s, strategy, 128),
            xyzv(&want),
            2e-3,
        );
    }
}

#[test]
fn a_dispersive_glass_sphere_vanishes_under_a_uniform_sky() {
    // A lossless dielectric in a uniform radiance field is invisible, even
    // when it disperses: the collapsed cluster must stay unbiased (a
    // survivor always drawn from the bluest stratum would tint it).
    let sphere = Shape::Sphere(Sphere {
        center: Vec3::ZERO,
        radius: 1.0,
    });
    let cam = camera(Vec3::new(0.0, 0.0, 4.0), Vec3::ZERO, 10.0);
    let lights = vec![Light::Constant(ConstantLight { radiance: sky() })];
    let mut s = scene(
        cam,
        vec![sphere],
        Spectrum::Constant(1.0),
        lights,
        vec![None],
    );
    let dispersive =
        Spectrum::tabulated(Tabulated::new(vec![360.0, 830.0], vec![1.75, 1.45]).unwrap());
    s.materials = vec![Bsdf::Dielectric(Dielectric {
        ior: Ior {
            interior: dispersive,
            exterior: Spectrum::Constant(1.0),
        },
        specular_reflectance: Texture::constant(1.0),
        specular_transmittance: Texture::constant(1.0),
    })];
    for strategy in WavelengthStrategy::ALL {
        check(
            strategy.name(),
            mean_and_se(&s, strategy, 256),
            xyzv(&sky()),
            2e-3,
        );
    }
}

#[test]
fn one_or_two_threads_give_the_same_bits() {
    let cube = inward_cube();
    let light = Light::Area(AreaLight::new(0, &cube, Spectrum::Constant(0.1)));
    let cam = camera(Vec3::new(0.2, -0.1, 0.3), Vec3::new(0.5, 0.4, -1.0), 60.0);
    let s = scene(
        cam,
        vec![cube],
        Spectrum::Constant(0.7),
        vec![light],
        vec![Some(0)],
    );
    let options = RenderOptions {
        spp: Some(8),
        seed: 11,
        ..RenderOptions::default()
    };
    let run = |threads| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| render(&s, &options, &AtomicBool::new(false), &|_, _| {}).unwrap())
    };
    assert_eq!(run(1).film, run(2).film);
    // A different seed is a different image.
    let other = RenderOptions {
        seed: 12,
        ..options.clone()
    };
    let b = render(&s, &other, &AtomicBool::new(false), &|_, _| {}).unwrap();
    assert_ne!(run(1).film, b.film);
}

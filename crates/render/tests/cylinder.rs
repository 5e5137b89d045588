//! Cylinders: ray hits against the analytic tube, Mitsuba's UVs, area
//! sampling's density, and the power of an emitting cylinder.

mod common;

use common::Rng;
use scotopia_color::{SampledWavelengths, Spectrum};
use scotopia_render::accel::Aggregate;
use scotopia_render::geometry::{Cylinder, Hit, Shape};
use scotopia_render::light::{AreaLight, Light, SceneExtent};
use scotopia_render::math::{Ray, Transform, Vec3};
use scotopia_render::sampling::warp::square_to_uniform_sphere;

/// A tilted, moved cylinder: axis from `p0` along `axis` (unit) for
/// `length`, radius `r` (world space), built through a rotating and
/// translating `to_world`.
struct Tube {
    shape: Shape,
    p0: Vec3,
    axis: Vec3,
    length: f32,
    r: f32,
}

fn tube(flip: bool) -> Tube {
    let to_world = Transform::translate(Vec3::new(0.5, -1.0, 2.0))
        .then_after(&Transform::rotate(Vec3::new(1.0, 2.0, 0.5), 40.0).unwrap())
        .then_after(&Transform::scale(Vec3::splat(2.0)).unwrap());
    let (p0, p1, r) = (Vec3::new(0.2, 0.1, -0.5), Vec3::new(-0.3, 0.4, 0.7), 0.3);
    let c = Cylinder::new(p0, p1, r, &to_world, flip).unwrap();
    let w0 = to_world.point(p0);
    let d = to_world.point(p1) - w0;
    Tube {
        shape: Shape::Cylinder(Box::new(c)),
        p0: w0,
        axis: d.normalize(),
        length: d.length(),
        r: 2.0 * r,
    }
}

/// The analytic hits of the infinite tube around the axis, in f64, kept
/// where they lie between the ends: |(q − p0) − ((q − p0)·a) a|² = r².
fn analytic_hits(t: &Tube, ray: &Ray) -> Vec<f64> {
    let f = |v: Vec3| [v.x as f64, v.y as f64, v.z as f64];
    let (o, d, a, p0) = (f(ray.o), f(ray.d), f(t.axis), f(t.p0));
    let dot = |x: [f64; 3], y: [f64; 3]| x[0] * y[0] + x[1] * y[1] + x[2] * y[2];
    let perp = |v: [f64; 3]| {
        let s = dot(v, a);
        [v[0] - s * a[0], v[1] - s * a[1], v[2] - s * a[2]]
    };
    let op = perp([o[0] - p0[0], o[1] - p0[1], o[2] - p0[2]]);
    let dp = perp(d);
    let (qa, qb, qc) = (
        dot(dp, dp),
        2.0 * dot(op, dp),
        dot(op, op) - (t.r as f64).powi(2),
    );
    let disc = qb * qb - 4.0 * qa * qc;
    if disc < 0.0 || qa == 0.0 {
        return vec![];
    }
    let mut hits = vec![];
    for s in [-1.0, 1.0] {
        let h = (-qb + s * disc.sqrt()) / (2.0 * qa);
        let q = [o[0] + h * d[0], o[1] + h * d[1], o[2] + h * d[2]];
        let z = dot([q[0] - p0[0], q[1] - p0[1], q[2] - p0[2]], a);
        if h > 0.0 && (0.0..=t.length as f64).contains(&z) {
            hits.push(h);
        }
    }
    hits
}

#[test]
fn hits_match_the_analytic_tube_from_outside_inside_and_through_the_ends() {
    let t = tube(false);
    let agg = Aggregate::new(vec![t.shape.clone()]);
    let centre = t.p0 + t.axis * (0.5 * t.length);
    let mut rng = Rng(3);
    let (mut hits, mut far_hits, mut inside) = (0, 0, 0);
    for i in 0..20_000 {
        // Origins around the tube, some inside it; directions uniform.
        let o = if i % 4 == 0 {
            // Inside: on the axis between the ends.
            t.p0 + t.axis * (t.length * rng.next())
        } else {
            centre + square_to_uniform_sphere(rng.pair()) * (3.0 * t.r + 3.0 * rng.next())
        };
        let ray = Ray::new(o, square_to_uniform_sphere(rng.pair()));
        let want = analytic_hits(&t, &ray);
        let got = agg.intersect(&ray);
        match (want.first(), got) {
            (None, None) => {}
            (Some(&w), Some(h)) => {
                let scale = 1.0 + w.abs();
                assert!(
                    (h.t as f64 - w).abs() < 1e-4 * scale,
                    "ray {ray:?}: t {} vs {w}",
                    h.t
                );
                hits += 1;
                far_hits += usize::from(want.len() == 1);
                let s = t.shape.surface(&h, &ray);
                // On the tube, the normal radial and outward.
                let q = s.p - t.p0;
                let radial = q - t.axis * q.dot(t.axis);
                assert!((radial.length() / t.r - 1.0).abs() < 1e-4, "{s:?}");
                assert!(s.n_geometric.dot(radial.normalize()) > 0.9999, "{s:?}");
                if i % 4 == 0 {
                    inside += 1;
                    assert!(s.n_geometric.dot(ray.d) > 0.0);
                }
            }
            (w, g) => {
                // Grazing rays may differ at the rounding of the ends or the
                // silhouette: accept only those.
                let w = w.copied().or(g.map(|h| h.t as f64)).unwrap();
                let q = ray.at(w as f32) - t.p0;
                let z = q.dot(t.axis) / t.length;
                let end = z.abs() < 1e-4 || (z - 1.0).abs() < 1e-4;
                // The ray's closest approach to the axis line.
                let n = ray.d.cross(t.axis).normalize();
                let silhouette = ((ray.o - t.p0).dot(n).abs() / t.r - 1.0).abs() < 1e-4;
                assert!(end || silhouette, "ray {ray:?}: analytic {w:?}, got {g:?}");
            }
        }
    }
    // The cases were exercised: hits from outside, from inside, and far
    // hits through an open end or from inside.
    assert!(
        hits > 2000 && inside > 1000 && far_hits > 1000,
        "{hits} {inside} {far_hits}"
    );
    // t_max is respected.
    let ray = Ray::new(centre, t.axis.cross(Vec3::new(0.0, 0.0, 1.0)).normalize());
    let h = agg.intersect(&ray).unwrap();
    let short = Ray {
        t_max: h.t * 0.999,
        ..ray
    };
    assert!(agg.intersect(&short).is_none());
}

#[test]
fn uvs_and_normals_as_mitsuba() {
    // The default cylinder: axis z from 0 to 1, radius 1; u = φ/2π, v = z.
    let c = Shape::Cylinder(Box::new(
        Cylinder::new(
            Vec3::ZERO,
            Vec3::new(0.0, 0.0, 1.0),
            1.0,
            &Transform::IDENTITY,
            false,
        )
        .unwrap(),
    ));
    let ray = Ray::new(Vec3::new(0.0, 5.0, 0.25), Vec3::new(0.0, -1.0, 0.0));
    let (t, uv) = c
        .intersect(
            0,
            &ray,
            &scotopia_render::geometry::RayShear::new(&ray),
            100.0,
        )
        .unwrap();
    let hit = Hit {
        t,
        shape: 0,
        prim: 0,
        uv,
        instance: None,
    };
    let s = c.surface(&hit, &ray);
    assert!((t - 4.0).abs() < 1e-6);
    assert!(
        (s.uv[0] - 0.25).abs() < 1e-6 && (s.uv[1] - 0.25).abs() < 1e-6,
        "{s:?}"
    );
    assert!((s.n_geometric - Vec3::new(0.0, 1.0, 0.0)).length() < 1e-6);
    // Flipped: the normal points to the axis.
    let f = Shape::Cylinder(Box::new(
        Cylinder::new(
            Vec3::ZERO,
            Vec3::new(0.0, 0.0, 1.0),
            1.0,
            &Transform::IDENTITY,
            true,
        )
        .unwrap(),
    ));
    assert!((f.surface(&hit, &ray).n_geometric - Vec3::new(0.0, -1.0, 0.0)).length() < 1e-6);
    // Bounds hold the two end circles.
    let b = c.bounds(0);
    assert!((b.min - Vec3::new(-1.0, -1.0, 0.0)).length() < 1e-4);
    assert!((b.max - Vec3::new(1.0, 1.0, 1.0)).length() < 1e-4);
    // Area 2π r l, with the transform's scale.
    assert!((c.area() - 2.0 * std::f32::consts::PI).abs() < 1e-5);
    let t = tube(false);
    let want = 2.0 * std::f32::consts::PI * t.r * t.length;
    assert!((t.shape.area() / want - 1.0).abs() < 1e-5);
}

#[test]
fn area_samples_lie_on_the_tube_and_cover_it_uniformly() {
    let t = tube(true);
    let mut rng = Rng(11);
    let n = 40_000;
    // Counts in 4 × 4 cells of (height along the axis, angle around it).
    let mut cells = [0usize; 16];
    let e1 = t.axis.cross(Vec3::new(0.3, 0.1, 0.9)).normalize();
    let e2 = t.axis.cross(e1);
    for _ in 0..n {
        let s = t.shape.sample_area(None, rng.next(), rng.pair()).unwrap();
        let q = s.p - t.p0;
        let z = q.dot(t.axis) / t.length;
        let radial = q - t.axis * q.dot(t.axis);
        assert!((radial.length() / t.r - 1.0).abs() < 1e-4);
        assert!((-1e-5..=1.0 + 1e-5).contains(&z));
        // Flipped: normals inwards.
        assert!(s.n.dot(radial.normalize()) < -0.9999);
        let phi = radial
            .dot(e2)
            .atan2(radial.dot(e1))
            .rem_euclid(std::f32::consts::TAU);
        let (i, j) = (
            ((z * 4.0) as usize).min(3),
            ((phi / std::f32::consts::TAU * 4.0) as usize).min(3),
        );
        cells[4 * i + j] += 1;
    }
    // Chi-square against uniform, 15 degrees of freedom: the 99.9 %
    // quantile is 37.7.
    let expected = n as f64 / 16.0;
    let chi2: f64 = cells
        .iter()
        .map(|&c| (c as f64 - expected).powi(2) / expected)
        .sum();
    assert!(chi2 < 37.7, "chi² = {chi2}, cells {cells:?}");
}

#[test]
fn an_emitting_cylinder_radiates_pi_area_radiance_through_an_enclosing_sphere() {
    // Its outside emits outwards and nothing it emits comes back to it, so
    // the flux through a sphere around it is Φ = π A L. Estimated from the
    // light's own sampling (its pdf) at points uniform on the sphere, with
    // the receiver facing inwards: Φ = 4πR² E[L cos θ / pdf].
    let t = tube(false);
    let shapes = vec![t.shape.clone()];
    let l = 1.5f32;
    let light = Light::Area(AreaLight::new(0, &shapes[0], Spectrum::Constant(l)));
    let centre = t.p0 + t.axis * (0.5 * t.length);
    let big = 3.0 * t.length;
    let extent = SceneExtent {
        shapes: &shapes,
        center: centre,
        radius: big,
        casters: &[],
    };
    let w = SampledWavelengths::<4>::sample_uniform(0.5);
    let mut rng = Rng(5);
    let n = 400_000;
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    let Light::Area(area) = &light else {
        unreachable!()
    };
    for _ in 0..n {
        let m = square_to_uniform_sphere(rng.pair());
        let p = centre + m * big;
        let v = light
            .sample_li(&extent, &w, p, rng.next(), rng.pair())
            .map_or(0.0, |s| {
                // The density the light reports for its own sample (away
                // from grazing, where rebuilding the point in f32 loses
                // the cosine's digits).
                let q = p + s.wi * s.distance;
                let pdf = area.pdf_li(p, q, s.n);
                if -s.wi.dot(s.n) > 0.05 {
                    assert!((pdf / s.pdf - 1.0).abs() < 1e-3, "{pdf} vs {}", s.pdf);
                }
                (s.radiance[0] * s.wi.dot(-m).max(0.0) / s.pdf) as f64
            });
        sum += v;
        sum2 += v * v;
    }
    let sphere = 4.0 * std::f64::consts::PI * (big as f64).powi(2);
    let mean = sum / n as f64;
    let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
    let (flux, flux_se) = (sphere * mean, sphere * se);
    let want = std::f64::consts::PI * (t.shape.area() * l) as f64;
    assert!(
        (flux - want).abs() < 4.0 * flux_se,
        "{flux} ± {flux_se} vs {want}"
    );
    // The light's power is the same π A L over 360–830 nm.
    let watts = light.power(&extent).watts;
    assert!((watts / (want * 470.0) - 1.0).abs() < 1e-3, "{watts} W");
}

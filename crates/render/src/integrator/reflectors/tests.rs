//! The reflector density against independent integrals: it integrates
//! to 1 over the sphere, its samples' 1/p sum to the box's solid angle
//! (counted by uniform directions), and a diffuse bounce drawn from the
//! mixture still averages the albedo.

use super::*;
use crate::bsdf::{Diffuse, ShadingPoint};
use crate::math::Frame;
use crate::sampling::splitmix::SplitMix;
use crate::sampling::warp::square_to_uniform_sphere;
use crate::texture::Texture;
use scotopia_color::Spectrum;
use std::f32::consts::PI;

/// A pole-like box (12 triangles), half of them wound inwards, so the
/// outward normals must come from the centre, not the winding.
fn pole(min: Vec3, max: Vec3) -> Vec<[Vec3; 3]> {
    let c = |i: usize| {
        Vec3::new(
            if i & 1 == 0 { min.x } else { max.x },
            if i & 2 == 0 { min.y } else { max.y },
            if i & 4 == 0 { min.z } else { max.z },
        )
    };
    let quads = [
        [0, 1, 3, 2],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 3, 7, 6],
        [0, 2, 6, 4],
        [1, 3, 7, 5],
    ];
    let mut tris = Vec::new();
    for (i, q) in quads.iter().enumerate() {
        let [a, b, cc, d] = q.map(c);
        if i % 2 == 0 {
            tris.push([a, b, cc]);
            tris.push([a, cc, d]);
        } else {
            tris.push([a, cc, b]);
            tris.push([a, d, cc]);
        }
    }
    tris
}

fn street() -> Reflectors {
    let lamps = [Lamp {
        centre: Vec3::new(0.4, 6.7, 0.0),
        watts: 26.0,
    }];
    let meshes = vec![pole(
        Vec3::new(-0.06, 0.0, -0.06),
        Vec3::new(0.06, 6.5, 0.06),
    )];
    let r = Reflectors::from_meshes(&meshes, &lamps);
    assert_eq!(r.len(), 1);
    r
}

/// Mean and standard error.
fn mean_se(xs: &[f64]) -> (f64, f64) {
    let n = xs.len() as f64;
    let m = xs.iter().sum::<f64>() / n;
    let v = xs.iter().map(|x| (x - m).powi(2)).sum::<f64>() / (n - 1.0);
    (m, (v / n).sqrt())
}

#[test]
fn reflector_density_integrates_to_one_over_the_sphere() {
    let r = street();
    let mut rng = SplitMix(7);
    // A point on a wall 1.5 m from the pole and one on the road below it.
    for x in [Vec3::new(1.5, 2.0, 0.3), Vec3::new(0.8, 0.0, -0.5)] {
        let xs: Vec<f64> = (0..400_000)
            .map(|_| {
                let d = square_to_uniform_sphere([rng.next_f32(), rng.next_f32()]);
                (r.pdf_refl(x, d) * 4.0 * PI) as f64
            })
            .collect();
        let (m, se) = mean_se(&xs);
        assert!((m - 1.0).abs() < 4.0 * se, "∫p dω = {m} ± {se} at {x:?}");
    }
}

#[test]
fn sampled_directions_weighted_by_one_over_density_give_the_solid_angle() {
    let r = street();
    let x = Vec3::new(2.0, 1.0, 0.5);
    let mut rng = SplitMix(11);
    // E[1/p] over drawn directions is the solid angle the box covers ...
    let inv: Vec<f64> = (0..200_000)
        .map(|_| {
            let d = r
                .sample_refl(x, rng.next_f32(), [rng.next_f32(), rng.next_f32()])
                .expect("the box faces x");
            1.0 / r.pdf_refl(x, d) as f64
        })
        .collect();
    let (m, se) = mean_se(&inv);
    // ... which uniform directions count independently.
    let b = Aabb {
        min: Vec3::new(-0.06, 0.0, -0.06),
        max: Vec3::new(0.06, 6.5, 0.06),
    };
    let hits: Vec<f64> = (0..2_000_000)
        .map(|_| {
            let d = square_to_uniform_sphere([rng.next_f32(), rng.next_f32()]);
            let inv_d = Vec3::new(1.0 / d.x, 1.0 / d.y, 1.0 / d.z);
            if b.hit(&Ray::new(x, d), inv_d, f32::INFINITY) {
                4.0 * PI as f64
            } else {
                0.0
            }
        })
        .collect();
    let (omega, se_omega) = mean_se(&hits);
    let combined = (se * se + se_omega * se_omega).sqrt();
    assert!(
        (m - omega).abs() < 4.0 * combined,
        "E[1/p] = {m} ± {se}, solid angle {omega} ± {se_omega}"
    );
}

#[test]
fn a_diffuse_bounce_from_the_mixture_averages_the_albedo() {
    let r = street();
    let white = Bsdf::Diffuse(Diffuse {
        reflectance: Texture::Constant(Spectrum::Constant(1.0)),
    });
    let wl = SampledWavelengths::<4>::new([450.0, 500.0, 550.0, 600.0], [1.0; 4]);
    let at = ShadingPoint::from([0.0, 0.0]);
    // The road beside the pole, facing up.
    let x = Vec3::new(0.9, 0.0, 0.2);
    let frame = Frame::from_normal(Vec3::new(0.0, 1.0, 0.0));
    let point = ScatterPoint {
        p: x,
        ng: frame.n,
        frame,
        at,
    };
    let wi = Vec3::new(0.3, 0.0, 0.954).normalize();
    let mut rng = SplitMix(3);
    let mut towards = 0usize;
    let xs: Vec<f64> = (0..400_000)
        .map(|_| {
            let u_lobe = rng.next_f32();
            towards += (u_lobe < SHARE) as usize;
            match r.sample(
                &white,
                &wl,
                &point,
                wi,
                u_lobe,
                [rng.next_f32(), rng.next_f32()],
            ) {
                Some(s) => {
                    // The density next-event estimation would use agrees.
                    let d = frame.to_world(s.wo);
                    let q = r.pdf(&white, x, d, white.pdf(&wl, wi, s.wo));
                    assert!((q - s.pdf).abs() <= 1e-4 * s.pdf, "{q} against {}", s.pdf);
                    s.weight.0[0] as f64
                }
                None => 0.0,
            }
        })
        .collect();
    assert!(towards > 70_000);
    let (m, se) = mean_se(&xs);
    assert!((m - 1.0).abs() < 4.0 * se, "albedo {m} ± {se}");
}

#[test]
fn without_reflectors_the_bsdf_sample_is_unchanged() {
    let none = Reflectors::from_meshes(&[pole(Vec3::ZERO, Vec3::splat(1.0))], &[]);
    assert!(none.is_empty());
    // A lamp far from a small box: it intercepts less than MIN_SHARE.
    let far = Reflectors::from_meshes(
        &[pole(Vec3::ZERO, Vec3::splat(0.01))],
        &[Lamp {
            centre: Vec3::new(0.0, 100.0, 0.0),
            watts: 10.0,
        }],
    );
    assert!(far.is_empty());
    let white = Bsdf::Diffuse(Diffuse {
        reflectance: Texture::Constant(Spectrum::Constant(0.5)),
    });
    let wl = SampledWavelengths::<4>::new([450.0, 500.0, 550.0, 600.0], [1.0; 4]);
    let at = ShadingPoint::from([0.0, 0.0]);
    let frame = Frame::from_normal(Vec3::new(0.0, 0.0, 1.0));
    let wi = Vec3::new(0.0, 0.0, 1.0);
    let point = ScatterPoint {
        p: Vec3::ZERO,
        ng: frame.n,
        frame,
        at,
    };
    let a = none.sample(&white, &wl, &point, wi, 0.1, [0.3, 0.7]);
    let b = white.sample(&wl, at, wi, 0.1, [0.3, 0.7], Transport::Radiance);
    assert_eq!(a, b);
}

#[test]
fn cells_cover_the_triangle_once() {
    let valid = (0..2 * CELLS * CELLS).filter(|&k| cell_valid(k)).count();
    assert_eq!(valid, CELLS * CELLS);
    let mut rng = SplitMix(5);
    for _ in 0..10_000 {
        let (u, v) = (rng.next_f32(), rng.next_f32());
        let (b1, b2) = if u + v > 1.0 {
            (1.0 - u, 1.0 - v)
        } else {
            (u, v)
        };
        let k = cell_of(b1, b2);
        assert!(cell_valid(k));
        // The point lies in the cell cell_of names.
        let [p, q, r] = cell_corners(k);
        let det = (q[0] - p[0]) * (r[1] - p[1]) - (r[0] - p[0]) * (q[1] - p[1]);
        let s = ((b1 - p[0]) * (r[1] - p[1]) - (r[0] - p[0]) * (b2 - p[1])) / det;
        let t = ((q[0] - p[0]) * (b2 - p[1]) - (b1 - p[0]) * (q[1] - p[1])) / det;
        assert!(
            s > -1e-4 && t > -1e-4 && s + t < 1.0 + 1e-4,
            "({b1}, {b2}) in {k}"
        );
    }
}

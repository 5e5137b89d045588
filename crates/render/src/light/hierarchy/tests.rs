//! The hierarchy's probabilities: normalised, reported exactly as
//! sampled, drawn with the frequencies they claim, never 0 where a light
//! reaches the point, and concentrated on the near lights.

use std::sync::Arc;

use scotopia_color::{SampledWavelengths, Spectrum};

use super::*;
use crate::camera::{Camera, FovAxis};
use crate::geometry::{Planar, PlanarKind, Sphere, TriangleMesh};
use crate::light::{
    AreaLight, ConstantLight, DirectionalLight, GoniometricLight, IntensityGrid, PointLight,
    ProjectorLight, SceneExtent, SpotLight,
};
use crate::math::{Frame, Transform};
use crate::test_rng::{chi2_z, Rng};

struct Scene {
    shapes: Vec<Shape>,
    lights: Vec<Light>,
    power: Vec<f32>,
}

impl Scene {
    fn extent(&self) -> SceneExtent<'_> {
        SceneExtent {
            shapes: &self.shapes,
            center: Vec3::ZERO,
            radius: 20.0,
            casters: &[],
        }
    }

    fn hierarchy(&self) -> LightHierarchy {
        LightHierarchy::new(&self.lights, &self.shapes, &self.power, 10.0)
    }
}

fn unit(rng: &mut Rng) -> Vec3 {
    loop {
        let v = rng.vec(-1.0, 1.0);
        let l2 = v.length_squared();
        if l2 > 1e-3 && l2 <= 1.0 {
            return v.normalize();
        }
    }
}

fn constant(v: f32) -> Spectrum {
    Spectrum::Constant(v)
}

/// `n` lights of every kind, placed in [−10, 10]³, with random
/// brightness; about one in ten at infinity, one in thirty dark.
fn random_scene(n: usize, seed: u64) -> Scene {
    let mut rng = Rng(seed);
    let mut shapes = Vec::new();
    let mut lights = Vec::new();
    for _ in 0..n {
        let at = rng.vec(-10.0, 10.0);
        let bright = 0.1 + 10.0 * rng.next();
        let r = rng.next();
        let light = if r < 0.05 {
            Light::Directional(DirectionalLight {
                direction: unit(&mut rng),
                irradiance: constant(0.05 * bright),
            })
        } else if r < 0.1 {
            Light::Constant(ConstantLight {
                radiance: constant(0.01 * bright),
            })
        } else {
            match (rng.next() * 8.0) as usize {
                0 => Light::Point(PointLight {
                    position: at,
                    intensity: constant(bright),
                }),
                1 => {
                    let cutoff = 5.0 + 80.0 * rng.next();
                    let beam = cutoff * rng.next();
                    Light::Spot(SpotLight::new(
                        at,
                        unit(&mut rng),
                        constant(bright),
                        cutoff,
                        beam,
                    ))
                }
                2 => {
                    // Lit below γ_max, above γ_min, or everywhere.
                    let (lo, hi) = match (rng.next() * 3.0) as usize {
                        0 => (0.0, 20.0 + 100.0 * rng.next()),
                        1 => (60.0 + 100.0 * rng.next(), 180.0),
                        _ => (0.0, 180.0),
                    };
                    let phase = rng.next();
                    let grid = IntensityGrid::new(18, 12, move |g, c| {
                        if (lo..=hi).contains(&g) {
                            1.0 + (c.to_radians() + phase).cos() * 0.5
                        } else {
                            0.0
                        }
                    })
                    .unwrap();
                    Light::Goniometric(GoniometricLight {
                        position: at,
                        frame: Frame::from_normal(unit(&mut rng)),
                        spectrum: constant(1e-3 * bright),
                        grid: Arc::new(grid),
                    })
                }
                3 => {
                    let target = at + unit(&mut rng);
                    let up = unit(&mut rng);
                    let t = Transform::look_at(at, target, up).unwrap();
                    let fov = 10.0 + 100.0 * rng.next();
                    let camera =
                        Camera::new(t, 32, 24, fov, FovAxis::X, 1e-2, 1e4, 0.0, 1.0).unwrap();
                    Light::Projector(Box::new(ProjectorLight::new(
                        camera,
                        constant(bright).into(),
                        1.0,
                    )))
                }
                4 => {
                    shapes.push(Shape::Sphere(Sphere::new(at, 0.05 + rng.next())));
                    let i = shapes.len() - 1;
                    Light::Area(AreaLight::new(i as u32, &shapes[i], constant(bright)))
                }
                5 => {
                    let axis = unit(&mut rng);
                    let s = 0.1 + rng.next();
                    let t = Transform::translate(at).then_after(
                        &Transform::rotate(axis, 360.0 * rng.next())
                            .unwrap()
                            .then_after(&Transform::scale(Vec3::new(s, 0.3 * s, 1.0)).unwrap()),
                    );
                    let kind = if rng.next() < 0.5 {
                        PlanarKind::Rectangle
                    } else {
                        PlanarKind::Disk
                    };
                    shapes.push(Shape::Planar(Box::new(Planar::new(kind, t))));
                    let i = shapes.len() - 1;
                    Light::Area(AreaLight::new(i as u32, &shapes[i], constant(bright)))
                }
                _ => {
                    // A few triangles near `at`, some with vertex normals
                    // against their winding.
                    let count = 1 + (rng.next() * 4.0) as usize;
                    let positions: Vec<Vec3> =
                        (0..3 * count).map(|_| at + rng.vec(-0.7, 0.7)).collect();
                    let indices: Vec<[u32; 3]> = (0..count as u32)
                        .map(|f| [3 * f, 3 * f + 1, 3 * f + 2])
                        .collect();
                    let normals = (rng.next() < 0.3)
                        .then(|| (0..3 * count).map(|_| unit(&mut rng)).collect());
                    let mesh =
                        TriangleMesh::new(positions, normals, None, indices, &Transform::IDENTITY)
                            .unwrap();
                    shapes.push(Shape::Mesh(mesh));
                    let i = shapes.len() - 1;
                    Light::Area(AreaLight::new(i as u32, &shapes[i], constant(bright)))
                }
            }
        };
        lights.push(light);
    }
    let mut scene = Scene {
        shapes,
        lights,
        power: Vec::new(),
    };
    let extent = scene.extent();
    let mut power: Vec<f32> = scene
        .lights
        .iter()
        .map(|l| l.power(&extent).watts as f32)
        .collect();
    for w in power.iter_mut() {
        if rng.next() < 1.0 / 30.0 {
            *w = 0.0;
        }
    }
    scene.power = power;
    scene
}

/// Random points in [−12, 12]³, each with a random normal.
fn points(seed: u64, count: usize) -> Vec<(Vec3, Vec3)> {
    let mut rng = Rng(seed);
    (0..count)
        .map(|_| (rng.vec(-12.0, 12.0), unit(&mut rng)))
        .collect()
}

const SIZES: [usize; 5] = [1, 2, 3, 50, 300];

#[test]
fn the_probabilities_sum_to_one() {
    let (mut dead, mut total) = (0usize, 0usize);
    for (s, &size) in SIZES.iter().enumerate() {
        for seed in 0..6u64 {
            let scene = random_scene(size, 100 * s as u64 + seed);
            let h = scene.hierarchy();
            for (p, n) in points(seed + 17, 100) {
                for n in [Some(n), None] {
                    let sum: f64 = (0..size).map(|i| h.pmf(p, n, i) as f64).sum();
                    // No light to choose: none at infinity, and no
                    // bounded light can reach p.
                    let none = h.shares(p, LightHierarchy::clean_normal(n)).1 <= 0.0;
                    if none {
                        assert_eq!(sum, 0.0);
                        assert_eq!(h.sample(p, n, 0.5), None);
                        dead += 1;
                    } else {
                        assert!(
                            (sum - 1.0).abs() < 1e-4,
                            "{size} lights (seed {seed}) at {p:?}, {n:?}: Σ pmf = {sum}"
                        );
                    }
                    total += 1;
                }
            }
            for (i, &w) in scene.power.iter().enumerate() {
                if w == 0.0 {
                    assert_eq!(h.pmf(Vec3::ZERO, None, i), 0.0);
                }
            }
        }
    }
    // Only where one light faces away (scenes of one or two lights).
    assert!(dead * 20 < total, "{dead} of {total} points reach no light");
}

#[test]
fn samples_come_with_their_pmf_and_its_frequencies() {
    for (size, seed) in [(3usize, 3u64), (50, 4), (300, 5)] {
        let scene = random_scene(size, seed);
        let h = scene.hierarchy();
        let mut rng = Rng(seed + 99);
        for (p, n) in points(seed + 7, 3) {
            // Stratified and jittered u (as a sampler gives them), and
            // independent u (the χ² test's own assumption).
            for (n, stratified) in [(Some(n), true), (None, true), (Some(n), false)] {
                let count = 200_000;
                let mut hits = vec![0u64; size];
                for k in 0..count {
                    let u = if stratified {
                        (k as f32 + rng.next()) / count as f32
                    } else {
                        rng.next()
                    };
                    let (i, q) = h.sample(p, n, u).expect("a light");
                    assert_eq!(q, h.pmf(p, n, i), "light {i} at {p:?}");
                    hits[i] += 1;
                }
                // χ² over the lights, those expected fewer than 5 times
                // pooled into one bin.
                let expected: Vec<f64> = (0..size)
                    .map(|i| h.pmf(p, n, i) as f64 * count as f64)
                    .collect();
                if let Some((z, chi2, dof)) = chi2_z(&expected, &hits) {
                    assert!(
                        z < 3.0902,
                        "{size} lights at {p:?}: χ² = {chi2} over {dof} dof"
                    );
                }
            }
        }
    }
}

#[test]
fn a_light_that_reaches_a_point_has_a_probability() {
    let wl = SampledWavelengths::<4>::sample_uniform(0.37);
    for (size, seed) in [(1usize, 11u64), (2, 12), (3, 13), (50, 14), (300, 15)] {
        for rep in 0..4 {
            let scene = random_scene(size, seed + 1000 * rep);
            let h = scene.hierarchy();
            let extent = scene.extent();
            let mut rng = Rng(seed + 5);
            let mut reached = 0usize;
            for (p, n) in points(seed + 23 + rep, 150) {
                for (i, light) in scene.lights.iter().enumerate() {
                    if scene.power[i] <= 0.0 {
                        continue;
                    }
                    for _ in 0..3 {
                        let u = [rng.next(), rng.next()];
                        let Some(ls) = light.sample_li(&extent, &wl, p, rng.next(), u) else {
                            continue;
                        };
                        if ls.radiance.is_zero() {
                            continue;
                        }
                        reached += 1;
                        assert!(
                            h.pmf(p, None, i) > 0.0,
                            "light {i} ({light:?}) reaches {p:?} but has pmf 0"
                        );
                        if ls.wi.dot(n) > 0.0 {
                            assert!(
                                h.pmf(p, Some(n), i) > 0.0,
                                "light {i} ({light:?}) reaches {p:?} (n {n:?}) but has pmf 0"
                            );
                        }
                    }
                }
            }
            assert!(reached > 0);
        }
    }
}

#[test]
fn the_near_lamps_of_a_street_are_chosen() {
    let lights: Vec<Light> = (0..40)
        .map(|i| {
            Light::Point(PointLight {
                position: Vec3::new(4.0 * i as f32, 6.0, 0.0),
                intensity: constant(1.0),
            })
        })
        .collect();
    let power = vec![100.0; 40];
    let h = LightHierarchy::new(&lights, &[], &power, 10.0);
    // Beside lamp 7, at the foot of its pole.
    let p = Vec3::new(28.3, 0.5, 1.0);
    for n in [Some(Vec3::new(0.0, 1.0, 0.0)), None] {
        let q: Vec<f32> = (0..40).map(|i| h.pmf(p, n, i)).collect();
        // (By power over squared distance alone, lamps 6–8 would hold
        // 0.57, lamp 7 0.25 and the lamps past 17 together 0.03; the tree
        // gives 0.61, 0.28 and 0.05 without the normal, 0.71, 0.34 and
        // 0.02 with it.)
        let near = q[6] + q[7] + q[8];
        assert!(near > 0.5, "{q:?}");
        assert!(q.iter().all(|&qi| qi <= q[7]), "{q:?}");
        let mut far = 0.0;
        for (i, &qi) in q.iter().enumerate() {
            if i.abs_diff(7) > 10 {
                assert!(qi > 0.0 && qi < 0.02, "lamp {i}: {q:?}");
                far += qi;
            }
        }
        assert!(far < 0.15, "{far}: {q:?}");
    }
}

#[test]
fn lights_at_infinity_weigh_their_power_against_the_tree() {
    let lights = vec![
        Light::Point(PointLight {
            position: Vec3::new(0.0, 3.0, 0.0),
            intensity: constant(1.0),
        }),
        Light::Constant(ConstantLight {
            radiance: constant(1.0),
        }),
        Light::Directional(DirectionalLight {
            direction: Vec3::new(0.0, -1.0, 0.0),
            irradiance: constant(1.0),
        }),
        Light::Constant(ConstantLight {
            radiance: constant(1.0),
        }),
    ];
    // Radius 1: the lights at infinity weigh their power, the point light
    // (power 5, √10 m away, no normal) its importance 5/10.
    let h = LightHierarchy::new(&lights, &[], &[5.0, 1.0, 2.0, 0.0], 1.0);
    let p = Vec3::new(1.0, 0.0, 0.0);
    let total = 0.5 + 1.0 + 2.0;
    for (i, w) in [(0, 0.5), (1, 1.0), (2, 2.0)] {
        assert!((h.pmf(p, None, i) - w / total).abs() < 1e-6, "light {i}");
    }
    assert_eq!(h.pmf(p, None, 3), 0.0);
    assert_eq!(h.pmf(p, None, 4), 0.0);
    // u below 1/3.5 picks the constant light, then the directional, then
    // the tree.
    assert_eq!(h.sample(p, None, 0.2).map(|s| s.0), Some(1));
    assert_eq!(h.sample(p, None, 0.5).map(|s| s.0), Some(2));
    assert_eq!(h.sample(p, None, 0.9).map(|s| s.0), Some(0));
    // Without bounded lights the lights at infinity share everything, by
    // their weights.
    let h = LightHierarchy::new(&lights[1..], &[], &[1.0, 2.0, 0.0], 1.0);
    assert_eq!(h.pmf(p, None, 0), 1.0 / 3.0);
    assert_eq!(h.sample(p, None, 0.7), Some((1, 2.0 / 3.0)));
    let h = LightHierarchy::new(&[], &[], &[], 1.0);
    assert_eq!(h.sample(p, None, 0.5), None);
}

#[test]
fn the_tree_is_deterministic_and_deep_lines_stay_within_the_path_bits() {
    let scene = random_scene(300, 42);
    assert_eq!(scene.hierarchy(), scene.hierarchy());
    // 5000 lamps on one line: every leaf is reachable by its bits.
    let lights: Vec<Light> = (0..5000)
        .map(|i| {
            Light::Point(PointLight {
                position: Vec3::new(0.01 * i as f32, 0.0, 0.0),
                intensity: constant(1.0),
            })
        })
        .collect();
    let power: Vec<f32> = (0..5000).map(|i| 1.0 + (i % 7) as f32).collect();
    let h = LightHierarchy::new(&lights, &[], &power, 10.0);
    assert_eq!(h.tree_len(), 5000);
    let p = Vec3::new(20.0, 1.0, 0.0);
    let sum: f64 = (0..5000).map(|i| h.pmf(p, None, i) as f64).sum();
    assert!((sum - 1.0).abs() < 1e-4, "{sum}");
}

#[test]
fn cones_cut_off_lights_that_face_away_and_keep_their_edges() {
    // A spot at the origin shining down +z's opposite with a 30° cutoff,
    // a downward panel above, and a lamp far off so that the tree has
    // something else to choose.
    let rect = Transform::translate(Vec3::new(0.0, 5.0, 0.0))
        .then_after(&Transform::rotate(Vec3::new(1.0, 0.0, 0.0), 90.0).unwrap());
    let shapes = vec![Shape::Planar(Box::new(Planar::new(
        PlanarKind::Rectangle,
        rect,
    )))];
    let down = shapes[0].clone();
    let Shape::Planar(pl) = &down else {
        unreachable!()
    };
    // The panel's normal, whichever way the rotation turned it.
    let panel_n = pl.normal();
    let lights = vec![
        Light::Spot(SpotLight::new(
            Vec3::ZERO,
            Vec3::new(0.0, 0.0, -1.0),
            constant(1.0),
            30.0,
            20.0,
        )),
        Light::Area(AreaLight::new(0, &shapes[0], constant(1.0))),
        Light::Point(PointLight {
            position: Vec3::new(50.0, 0.0, 0.0),
            intensity: constant(1.0),
        }),
    ];
    let h = LightHierarchy::new(&lights, &shapes, &[10.0, 10.0, 10.0], 10.0);
    // Each light's own bound (a leaf's importance).
    let leaf = |i: usize, p: Vec3| {
        bounds::light_bounds(&lights[i], &shapes, 10.0)
            .unwrap()
            .compact()
            .importance(p, None)
    };
    // Behind the spot: nothing; just inside its cutoff, at 29.9° and 10 m
    // away: a probability.
    let behind = Vec3::new(0.0, 0.0, 3.0);
    assert_eq!(leaf(0, behind), 0.0);
    let a = 29.9f32.to_radians();
    let inside = Vec3::new(a.sin(), 0.0, -a.cos()) * 10.0;
    assert!(leaf(0, inside) > 0.0 && h.pmf(inside, None, 0) > 0.0);
    // Behind the one-sided panel: nothing; in front of it: a probability.
    let front = Vec3::new(0.0, 5.0, 0.0) + panel_n * 2.0;
    let back = Vec3::new(0.0, 5.0, 0.0) - panel_n * 2.0;
    assert!(leaf(1, front) > 0.0 && h.pmf(front, None, 1) > 0.0);
    assert_eq!(leaf(1, back), 0.0);
    // (In the tree the far lamp need not take the whole choice there: the
    // cluster of spot and panel has the union of their cones, which may
    // face the point, and where neither child can reach it the choice
    // below falls back to power. The probabilities still sum to 1.)
    for p in [behind, back] {
        let sum: f32 = (0..3).map(|i| h.pmf(p, None, i)).sum();
        assert!((sum - 1.0).abs() < 1e-6 && h.pmf(p, None, 2) > 0.0);
    }
}

#[test]
fn a_mesh_whose_normals_oppose_its_winding_may_emit_from_its_back() {
    // One triangle in the plane z = 0 wound to face +z, its vertex normals
    // facing −z: a hit from below finds the emitting side (the geometric
    // normal follows the shading normals).
    let positions = vec![
        Vec3::new(0.0, 0.0, 0.0),
        Vec3::new(1.0, 0.0, 0.0),
        Vec3::new(0.0, 1.0, 0.0),
    ];
    let normals = vec![Vec3::new(0.0, 0.0, -1.0); 3];
    let mesh = TriangleMesh::new(
        positions,
        Some(normals),
        None,
        vec![[0, 1, 2]],
        &Transform::IDENTITY,
    )
    .unwrap();
    let shapes = vec![Shape::Mesh(mesh)];
    let lights = vec![
        Light::Area(AreaLight::new(0, &shapes[0], constant(1.0))),
        Light::Point(PointLight {
            position: Vec3::new(9.0, 9.0, 9.0),
            intensity: constant(1.0),
        }),
    ];
    let h = LightHierarchy::new(&lights, &shapes, &[1.0, 1.0], 10.0);
    assert!(h.pmf(Vec3::new(0.3, 0.3, -2.0), None, 0) > 0.0);
    assert!(h.pmf(Vec3::new(0.3, 0.3, 2.0), None, 0) > 0.0);
}

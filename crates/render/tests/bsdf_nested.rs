//! The BSDFs that wrap or mix others — `blendbsdf`, `mask`, `normalmap`,
//! `bumpmap` — and `pplastic`: sampling matches the density (chi-square),
//! weights are eval/pdf, a blend's eval is the weighted sum of its parts,
//! and normal and bump maps tilt a mirror by the angle their normals say.

mod common;

use std::sync::Arc;

use common::bsdf_checks::{albedo, assert_weights_are_eval_over_pdf, sampling_p_value};
use common::Rng;
use scotopia_color::{SampledWavelengths, Spectrum};
use scotopia_render::bsdf::{
    Blend, Bsdf, BumpMap, Conductor, Diffuse, Mask, MicrofacetDistribution, MicrofacetKind,
    NormalMap, PolarizedPlastic, ShadingPoint, Transport,
};
use scotopia_render::math::Vec3;
use scotopia_render::texture::{FloatTexture, RgbBitmap, Texture};

/// Significance per chi-square case, Bonferroni-corrected over the cases.
const ALPHA: f64 = 0.01 / 30.0;

const UV: [f32; 2] = [0.3, 0.6];

fn wl() -> SampledWavelengths<4> {
    SampledWavelengths::sample_uniform(0.61)
}

fn dir(theta_deg: f32, phi_deg: f32) -> Vec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

fn diffuse(rho: f32) -> Bsdf {
    Bsdf::Diffuse(Diffuse {
        reflectance: Texture::constant(rho),
    })
}

/// A GGX conductor (a mirror at α = 0) of constant index.
fn conductor(alpha: f32) -> Bsdf {
    Bsdf::Conductor(Conductor {
        eta: Spectrum::Constant(0.2),
        k: Spectrum::Constant(3.0),
        specular_reflectance: Texture::constant(1.0),
        distribution: (alpha > 0.0)
            .then(|| MicrofacetDistribution::isotropic(MicrofacetKind::Ggx, alpha).into()),
    })
}

fn blend(w: f32, first: Bsdf, second: Bsdf) -> Bsdf {
    Bsdf::Blend(Box::new(Blend {
        weight: FloatTexture::Constant(w),
        first,
        second,
    }))
}

/// A constant normal map of unit normal `n`, as its colour (n + 1)/2.
fn normal_map(n: Vec3, inner: Bsdf) -> Bsdf {
    let c = [(n.x + 1.0) / 2.0, (n.y + 1.0) / 2.0, (n.z + 1.0) / 2.0];
    Bsdf::NormalMap(Box::new(NormalMap {
        normals: Arc::new(RgbBitmap::new(1, 1, vec![c]).unwrap()),
        inner,
        flip_invalid_normals: true,
        use_shadowing_function: true,
    }))
}

/// A bump map whose height rises by 1 between the centres of a 2×1
/// bitmap's texels: ∂h/∂u = 2 for u in (¼, ¾).
fn ramp_bump(scale: f32, inner: Bsdf) -> Bsdf {
    let ramp = RgbBitmap::new(2, 1, vec![[0.0; 3], [1.0; 3]]).unwrap();
    Bsdf::BumpMap(Box::new(BumpMap {
        height: FloatTexture::Bitmap(Arc::new(ramp)),
        scale,
        inner,
        flip_invalid_normals: true,
        use_shadowing_function: false,
    }))
}

fn pplastic(alpha: f32) -> Bsdf {
    Bsdf::PolarizedPlastic(PolarizedPlastic::new(
        Texture::constant(0.5),
        Texture::constant(1.0),
        1.5,
        MicrofacetDistribution::isotropic(MicrofacetKind::Ggx, alpha).into(),
    ))
}

/// The non-delta cases: (name, BSDF, wi).
fn cases() -> Vec<(&'static str, Bsdf, Vec3)> {
    let tilt = dir(20.0, 30.0);
    let mut cases = vec![];
    for theta in [10.0, 50.0, 75.0] {
        let wi = dir(theta, 40.0);
        cases.push((
            "blend diffuse / rough conductor, w 0.3",
            blend(0.3, diffuse(0.8), conductor(0.2)),
            wi,
        ));
        cases.push((
            "blend rough conductors, w 0.8",
            blend(0.8, conductor(0.5), conductor(0.1)),
            wi,
        ));
        cases.push((
            "blend of a blend",
            blend(
                0.5,
                blend(0.4, diffuse(0.5), conductor(0.3)),
                conductor(0.05),
            ),
            wi,
        ));
        cases.push((
            "mask 0.6 over a rough conductor",
            Bsdf::Mask(Box::new(Mask {
                opacity: FloatTexture::Constant(0.6),
                inner: conductor(0.3),
            })),
            wi,
        ));
        cases.push((
            "normal map over a rough conductor",
            normal_map(tilt, conductor(0.3)),
            wi,
        ));
        cases.push((
            "normal map over diffuse",
            normal_map(tilt, diffuse(0.7)),
            wi,
        ));
        cases.push((
            "bump map over a rough conductor",
            ramp_bump(0.2, conductor(0.25)),
            wi,
        ));
        cases.push(("pplastic α 0.2", pplastic(0.2), wi));
        cases.push(("pplastic α 0.6", pplastic(0.6), wi));
        cases.push((
            "twosided normal map from below",
            Bsdf::TwoSided(Box::new(normal_map(tilt, conductor(0.3)))),
            -wi,
        ));
    }
    cases
}

#[test]
fn sampling_matches_pdf_chi_square() {
    let w = wl();
    assert_eq!(cases().len(), 30);
    for (i, (name, bsdf, wi)) in cases().into_iter().enumerate() {
        let p = sampling_p_value(&bsdf, &w, UV, wi, 500 + i as u64);
        assert!(p > ALPHA, "{name}, wi {wi:?}: p = {p:e}");
    }
}

#[test]
fn weights_are_eval_over_pdf() {
    let w = wl();
    let mut rng = Rng(9);
    for mode in [Transport::Radiance, Transport::Importance] {
        for (name, bsdf, wi) in cases() {
            assert_weights_are_eval_over_pdf(
                name, &bsdf, &w, UV, wi, mode, 300, &mut rng, 1e-3, true,
            );
        }
    }
}

#[test]
fn a_blend_evaluates_to_the_weighted_sum_of_its_parts() {
    let w = wl();
    let mut rng = Rng(11);
    let (a, b) = (diffuse(0.6), conductor(0.15));
    for weight in [0.0, 0.25, 0.9, 1.0] {
        let mix = blend(weight, a.clone(), b.clone());
        for _ in 0..200 {
            let wi = dir(80.0 * rng.next(), 360.0 * rng.next());
            let wo = dir(80.0 * rng.next(), 360.0 * rng.next());
            let got = mix.eval(&w, UV, wi, wo, Transport::Radiance);
            let want = a.eval(&w, UV, wi, wo, Transport::Radiance) * (1.0 - weight)
                + b.eval(&w, UV, wi, wo, Transport::Radiance) * weight;
            let pdf = mix.pdf_at(&w, UV, wi, wo);
            let want_pdf = a.pdf(&w, wi, wo) * (1.0 - weight) + b.pdf(&w, wi, wo) * weight;
            for k in 0..4 {
                assert!((got[k] - want[k]).abs() <= 1e-5 * want[k].max(1.0));
            }
            assert!((pdf - want_pdf).abs() <= 1e-5 * want_pdf.max(1.0));
        }
    }
    // A textured weight is read at the point: a 2×1 map, 0 left, 1 right.
    let map = RgbBitmap::new(2, 1, vec![[0.0; 3], [1.0; 3]]).unwrap();
    let textured = Bsdf::Blend(Box::new(Blend {
        weight: FloatTexture::Bitmap(Arc::new(map)),
        first: diffuse(0.2),
        second: diffuse(0.8),
    }));
    let (wi, wo) = (dir(30.0, 0.0), dir(40.0, 90.0));
    let left = textured.eval(&w, [0.25, 0.5], wi, wo, Transport::Radiance);
    let right = textured.eval(&w, [0.75, 0.5], wi, wo, Transport::Radiance);
    let cos_over_pi = wo.z / std::f32::consts::PI;
    assert!((left[0] - 0.2 * cos_over_pi).abs() < 1e-5);
    assert!((right[0] - 0.8 * cos_over_pi).abs() < 1e-5);
}

/// A blend of a diffuse BSDF and a mirror reflects, in expectation,
/// (1 − w)·ρ + w·F: a mirror sample keeps F, the mirror's own weight.
/// Mitsuba 3.9.1 instead weights it by (w·F + (1 − w)·f₁) / (w + (1 − w)·p₁)
/// at the mirror direction, as if the delta lobe's placeholder density 1
/// were a density, and reflects less (its `bsdf_blendbsdf` scene renders
/// 3.4 % darker; docs/scene-format.md).
#[test]
fn a_blend_with_a_mirror_reflects_the_weighted_albedo() {
    let w = wl();
    let (rho, mirror) = (0.3, conductor(0.0));
    let mix = blend(0.5, diffuse(rho), mirror.clone());
    let mut rng = Rng(13);
    let n = 100_000;
    for theta in [0.0, 45.0, 75.0] {
        let wi = dir(theta, 20.0);
        let f = mirror
            .sample(&w, UV, wi, 0.5, [0.5, 0.5], Transport::Radiance)
            .unwrap();
        assert!(f.delta);
        let want = 0.5 * rho as f64 + 0.5 * f.weight[0] as f64;
        let (mut s1, mut s2) = (0.0f64, 0.0f64);
        for _ in 0..n {
            let x = mix
                .sample(&w, UV, wi, rng.next(), rng.pair(), Transport::Radiance)
                .map_or(0.0, |s| s.weight[0] as f64);
            s1 += x;
            s2 += x * x;
        }
        let got = s1 / n as f64;
        let se = ((s2 / n as f64 - got * got) / n as f64).sqrt();
        assert!(
            (got - want).abs() < 4.0 * se,
            "θ {theta}: blend albedo {got} vs {want} ± {se}"
        );
    }
}

#[test]
fn a_mask_passes_light_with_probability_one_minus_opacity() {
    let w = wl();
    let mask = Bsdf::Mask(Box::new(Mask {
        opacity: FloatTexture::Constant(0.3),
        inner: diffuse(0.5),
    }));
    let wi = dir(35.0, 10.0);
    let mut rng = Rng(12);
    let n = 100_000;
    let mut passed = 0;
    for _ in 0..n {
        let s = mask
            .sample(&w, UV, wi, rng.next(), rng.pair(), Transport::Radiance)
            .unwrap();
        if s.delta {
            passed += 1;
            assert_eq!(s.wo, -wi);
            assert_eq!(s.weight[0], 1.0);
        }
    }
    // Binomial: mean 0.7 n, standard deviation √(n · 0.21).
    let z = (passed as f64 - 0.7 * n as f64) / (n as f64 * 0.21).sqrt();
    assert!(z.abs() < 4.0, "{passed} of {n}");
    assert!(!mask.is_delta());
}

#[test]
fn a_flat_normal_map_changes_nothing() {
    let w = wl();
    let mut rng = Rng(13);
    for inner in [diffuse(0.6), conductor(0.3), pplastic(0.2)] {
        let mapped = normal_map(Vec3::new(0.0, 0.0, 1.0), inner.clone());
        for _ in 0..200 {
            let wi = dir(85.0 * rng.next(), 360.0 * rng.next());
            let wo = dir(85.0 * rng.next(), 360.0 * rng.next());
            let a = mapped.eval(&w, UV, wi, wo, Transport::Radiance);
            let b = inner.eval(&w, UV, wi, wo, Transport::Radiance);
            for k in 0..4 {
                assert!((a[k] - b[k]).abs() <= 1e-5 * b[k].max(1.0), "{a:?} {b:?}");
            }
            let (pa, pb) = (mapped.pdf_at(&w, UV, wi, wo), inner.pdf(&w, wi, wo));
            assert!((pa - pb).abs() <= 1e-4 * pb.max(1.0));
            let (u, u2) = (rng.next(), rng.pair());
            let sa = mapped.sample(&w, UV, wi, u, u2, Transport::Radiance);
            let sb = inner.sample(&w, UV, wi, u, u2, Transport::Radiance);
            match (sa, sb) {
                (Some(sa), Some(sb)) => {
                    assert!((sa.wo - sb.wo).length() < 1e-5);
                    assert!((sa.weight[0] - sb.weight[0]).abs() <= 1e-4 * sb.weight[0].max(1.0));
                }
                (None, None) => {}
                other => panic!("{other:?}"),
            }
        }
    }
}

/// The mirror direction of `wi` about unit `n`.
fn mirror(wi: Vec3, n: Vec3) -> Vec3 {
    n * (2.0 * wi.dot(n)) - wi
}

#[test]
fn a_tilted_normal_map_tilts_a_mirror() {
    let w = wl();
    // Tilted 15° towards the tangent (∂p/∂u), no shadowing at normal
    // incidence: the reflection turns by 30°.
    let tilt = 15.0f32.to_radians();
    let n = Vec3::new(tilt.sin(), 0.0, tilt.cos());
    let bsdf = normal_map(n, conductor(0.0));
    let wi = Vec3::new(0.0, 0.0, 1.0);
    let s = bsdf
        .sample(&w, UV, wi, 0.5, [0.5, 0.5], Transport::Radiance)
        .unwrap();
    assert!(s.delta);
    let angle = s.wo.z.clamp(-1.0, 1.0).acos().to_degrees();
    assert!((angle - 30.0).abs() < 1e-3, "{angle}");
    assert!(s.wo.x > 0.0 && s.wo.y.abs() < 1e-6);
    // Fresnel at 15° to the mapped normal, times the shadowing term at
    // 30° from a 15° normal (Estevez et al. 2019).
    let a2 = 0.125 * tilt.tan().powi(2);
    let g = 2.0 / (1.0 + (1.0 + a2 * 30.0f32.to_radians().tan().powi(2)).sqrt());
    let plain = conductor(0.0)
        .sample(&w, UV, dir(15.0, 0.0), 0.5, [0.5, 0.5], Transport::Radiance)
        .unwrap();
    assert!((s.weight[0] - g * plain.weight[0]).abs() < 1e-4, "{s:?}");
    // Oblique incidence: the mirror image about the mapped normal.
    let wi = dir(20.0, 200.0);
    let s = bsdf
        .sample(&w, UV, wi, 0.5, [0.5, 0.5], Transport::Radiance)
        .unwrap();
    assert!((s.wo - mirror(wi, n)).length() < 1e-5, "{:?}", s.wo);

    // Seen through a hit whose ∂p/∂u is world +y: the normal tilts towards
    // +y in the world.
    let (frame, at) = ShadingPoint::at(
        UV,
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(0.0, 0.0, 1.0),
        Vec3::new(0.0, 3.0, 0.0),
        Vec3::new(-1.0, 0.0, 0.0),
    );
    let wi_world = Vec3::new(0.0, 0.0, 1.0);
    let s = bsdf
        .sample(
            &w,
            at,
            frame.to_local(wi_world),
            0.5,
            [0.5, 0.5],
            Transport::Radiance,
        )
        .unwrap();
    let wo_world = frame.to_world(s.wo);
    assert!(wo_world.y > 0.49 && wo_world.x.abs() < 1e-5, "{wo_world:?}");
}

#[test]
fn a_height_ramp_tilts_a_mirror_by_its_slope() {
    let w = wl();
    // h = 2u between the texel centres, times scale 0.25: slope ½, so the
    // normal is (−½, 0, 1) normalised — 26.57° — and the reflection of
    // normal incidence turns by twice that, away from +u.
    let bsdf = ramp_bump(0.25, conductor(0.0));
    let wi = Vec3::new(0.0, 0.0, 1.0);
    let s = bsdf
        .sample(&w, [0.5, 0.5], wi, 0.5, [0.5, 0.5], Transport::Radiance)
        .unwrap();
    let want = 2.0 * 0.5f32.atan().to_degrees();
    let angle = s.wo.z.clamp(-1.0, 1.0).acos().to_degrees();
    assert!((angle - want).abs() < 1e-2, "{angle} vs {want}");
    assert!(s.wo.x < 0.0 && s.wo.y.abs() < 1e-6, "{:?}", s.wo);
    // Twice the scale, twice the slope.
    let steeper = ramp_bump(0.5, conductor(0.0))
        .sample(&w, [0.5, 0.5], wi, 0.5, [0.5, 0.5], Transport::Radiance)
        .unwrap();
    let angle = steeper.wo.z.acos().to_degrees();
    assert!(
        (angle - 2.0 * 1.0f32.atan().to_degrees()).abs() < 1e-2,
        "{angle}"
    );
    // The slope is per unit of u: with ∂p/∂u twice as long, half the tilt.
    let at = ShadingPoint {
        dpdu: Vec3::new(2.0, 0.0, 0.0),
        ..ShadingPoint::from([0.5, 0.5])
    };
    let s = bsdf
        .sample(&w, at, wi, 0.5, [0.5, 0.5], Transport::Radiance)
        .unwrap();
    let angle = s.wo.z.acos().to_degrees();
    assert!(
        (angle - 2.0 * 0.25f32.atan().to_degrees()).abs() < 1e-2,
        "{angle}"
    );
}

#[test]
fn pplastic_conserves_energy_and_is_reciprocal() {
    let w = wl();
    let mut rng = Rng(14);
    for alpha in [0.05, 0.3, 0.8] {
        let b = pplastic(alpha);
        for theta in [0.0, 45.0, 80.0] {
            let wi = dir(theta, 0.0);
            let (mean, se) = albedo(&b, &w, UV, wi, Transport::Radiance, 50_000, &mut rng);
            assert!(
                mean - 4.0 * se <= 1.0,
                "α {alpha}, θ {theta}: {mean} ± {se}"
            );
        }
        for _ in 0..200 {
            let (a, c) = (
                dir(85.0 * rng.next(), 360.0 * rng.next()),
                dir(85.0 * rng.next(), 360.0 * rng.next()),
            );
            let fac = b.eval(&w, UV, a, c, Transport::Radiance)[0] / c.z;
            let fca = b.eval(&w, UV, c, a, Transport::Radiance)[0] / a.z;
            assert!((fac - fca).abs() <= 1e-4 * fac.max(1e-3), "{fac} {fca}");
        }
    }
}

/// (θi, φi, θo, φo) in degrees, then Mitsuba 3.9.1's (`scalar_spectral`)
/// eval and pdf of a `normalmap` (raw 1×1 bitmap of the normal tilted 25°
/// at azimuth 30°) and of a `bumpmap` (raw 2×1 ramp 0 | 1, `scale` 0.25),
/// each over `diffuse` 0.5, at uv (0.4, 0.5) of a flat surface with
/// ∂p/∂u = x, ∂p/∂v = y.
const MITSUBA_MAPS: [[f32; 8]; 6] = [
    [
        30.0, 0.0, 30.0, 180.0, 0.0955772, 0.19158642, 0.15845743, 0.317738,
    ],
    [
        10.0,
        20.0,
        60.0,
        150.0,
        0.042153984,
        0.08599294,
        0.121768415,
        0.24911687,
    ],
    [
        70.0, 0.0, 40.0, 200.0, 0.06759675, 0.13583724, 0.06569684, 0.13211252,
    ],
    [
        45.0, 90.0, 45.0, 270.0, 0.07769047, 0.15642968, 0.09988408, 0.20131683,
    ],
    [20.0, 0.0, 80.0, 30.0, 0.077067785, 0.18257505, 0.0, 0.0],
    [
        60.0, 210.0, 50.0, 30.0, 0.14287752, 0.28848672, 0.04380236, 0.08856622,
    ],
];

/// The same directions' eval and pdf of Mitsuba 3.9.1's `pplastic` (GGX
/// α 0.2, int_ior 1.5, diffuse 0.5) in its unpolarised variant.
const MITSUBA_PPLASTIC: [[f32; 6]; 5] = [
    [30.0, 0.0, 30.0, 180.0, 0.22137883, 1.6182864],
    [10.0, 20.0, 60.0, 150.0, 0.07185918, 0.0898917],
    [70.0, 0.0, 40.0, 200.0, 0.12154324, 0.33448508],
    [45.0, 90.0, 45.0, 270.0, 0.24010685, 1.9322951],
    [20.0, 0.0, 80.0, 90.0, 0.016759193, 0.027875764],
];

fn close_to(got: f32, want: f32, what: &str) {
    assert!(
        (got - want).abs() <= 2e-4 * want.abs().max(1e-3),
        "{what}: {got} vs Mitsuba's {want}"
    );
}

#[test]
fn normal_map_bump_map_and_pplastic_match_mitsuba() {
    let w = wl();
    let (t, p) = (25.0f32.to_radians(), 30.0f32.to_radians());
    // The colour Mitsuba read, as f32.
    let c = [
        (t.sin() * p.cos() + 1.0) / 2.0,
        (t.sin() * p.sin() + 1.0) / 2.0,
        (t.cos() + 1.0) / 2.0,
    ];
    let nm = Bsdf::NormalMap(Box::new(NormalMap {
        normals: Arc::new(RgbBitmap::new(1, 1, vec![c]).unwrap()),
        inner: diffuse(0.5),
        flip_invalid_normals: true,
        use_shadowing_function: true,
    }));
    let ramp = RgbBitmap::new(2, 1, vec![[0.0; 3], [1.0; 3]]).unwrap();
    let bump = Bsdf::BumpMap(Box::new(BumpMap {
        height: FloatTexture::Bitmap(Arc::new(ramp)),
        scale: 0.25,
        inner: diffuse(0.5),
        flip_invalid_normals: true,
        use_shadowing_function: true,
    }));
    let uv = [0.4, 0.5];
    for [ti, pi, to, po, nm_f, nm_p, bump_f, bump_p] in MITSUBA_MAPS {
        let (wi, wo) = (dir(ti, pi), dir(to, po));
        let case = format!("({ti}, {pi}) → ({to}, {po})");
        close_to(
            nm.eval(&w, uv, wi, wo, Transport::Radiance)[0],
            nm_f,
            &format!("normalmap eval {case}"),
        );
        close_to(
            nm.pdf_at(&w, uv, wi, wo),
            nm_p,
            &format!("normalmap pdf {case}"),
        );
        close_to(
            bump.eval(&w, uv, wi, wo, Transport::Radiance)[0],
            bump_f,
            &format!("bumpmap eval {case}"),
        );
        close_to(
            bump.pdf_at(&w, uv, wi, wo),
            bump_p,
            &format!("bumpmap pdf {case}"),
        );
    }
    let pp = pplastic(0.2);
    for [ti, pi, to, po, f, pdf] in MITSUBA_PPLASTIC {
        let (wi, wo) = (dir(ti, pi), dir(to, po));
        close_to(
            pp.eval(&w, UV, wi, wo, Transport::Radiance)[0],
            f,
            "pplastic eval",
        );
        close_to(pp.pdf(&w, wi, wo), pdf, "pplastic pdf");
    }
}

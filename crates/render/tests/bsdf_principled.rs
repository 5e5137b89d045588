//! Mitsuba 3's `principled`: eval and pdf against Mitsuba 3.9.1, sampling
//! against the density (chi-square), weights eval/pdf, and no energy gain
//! for a white metal or glass (a white dielectric has Mitsuba's albedo,
//! above 1).

mod common;

use common::bsdf_checks::{self, assert_weights_are_eval_over_pdf, sampling_p_value};
use common::principled::{assert_matches_mitsuba, base, c, dir, wl, UV};
use common::Rng;
use scotopia_render::bsdf::{specular_to_eta, Bsdf, Principled, Transport};
use scotopia_render::math::Vec3;
use scotopia_render::texture::{FloatTexture, Texture};

fn metallic() -> Principled {
    Principled {
        base_color: base(),
        roughness: FloatTexture::Constant(0.4),
        metallic: c(0.7),
        spec_tint: c(0.3),
        ..Principled::default()
    }
}

fn glass() -> Principled {
    Principled {
        base_color: Texture::constant(1.0),
        roughness: FloatTexture::Constant(0.3),
        spec_trans: c(1.0),
        eta: 1.5,
        ..Principled::default()
    }
}

fn clearcoat() -> Principled {
    Principled {
        base_color: base(),
        roughness: FloatTexture::Constant(0.5),
        clearcoat: c(0.8),
        clearcoat_gloss: FloatTexture::Constant(0.6),
        sheen: c(0.5),
        sheen_tint: c(0.4),
        ..Principled::default()
    }
}

fn aniso() -> Principled {
    Principled {
        base_color: base(),
        roughness: FloatTexture::Constant(0.5),
        anisotropic: c(0.7),
        metallic: c(0.3),
        spec_trans: c(0.4),
        flatness: c(0.5),
        spec_tint: c(0.5),
        eta: 1.33,
        ..Principled::default()
    }
}

/// Mitsuba's documentation example.
fn everything() -> Principled {
    Principled {
        base_color: base(),
        metallic: c(0.7),
        eta: specular_to_eta(0.6),
        roughness: FloatTexture::Constant(0.2),
        spec_tint: c(0.4),
        anisotropic: c(0.5),
        sheen: c(0.3),
        sheen_tint: c(0.2),
        clearcoat: c(0.6),
        clearcoat_gloss: FloatTexture::Constant(0.3),
        spec_trans: c(0.4),
        ..Principled::default()
    }
}

// Measured with Mitsuba 3.9.1 (pip `mitsuba`), variant `scalar_spectral`:
// `mi.load_dict({'type': 'principled', ...})` with the parameters of the
// functions above (`specular` 0.5 where no eta is given; 0.6 for
// `everything`), a SurfaceInteraction3f with the wi below, shading frame
// z = (0, 0, 1) and wavelengths (450, 520, 580, 650) nm, a default
// BSDFContext (radiance). Each row: θi, φi, θo, φo in degrees, then
// `bsdf.eval` on the four wavelengths and `bsdf.pdf`.
const MITSUBA_METALLIC: [[f32; 9]; 12] = [
    [
        30.0, 0.0, 30.0, 180.0, 1.3935484, 0.98487, 1.4616611, 1.3902577, 2.8188121,
    ],
    [
        10.0,
        20.0,
        60.0,
        150.0,
        0.03905861,
        0.027444353,
        0.040994324,
        0.038965102,
        0.06668794,
    ],
    [
        70.0, 0.0, 40.0, 200.0, 0.15117145, 0.10787579, 0.15838738, 0.15082285, 0.28437495,
    ],
    [
        45.0, 90.0, 45.0, 270.0, 1.6872832, 1.1970544, 1.768988, 1.6833364, 3.4121685,
    ],
    [
        20.0,
        0.0,
        80.0,
        30.0,
        0.010834228,
        0.007598264,
        0.011373555,
        0.010808174,
        0.017625753,
    ],
    [30.0, 0.0, 150.0, 180.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [50.0, 40.0, 170.0, 250.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [140.0, 0.0, 130.0, 180.0, 0.0, 0.0, 0.0, 0.0, 2.4308631],
    [160.0, 30.0, 40.0, 210.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [
        60.0, 210.0, 50.0, 30.0, 1.4499074, 1.0430804, 1.5177118, 1.4466319, 2.8716872,
    ],
    [
        0.0,
        0.0,
        35.0,
        120.0,
        0.099553466,
        0.07008475,
        0.10446492,
        0.0993162,
        0.18136998,
    ],
    [
        85.0,
        10.0,
        20.0,
        190.0,
        0.102311924,
        0.072605506,
        0.107263,
        0.102072746,
        0.19280934,
    ],
];
const MITSUBA_GLASS: [[f32; 9]; 12] = [
    [
        30.0, 0.0, 30.0, 180.0, 0.47040698, 0.47040698, 0.47040698, 0.47040698, 0.4707242,
    ],
    [
        10.0,
        20.0,
        60.0,
        150.0,
        0.00058852206,
        0.00058852206,
        0.00058852206,
        0.00058852206,
        0.00059207604,
    ],
    [
        70.0,
        0.0,
        40.0,
        200.0,
        0.008142819,
        0.008142819,
        0.008142819,
        0.008142819,
        0.008154408,
    ],
    [
        45.0, 90.0, 45.0, 270.0, 0.6952093, 0.6952093, 0.6952093, 0.6952093, 0.69661427,
    ],
    [
        20.0,
        0.0,
        80.0,
        30.0,
        8.115814e-05,
        8.115814e-05,
        8.115814e-05,
        8.115814e-05,
        8.613848e-05,
    ],
    [
        30.0, 0.0, 150.0, 180.0, 0.17410684, 0.17410684, 0.17410684, 0.17410684, 0.39200458,
    ],
    [
        50.0,
        40.0,
        170.0,
        250.0,
        0.0018271548,
        0.0018271548,
        0.0018271548,
        0.0018271548,
        0.004111356,
    ],
    [
        140.0, 0.0, 130.0, 180.0, 3.4275708, 3.4275708, 3.4275708, 3.4275708, 3.4374006,
    ],
    [
        160.0, 30.0, 40.0, 210.0, 3.2591643, 3.2591643, 3.2591643, 3.2591643, 1.4505796,
    ],
    [
        60.0, 210.0, 50.0, 30.0, 0.36447388, 0.36447388, 0.36447388, 0.36447388, 0.36551917,
    ],
    [
        0.0,
        0.0,
        35.0,
        120.0,
        0.0027036823,
        0.0027036823,
        0.0027036823,
        0.0027036823,
        0.0027063626,
    ],
    [
        85.0,
        10.0,
        20.0,
        190.0,
        0.004411385,
        0.004411385,
        0.004411385,
        0.004411385,
        0.00441257,
    ],
];
const MITSUBA_CLEARCOAT: [[f32; 9]; 12] = [
    [
        30.0, 0.0, 30.0, 180.0, 0.40871775, 0.36618, 0.4158074, 0.4083753, 1.5796207,
    ],
    [
        10.0,
        20.0,
        60.0,
        150.0,
        0.08634964,
        0.061633144,
        0.090469055,
        0.08615063,
        0.112063415,
    ],
    [
        70.0,
        0.0,
        40.0,
        200.0,
        0.1628061,
        0.124515705,
        0.16918783,
        0.1624978,
        0.3299914,
    ],
    [
        45.0, 90.0, 45.0, 270.0, 0.37833625, 0.34337455, 0.38416317, 0.37805474, 1.8752931,
    ],
    [
        20.0,
        0.0,
        80.0,
        30.0,
        0.03146362,
        0.022186428,
        0.033009816,
        0.031388927,
        0.033280265,
    ],
    [30.0, 0.0, 150.0, 180.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [50.0, 40.0, 170.0, 250.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [140.0, 0.0, 130.0, 180.0, 0.0, 0.0, 0.0, 0.0, 1.3250439],
    [160.0, 30.0, 40.0, 210.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [
        60.0, 210.0, 50.0, 30.0, 0.28060573, 0.24783935, 0.28606677, 0.28034192, 1.1977984,
    ],
    [
        0.0,
        0.0,
        35.0,
        120.0,
        0.14675456,
        0.106522225,
        0.15345994,
        0.14643061,
        0.23501411,
    ],
    [
        85.0, 10.0, 20.0, 190.0, 0.16504994, 0.12135714, 0.17233205, 0.16469814, 0.25740674,
    ],
];
const MITSUBA_ANISO: [[f32; 9]; 12] = [
    [
        30.0, 0.0, 30.0, 180.0, 0.30834436, 0.21902362, 0.32323113, 0.30762517, 0.8228221,
    ],
    [
        10.0,
        20.0,
        60.0,
        150.0,
        0.03934376,
        0.027638815,
        0.04129458,
        0.039249517,
        0.07079467,
    ],
    [
        70.0,
        0.0,
        40.0,
        200.0,
        0.121667504,
        0.08745625,
        0.12736937,
        0.12139206,
        0.2577987,
    ],
    [
        45.0, 90.0, 45.0, 270.0, 0.3715427, 0.26597217, 0.38913774, 0.3706927, 0.98406714,
    ],
    [
        20.0,
        0.0,
        80.0,
        30.0,
        0.015527158,
        0.01090742,
        0.016297113,
        0.015489963,
        0.030675927,
    ],
    [
        30.0, 0.0, 150.0, 180.0, 2.078669, 1.7391393, 2.1300018, 2.076157, 3.6608863,
    ],
    [50.0, 40.0, 170.0, 250.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [
        140.0, 0.0, 130.0, 180.0, 0.05337117, 0.05337117, 0.05337117, 0.05337117, 0.20142974,
    ],
    [
        160.0, 30.0, 40.0, 210.0, 0.28641698, 0.23963365, 0.29349005, 0.28607085, 0.82475513,
    ],
    [
        60.0, 210.0, 50.0, 30.0, 0.39875215, 0.29231772, 0.41649127, 0.3978952, 1.0401092,
    ],
    [
        0.0,
        0.0,
        35.0,
        120.0,
        0.06185688,
        0.043469094,
        0.06492151,
        0.061708834,
        0.11827796,
    ],
    [
        85.0, 10.0, 20.0, 190.0, 0.18655668, 0.1344303, 0.1952444, 0.18613699, 0.43574736,
    ],
];
const MITSUBA_EVERYTHING: [[f32; 9]; 12] = [
    [
        30.0, 0.0, 30.0, 180.0, 22.116844, 15.654905, 23.193832, 22.064817, 38.677055,
    ],
    [
        10.0,
        20.0,
        60.0,
        150.0,
        0.016401812,
        0.011730025,
        0.017180443,
        0.016364198,
        0.0315666,
    ],
    [
        70.0,
        0.0,
        40.0,
        200.0,
        0.037423223,
        0.027388418,
        0.039095692,
        0.037342433,
        0.0760235,
    ],
    [
        45.0, 90.0, 45.0, 270.0, 27.237488, 19.342718, 28.553282, 27.173923, 47.413906,
    ],
    [
        20.0,
        0.0,
        80.0,
        30.0,
        0.005071446,
        0.003575955,
        0.0053206943,
        0.0050594057,
        0.01022133,
    ],
    [
        30.0,
        0.0,
        150.0,
        180.0,
        0.007950568,
        0.006651922,
        0.008146908,
        0.00794096,
        0.0203197,
    ],
    [
        50.0,
        40.0,
        170.0,
        250.0,
        9.4356314e-05,
        7.8944155e-05,
        9.668645e-05,
        9.4242285e-05,
        0.00024109526,
    ],
    [
        140.0, 0.0, 130.0, 180.0, 0.59904754, 0.59904754, 0.59904754, 0.59904754, 4.997213,
    ],
    [
        160.0, 30.0, 40.0, 210.0, 0.25212616, 0.21094388, 0.25835243, 0.2518215, 1.2026798,
    ],
    [
        60.0, 210.0, 50.0, 30.0, 1.545567, 1.1184423, 1.6167543, 1.542128, 2.80573,
    ],
    [
        0.0,
        0.0,
        35.0,
        120.0,
        0.029795866,
        0.021794308,
        0.031129459,
        0.029731441,
        0.057512578,
    ],
    [
        85.0,
        10.0,
        20.0,
        190.0,
        0.041271042,
        0.029567711,
        0.043221593,
        0.04117681,
        0.0792179,
    ],
];
const MITSUBA_DEFAULTS: [[f32; 9]; 12] = [
    [
        30.0, 0.0, 30.0, 180.0, 0.19825444, 0.19825444, 0.19825444, 0.19825444, 0.86914825,
    ],
    [
        10.0, 20.0, 60.0, 150.0, 0.08311299, 0.08311299, 0.08311299, 0.08311299, 0.11703436,
    ],
    [
        70.0, 0.0, 40.0, 200.0, 0.14912966, 0.14912966, 0.14912966, 0.14912966, 0.3461375,
    ],
    [
        45.0, 90.0, 45.0, 270.0, 0.20028201, 0.20028201, 0.20028201, 0.20028201, 0.9992117,
    ],
    [
        20.0,
        0.0,
        80.0,
        30.0,
        0.030507427,
        0.030507427,
        0.030507427,
        0.030507427,
        0.03495745,
    ],
    [30.0, 0.0, 150.0, 180.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [50.0, 40.0, 170.0, 250.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [140.0, 0.0, 130.0, 180.0, 0.0, 0.0, 0.0, 0.0, 1.3250439],
    [160.0, 30.0, 40.0, 210.0, 0.0, 0.0, 0.0, 0.0, 0.0],
    [
        60.0, 210.0, 50.0, 30.0, 0.23568949, 0.23568949, 0.23568949, 0.23568949, 1.0843356,
    ],
    [
        0.0, 0.0, 35.0, 120.0, 0.13952042, 0.13952042, 0.13952042, 0.13952042, 0.24502818,
    ],
    [
        85.0, 10.0, 20.0, 190.0, 0.15333478, 0.15333478, 0.15333478, 0.15333478, 0.27722168,
    ],
];

fn cases() -> Vec<(&'static str, Principled, [[f32; 9]; 12])> {
    vec![
        ("metallic", metallic(), MITSUBA_METALLIC),
        ("glass", glass(), MITSUBA_GLASS),
        ("clearcoat", clearcoat(), MITSUBA_CLEARCOAT),
        ("aniso", aniso(), MITSUBA_ANISO),
        ("everything", everything(), MITSUBA_EVERYTHING),
        ("defaults", Principled::default(), MITSUBA_DEFAULTS),
    ]
}

#[test]
fn eval_and_pdf_match_mitsuba() {
    assert_matches_mitsuba(
        cases()
            .into_iter()
            .map(|(name, p, rows)| (name, Bsdf::Principled(Box::new(p)), rows))
            .collect(),
    );
}

/// The sets where Mitsuba's lobe-selection probabilities do not depend on
/// the sampled microfacet, so its density is exact (see the module
/// comment of `principled`), from above and, for glass, from below.
fn exact_density_cases() -> Vec<(&'static str, Principled, Vec3)> {
    let aniso_opaque = Principled {
        spec_trans: None,
        ..aniso()
    };
    let rough_metal = Principled {
        metallic: c(1.0),
        roughness: FloatTexture::Constant(0.6),
        ..metallic()
    };
    let mut v = vec![];
    for wi in [dir(35.0, 20.0), dir(75.0, 200.0)] {
        v.push(("metallic", metallic(), wi));
        v.push(("metal r 0.6", rough_metal.clone(), wi));
        v.push(("glass", glass(), wi));
        v.push(("glass from below", glass(), -wi));
        v.push(("clearcoat", clearcoat(), wi));
        v.push(("anisotropic", aniso_opaque.clone(), wi));
        v.push(("defaults", Principled::default(), wi));
    }
    v
}

#[test]
fn sampling_matches_pdf_chi_square() {
    let w = wl();
    let cases = exact_density_cases();
    let alpha = 0.01 / cases.len() as f64;
    for (i, (name, p, wi)) in cases.into_iter().enumerate() {
        let bsdf = Bsdf::Principled(Box::new(p));
        let pv = sampling_p_value(&bsdf, &w, UV, wi, 700 + i as u64);
        assert!(pv > alpha, "{name}, wi {wi:?}: p = {pv:e}");
    }
}

#[test]
fn weights_are_eval_over_pdf() {
    let w = wl();
    let mut rng = Rng(11);
    for mode in [Transport::Radiance, Transport::Importance] {
        for (name, p, _) in cases() {
            let bsdf = Bsdf::Principled(Box::new(p));
            for wi in [dir(30.0, 10.0), dir(80.0, 100.0), -dir(40.0, 300.0)] {
                assert_weights_are_eval_over_pdf(
                    name, &bsdf, &w, UV, wi, mode, 300, &mut rng, 1e-4, false,
                );
            }
        }
    }
}

/// The albedo from 100 000 samples in importance mode (no 1/η² on
/// refraction): (mean, standard error).
fn albedo(bsdf: &Bsdf, wi: Vec3) -> (f64, f64) {
    bsdf_checks::albedo(
        bsdf,
        &wl(),
        UV,
        wi,
        Transport::Importance,
        100_000,
        &mut Rng(3),
    )
}

fn white(p: Principled) -> Principled {
    Principled {
        base_color: Texture::constant(1.0),
        ..p
    }
}

/// A white metal (isotropic or not) and a white glass reflect and
/// transmit at most what arrives, within four standard errors.
#[test]
fn a_white_metal_or_glass_does_not_create_energy() {
    let metal = white(Principled {
        metallic: c(1.0),
        ..metallic()
    });
    let aniso_metal = white(Principled {
        metallic: c(1.0),
        spec_trans: None,
        ..aniso()
    });
    for (name, p) in [
        ("metal", metal),
        ("anisotropic metal", aniso_metal),
        ("glass", glass()),
    ] {
        let bsdf = Bsdf::Principled(Box::new(p));
        for wi in [
            dir(5.0, 0.0),
            dir(45.0, 30.0),
            dir(80.0, 70.0),
            -dir(30.0, 0.0),
        ] {
            let (mean, se) = albedo(&bsdf, wi);
            assert!(
                mean <= 1.0 + 4.0 * se,
                "{name} wi {wi:?}: albedo {mean} ± {se}"
            );
        }
    }
}

/// Mitsuba's white dielectric (metallic 0, spec_trans 0) is not energy
/// conserving: Burley's diffuse lobe is not reduced by what the specular
/// lobe reflects, so the albedo exceeds 1 (by 4 % near normal incidence,
/// up to 31 % at grazing for roughness 1). Scotopia's albedo is
/// Mitsuba's: (θi, φi, roughness, Mitsuba 3.9.1's albedo, its standard
/// error), the mean `sample` weight[0] of 100 000 samples in
/// `scalar_spectral`, importance mode, the other settings as above.
const MITSUBA_WHITE_ALBEDO: [[f64; 5]; 6] = [
    [5.0, 0.0, 0.5, 1.0424357602820638, 0.0012692260875162157],
    [45.0, 30.0, 0.5, 1.049390078456808, 0.0018317791573712974],
    [80.0, 70.0, 0.5, 1.1612851358204148, 0.0019085834391191494],
    [5.0, 0.0, 1.0, 1.049736029493317, 0.0020293619859244444],
    [45.0, 30.0, 1.0, 1.0489274483312951, 0.001864237376542813],
    [80.0, 70.0, 1.0, 1.3122504549841416, 0.001742840543382207],
];

#[test]
fn a_white_dielectric_has_mitsubas_albedo() {
    for [t, ph, r, want, want_se] in MITSUBA_WHITE_ALBEDO {
        let p = white(Principled {
            roughness: FloatTexture::Constant(r as f32),
            ..Principled::default()
        });
        let bsdf = Bsdf::Principled(Box::new(p));
        let (mean, se) = albedo(&bsdf, dir(t as f32, ph as f32));
        let tol = 4.0 * (se * se + want_se * want_se).sqrt();
        assert!(
            (mean - want).abs() <= tol,
            "θ {t} roughness {r}: {mean} ± {se} vs Mitsuba's {want} ± {want_se}"
        );
    }
}

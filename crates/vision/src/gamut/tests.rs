use super::line::Frame;
use super::*;
use scotopia_color::cie::xyz_bar;
use scotopia_color::space::{delta_e_ok, srgb_encode, xyz_to_oklab, RgbColorSpace, RgbSpace};

/// A linear value's code on the 8-bit sRGB scale, undithered (0..=255,
/// not rounded): what the display's PNG rounds.
fn code(v: f64) -> f64 {
    srgb_encode(v.clamp(0.0, 1.0)) * 255.0
}

/// Test colours (XYZ, D65 white at Y = 1): a grid over an RGB cube wider
/// than Rec. 2020, monochromatic light from 380 to 700 nm alone and
/// mixed with white (the night street's lamps: low-pressure sodium at 589
/// nm, deep blue at 450 nm), the corners of each display's gamut and of
/// the wider ones, each at several luminances, and pseudo-random XYZ.
fn colours() -> Vec<[f64; 3]> {
    let rec2020 = RgbSpace::Rec2020.def();
    let mut out = Vec::new();
    let steps = [-0.1, 0.0, 0.03, 0.2, 0.5, 0.8, 1.0, 1.2];
    for r in steps {
        for g in steps {
            for b in steps {
                out.push(rec2020.rgb_to_xyz([r, g, b]));
            }
        }
    }
    let white = RgbSpace::Srgb.def().rgb_to_xyz([1.0; 3]);
    let mut lambda = 380.0;
    while lambda <= 700.0 {
        let bar = xyz_bar(lambda).map(f64::from);
        for y in [0.002, 0.02, 0.1, 0.3, 0.6, 0.9] {
            for white_part in [0.0, 0.2, 0.5] {
                let k = y * (1.0 - white_part) / bar[1];
                out.push(std::array::from_fn(|i| {
                    k * bar[i] + y * white_part * white[i]
                }));
            }
        }
        lambda += 2.5;
    }
    for space in [
        RgbSpace::Srgb,
        RgbSpace::DisplayP3,
        RgbSpace::Rec2020,
        RgbSpace::AcesCg,
    ] {
        let def = space.def();
        for corner in 0..8 {
            let rgb = [corner & 1, corner >> 1 & 1, corner >> 2 & 1].map(|b| b as f64);
            for k in [0.05, 0.3, 0.7, 1.0] {
                out.push(def.rgb_to_xyz(rgb.map(|c| c * k)));
            }
        }
    }
    // Pseudo-random XYZ in [0, 1.1]³ (a fixed LCG).
    let mut state = 0x2545_f491_4f6c_dd1du64;
    let mut next = || {
        state = state
            .wrapping_mul(6_364_136_223_846_793_005)
            .wrapping_add(1_442_695_040_888_963_407);
        (state >> 11) as f64 / (1u64 << 53) as f64 * 1.1
    };
    for _ in 0..20_000 {
        out.push([next(), next(), next()]);
    }
    out
}

#[test]
fn the_frames_oklab_is_scotopia_colors() {
    for space in [RgbSpace::Srgb, RgbSpace::DisplayP3, RgbSpace::Rec2020] {
        let def = space.def();
        Frame::with(def, |frame| {
            for xyz in colours().into_iter().step_by(7) {
                let want = xyz_to_oklab(xyz);
                let got = frame.oklab_of_xyz(xyz);
                let rgb = frame.oklab_of_rgb(def.xyz_to_rgb(xyz));
                for k in 0..3 {
                    assert!(
                        (got[k] - want[k]).abs() < 1e-14,
                        "{xyz:?}: {got:?} {want:?}"
                    );
                    assert!(
                        (rgb[k] - want[k]).abs() < 1e-12,
                        "{xyz:?}: {rgb:?} {want:?}"
                    );
                }
            }
        });
    }
}

#[test]
fn the_fast_mapping_gives_the_references_codes() {
    // Every channel of every colour within half an 8-bit code of the
    // reference before dither (so at most one code after it) and 2ε in
    // Oklab; nearly all within a hundredth of a code. (A colour on the
    // gamut's surface may fall just outside it in one computation and
    // just inside in the other: the reference's bisection then takes up
    // to ε of chroma off, or not.)
    let colours = colours();
    let oklab = |rgb: [f64; 3], space: &RgbColorSpace| xyz_to_oklab(space.rgb_to_xyz(rgb));
    for space in [RgbSpace::Srgb, RgbSpace::DisplayP3, RgbSpace::Rec2020] {
        let def = space.def();
        let (mut worst, mut worst_e, mut outside, mut moved) = (0.0f64, 0.0f64, 0, 0);
        for &xyz in &colours {
            let fast = map_to_gamut(xyz, def);
            let reference = map_to_gamut_reference(xyz, def);
            assert!(
                fast.iter().all(|c| (0.0..=1.0).contains(c)),
                "{xyz:?} → {fast:?}"
            );
            outside += usize::from(!in_gamut(def.xyz_to_rgb(xyz)));
            let d = (0..3)
                .map(|k| (code(fast[k]) - code(reference[k])).abs())
                .fold(0.0, f64::max);
            let e = delta_e_ok(oklab(fast, def), oklab(reference, def));
            assert!(
                d < 0.5 && e < 2.0 * EPSILON,
                "{space:?} {xyz:?}: {fast:?} vs {reference:?}"
            );
            worst = worst.max(d);
            worst_e = worst_e.max(e);
            moved += usize::from(d > 0.01);
        }
        eprintln!(
            "{space:?}: {outside} of {} colours mapped; worst {worst:.2e} codes, \
             {worst_e:.1e} ΔEOK; {moved} moved by over 0.01 code",
            colours.len()
        );
        // Most of the test colours do need mapping, and few move at all.
        assert!(outside * 2 > colours.len(), "{space:?}: {outside}");
        assert!(moved * 1000 < outside, "{space:?}: {moved}");
    }
}

#[test]
fn the_replay_sees_the_distance_turn_back_past_a_kink() {
    // Yellows of the night street by day whose clip distance dips below
    // JND again just after the blue channel starts clipping: the
    // reference's bisection stops in the dip, and so must the replay.
    let cases = [
        (
            [0.783_574_76, 0.888_988_26, 0.007_288_603],
            RgbSpace::DisplayP3,
        ),
        ([0.808_411_1, 0.925_661_9, 0.035_906_125], RgbSpace::Srgb),
        ([0.811_821_5, 0.933_253_5, 0.026_069_3], RgbSpace::Srgb),
        ([0.798_418_05, 0.903_89, 0.033_287_847], RgbSpace::Srgb),
    ];
    for (xyz, space) in cases {
        let def = space.def();
        let xyz = xyz.map(|v: f32| f64::from(v));
        let (fast, reference) = (map_to_gamut(xyz, def), map_to_gamut_reference(xyz, def));
        for k in 0..3 {
            let d = (code(fast[k]) - code(reference[k])).abs();
            assert!(d < 1e-6, "{xyz:?}: {fast:?} vs {reference:?}");
        }
    }
}

#[test]
fn the_lanes_give_the_references_codes() {
    // `map_pixels_to_gamut` (the reference's steps, side by side) on the
    // test colours as f32 pixels with a fourth value, against the
    // reference on the same f32 values; as strict as the test above.
    let pixels: Vec<[f32; 4]> = colours()
        .iter()
        .map(|xyz| [xyz[0] as f32, xyz[1] as f32, xyz[2] as f32, 0.5])
        .collect();
    let oklab =
        |rgb: [f32; 3], space: &RgbColorSpace| xyz_to_oklab(space.rgb_to_xyz(rgb.map(f64::from)));
    for space in [RgbSpace::Srgb, RgbSpace::DisplayP3, RgbSpace::Rec2020] {
        let def = space.def();
        let lanes = map_pixels_to_gamut(&pixels, def);
        assert_eq!(lanes.len(), pixels.len());
        let mut moved = 0;
        for (p, got) in pixels.iter().zip(&lanes) {
            let xyz = [p[0], p[1], p[2]].map(f64::from);
            let want = map_to_gamut_reference(xyz, def).map(|v| v as f32);
            let d = (0..3)
                .map(|k| (code(got[k].into()) - code(want[k].into())).abs())
                .fold(0.0, f64::max);
            let e = delta_e_ok(oklab(*got, def), oklab(want, def));
            assert!(
                d < 0.5 && e < 2.0 * EPSILON,
                "{space:?} {p:?}: {got:?} vs {want:?}"
            );
            moved += usize::from(d > 0.01);
        }
        assert!(moved * 1000 < pixels.len(), "{space:?}: {moved}");
    }
    // Fewer pixels than a queue holds, and none.
    let srgb = RgbSpace::Srgb.def();
    let few = &pixels[..5];
    let want: Vec<[f32; 3]> = few
        .iter()
        .map(|p| map_to_gamut([p[0], p[1], p[2]].map(f64::from), srgb).map(|v| v as f32))
        .collect();
    assert_eq!(map_pixels_to_gamut(few, srgb), want);
    assert!(map_pixels_to_gamut::<4>(&[], srgb).is_empty());
}

#[test]
fn in_gamut_white_and_black_are_as_the_reference() {
    let srgb = RgbSpace::Srgb.def();
    for rgb in [[0.2, 0.5, 0.9], [1.0, 1.0, 1.0], [0.0, 0.3, 0.0]] {
        let xyz = srgb.rgb_to_xyz(rgb);
        assert_eq!(map_to_gamut(xyz, srgb), map_to_gamut_reference(xyz, srgb));
    }
    assert_eq!(map_to_gamut([2.0, 2.1, 2.0], srgb), [1.0; 3]);
    assert_eq!(map_to_gamut([0.0, 0.0, 0.0], srgb), [0.0; 3]);
    assert_eq!(map_to_gamut([-0.1, -0.2, 0.3], srgb), [0.0; 3]);
    // Non-finite input does not panic (the pipeline overwrites it).
    for xyz in [[f64::NAN, 0.5, 0.5], [f64::INFINITY, 1.0, 0.0]] {
        let _ = map_to_gamut(xyz, srgb);
    }
}

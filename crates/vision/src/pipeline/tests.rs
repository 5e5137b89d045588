use super::*;

const W: usize = 64;
const H: usize = 48;

/// A grey scene (D65, S/P 2.46) at luminance `y` with one lamp `lamp`
/// times brighter in the middle.
fn scene(y: f32, lamp: f32) -> Vec<[f32; 4]> {
    let mut px = vec![[0.9505 * y, y, 1.089 * y, 2.4645 * y]; W * H];
    px[(H / 2) * W + W / 2] = px[0].map(|v| v * lamp);
    px
}

#[test]
fn every_output_lies_in_the_display_gamut() {
    // Saturated, very bright and black pixels together.
    let mut px = scene(20.0, 1.0e4);
    px[5] = [0.0, 0.0, 5000.0, 10.0];
    px[6] = [300.0, 100.0, 0.0, 50.0];
    px[7] = [0.0; 4];
    for tonemap in [
        ToneOperator::Multiscale,
        ToneOperator::Reinhard,
        ToneOperator::Exposure,
    ] {
        for gamut in [RgbSpace::Srgb, RgbSpace::DisplayP3, RgbSpace::Rec2020] {
            let p = DisplayParams {
                tonemap,
                gamut,
                ..DisplayParams::default()
            };
            let out = display(&px, W, H, &p);
            assert!(out.rgb.iter().flatten().all(|v| (0.0..=1.0).contains(v)));
        }
    }
}

#[test]
fn exposure_puts_the_log_average_at_mid_grey_and_reports_the_mode() {
    let p = DisplayParams {
        tonemap: ToneOperator::Exposure,
        glare: false,
        ..DisplayParams::default()
    };
    let out = display(&scene(200.0, 1.0), W, H, &p);
    // 18 % of peak, D65 grey: linear sRGB ≈ (0.18, 0.18, 0.18).
    for v in out.rgb[0] {
        assert!((v - 0.18).abs() < 0.002, "{:?}", out.rgb[0]);
    }
    assert_eq!(out.report.state.mode.name(), "photopic");
    assert_eq!(out.report.timings.len(), 5);
    let night = display(&scene(0.001, 1.0), W, H, &p);
    assert_eq!(night.report.state.mode.name(), "scotopic");
    assert!(night.report.blur_pixels > 0.0);
}

#[test]
fn glare_only_when_something_exceeds_the_display() {
    let p = DisplayParams::default();
    assert!(!display(&scene(50.0, 1.0), W, H, &p).report.glare_applied);
    assert!(display(&scene(50.0, 1.0e5), W, H, &p).report.glare_applied);
}

#[test]
fn the_night_shift_turns_a_dark_scene_blue_grey() {
    // The same scene at 0.001 cd/m² with and without the night shift: the
    // shifted one sits near Jensen's (0.25, 0.25), bluer than D65.
    let xy = |night_shift: bool| {
        let p = DisplayParams {
            night_shift,
            glare: false,
            ..DisplayParams::default()
        };
        let out = display(&scene(0.001, 1.0), W, H, &p);
        let xyz = RgbSpace::Srgb.def().rgb_to_xyz(out.rgb[0].map(f64::from));
        let sum: f64 = xyz.iter().sum();
        [xyz[0] / sum, xyz[1] / sum]
    };
    let (on, off) = (xy(true), xy(false));
    assert!(
        (off[0] - 0.3127).abs() < 0.01 && (off[1] - 0.329).abs() < 0.01,
        "{off:?}"
    );
    assert!(
        (on[0] - 0.25).abs() < 0.01 && (on[1] - 0.25).abs() < 0.01,
        "{on:?}"
    );
}

#[test]
fn local_adaptation_gives_each_region_its_own_sensitivity() {
    // Left half at 0.001 cd/m², right half at 100: the left is shifted
    // towards blue-grey, the right keeps D65's chromaticity.
    let px: Vec<[f32; 4]> = (0..W * H)
        .map(|i| {
            let y = if i % W < W / 2 { 0.001 } else { 100.0 };
            [0.9505 * y, y, 1.089 * y, 2.4645 * y]
        })
        .collect();
    let p = DisplayParams {
        adaptation: Adaptation::Local,
        glare: false,
        degrees_per_pixel: 0.25,
        ..DisplayParams::default()
    };
    let out = display(&px, W, H, &p);
    let x_of = |i: usize| {
        let xyz = RgbSpace::Srgb.def().rgb_to_xyz(out.rgb[i].map(f64::from));
        xyz[0] / xyz.iter().sum::<f64>()
    };
    let (left, right) = (x_of((H / 2) * W + 2), x_of((H / 2) * W + W - 3));
    assert!(left < 0.27, "{left}");
    assert!((right - 0.3127).abs() < 0.01, "{right}");
}

/// The largest difference between two outputs over the pixels `keep` accepts.
fn max_difference(a: &Displayed, b: &Displayed, keep: impl Fn(usize) -> bool) -> f32 {
    (0..W * H)
        .filter(|&i| keep(i))
        .flat_map(|i| (0..3).map(move |c| (i, c)))
        .map(|(i, c)| (a.rgb[i][c] - b.rgb[i][c]).abs())
        .fold(0.0, f32::max)
}

#[test]
fn a_nan_block_leaves_the_other_pixels_as_they_were() {
    // A 4 × 4 block of NaN (and ∞) in a grey scene with a glaring lamp:
    // every other pixel is shown as without the block, within half an
    // 8-bit step, for each tone operator and both adaptations.
    let clean = scene(20.0, 1.0e4);
    let in_block = |i: usize| (8..12).contains(&(i % W)) && (8..12).contains(&(i / W));
    let mut broken = clean.clone();
    for (i, p) in broken.iter_mut().enumerate() {
        if in_block(i) {
            *p = if i % 2 == 0 {
                [f32::NAN; 4]
            } else {
                [1.0, f32::INFINITY, 1.0, 1.0]
            };
        }
    }
    for tonemap in [
        ToneOperator::Multiscale,
        ToneOperator::Reinhard,
        ToneOperator::Exposure,
    ] {
        for adaptation in [Adaptation::Global, Adaptation::Local] {
            let p = DisplayParams {
                tonemap,
                adaptation,
                ..DisplayParams::default()
            };
            let (a, b) = (display(&clean, W, H, &p), display(&broken, W, H, &p));
            let d = max_difference(&a, &b, |i| !in_block(i));
            assert!(d <= 0.5 / 255.0, "{tonemap:?} {adaptation:?}: {d}");
            assert_eq!(b.report.statistics.left_out.non_finite, 16);
            assert!(b.report.statistics.left_out.note().is_some());
            assert!(a.report.statistics.left_out.note().is_none());
            // The block itself is shown black.
            assert!((0..W * H)
                .filter(|&i| in_block(i))
                .all(|i| b.rgb[i] == [0.0; 3]));
        }
    }
}

#[test]
fn one_absurd_pixel_does_not_blacken_the_rest() {
    // A single finite pixel of 2e38 (and one of -3e20): left out, shown at
    // the display's peak; the rest as without them.
    let clean = scene(20.0, 1.0);
    let mut broken = clean.clone();
    broken[100] = [2e38; 4];
    broken[200] = [-3e20, 1.0, 1.0, 1.0];
    let p = DisplayParams::default();
    let (a, b) = (display(&clean, W, H, &p), display(&broken, W, H, &p));
    let d = max_difference(&a, &b, |i| i != 100 && i != 200);
    assert!(d <= 0.5 / 255.0, "{d}");
    // Not black: the grey scene is shown as grey.
    assert!(b.rgb[0].iter().all(|&v| v > 0.05), "{:?}", b.rgb[0]);
    assert_eq!(b.rgb[100], [1.0; 3]);
    assert_eq!(b.report.statistics.left_out.absurd, 2);
}

#[test]
fn an_image_beyond_any_scene_is_reported_as_it_looks() {
    // The viewer at scale=1e20: every lit pixel above 1e10 cd/m² (shown at
    // the display's peak, white), the black ones still black. It used to
    // be adapted to the black pixels alone and called scotopic.
    let mut px = scene(20.0 * 1e20, 1.0);
    for p in px.iter_mut().take(W * H / 4) {
        *p = [0.0; 4];
    }
    let out = display(&px, W, H, &DisplayParams::default());
    assert_eq!(out.report.state.mode.name(), "photopic");
    assert!(out.rgb[W * H - 1] == [1.0; 3]);
    // Every pixel absurd: photopic; every pixel not finite: black and
    // adapted to black (scotopic), not to 1 cd/m².
    let all = display(&[[1e30f32; 4]; W * H], W, H, &DisplayParams::default());
    assert_eq!(all.report.state.mode.name(), "photopic");
    let nan = display(&[[f32::NAN; 4]; W * H], W, H, &DisplayParams::default());
    assert_eq!(nan.report.state.mode.name(), "scotopic");
    assert!(nan.rgb.iter().all(|c| *c == [0.0; 3]));
}

#[test]
fn negative_luminance_is_counted_for_a_warning() {
    let mut px = scene(20.0, 1.0);
    px[3] = [-1.0, -2.0, -1.0, -3.0];
    px[4] = [1.0, -0.5, 1.0, 1.0];
    let out = display(&px, W, H, &DisplayParams::default());
    assert_eq!(out.report.statistics.negative, 2);
    let note = out.report.statistics.negative_note().unwrap();
    assert!(
        note.contains("2 pixel(s) have negative luminance"),
        "{note}"
    );
    let clean = display(&scene(20.0, 1.0), W, H, &DisplayParams::default());
    assert_eq!(clean.report.statistics.negative_note(), None);
}

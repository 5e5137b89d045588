//! `scotopia display` and `render --display` end to end: outputs, `--info`,
//! and clear errors for bad input.

use std::path::{Path, PathBuf};

mod common;

use common::scotopia;

fn out_dir(name: &str) -> PathBuf {
    common::out_dir("display", name)
}

/// A small night scene: D65 grey at `y` cd/m² with a lamp, as an XYZV′ EXR.
fn night_exr(dir: &Path, y: f32) -> PathBuf {
    let (w, h) = (64, 48);
    let mut px = vec![[0.9505 * y, y, 1.089 * y, 2.4645 * y]; w * h];
    px[24 * w + 32] = [9.5e4, 1e5, 1.09e5, 2.4e5];
    let chan = |c: usize| px.iter().map(|p| p[c]).collect::<Vec<f32>>();
    let path = dir.join(format!("night-{y}.exr"));
    scotopia_image::write_exr(
        &path,
        w,
        h,
        vec![
            ("X".into(), chan(0)),
            ("Y".into(), chan(1)),
            ("Z".into(), chan(2)),
            ("V".into(), chan(3)),
        ],
        &[("fovHorizontalDegrees", scotopia_image::Meta::F32(30.0))],
    )
    .unwrap();
    path
}

#[test]
fn info_names_the_mode_and_outputs_are_written() {
    let dir = out_dir("ok");
    let exr = night_exr(&dir, 0.002);
    let png = dir.join("out.png");
    let sheet = dir.join("sheet.png");
    let (code, out, err) = scotopia(&[
        "display",
        exr.to_str().unwrap(),
        "-o",
        png.to_str().unwrap(),
        "--compare",
        sheet.to_str().unwrap(),
        "--info",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("mode          scotopic"), "{out}");
    assert!(
        out.contains("glare         veil") && out.contains("at the adaptation point"),
        "{out}"
    );
    let img = scotopia_image::read_rgb(&png).unwrap();
    assert_eq!((img.width, img.height), (64, 48));
    assert!(scotopia_image::read_rgb(&sheet).unwrap().width > 5 * 64);
    // A fixed adaptation luminance is reported as given.
    let (code, out, _) = scotopia(&[
        "display",
        exr.to_str().unwrap(),
        "--info",
        "--adaptation",
        "50",
    ]);
    assert_eq!(code, 0);
    assert!(
        out.contains("5.0000e1 cd/m²") && out.contains("photopic"),
        "{out}"
    );
}

#[test]
fn bad_input_is_a_clear_error() {
    let dir = out_dir("bad");
    let exr = night_exr(&dir, 1.0);
    let e = exr.to_str().unwrap();
    for (args, expect) in [
        (vec!["display", e], "nothing to do"),
        (
            vec!["display", e, "--info", "--tonemap", "filmic"],
            "--tonemap filmic",
        ),
        (
            vec!["display", e, "--info", "--adaptation", "bright"],
            "--adaptation bright",
        ),
        (
            vec!["display", e, "--info", "--glare", "maybe"],
            "--glare maybe",
        ),
        (
            vec!["display", e, "--info", "--gamut", "acescg"],
            "not a display gamut",
        ),
        (
            vec!["display", e, "--info", "--display-peak=-5"],
            "--display-peak",
        ),
        (vec!["display", e, "--info", "--bits", "12"], "--bits 12"),
        (
            vec!["display", "/nonexistent.exr", "--info"],
            "/nonexistent.exr",
        ),
    ] {
        let (code, _, err) = scotopia(&args);
        assert_ne!(code, 0, "{args:?}");
        assert!(err.contains(expect), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    let out = dir.join("o.tiff");
    let (code, _, err) = scotopia(&["display", e, "-o", out.to_str().unwrap()]);
    assert_ne!(code, 0);
    assert!(err.contains(".png or .exr"), "{err}");
}

#[test]
fn render_display_runs_the_pipeline_after_rendering() {
    let dir = out_dir("render");
    let scene = common::scenes().join("cornell-box.xml");
    let exr = dir.join("c.exr");
    let png = dir.join("c.png");
    let (code, _, err) = scotopia(&[
        "render",
        scene.to_str().unwrap(),
        "-D",
        "res=16",
        "--spp",
        "2",
        "-o",
        exr.to_str().unwrap(),
        "--display",
        png.to_str().unwrap(),
        "--tonemap",
        "reinhard",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("displayed"), "{err}");
    assert_eq!(scotopia_image::read_rgb(&png).unwrap().width, 16);
}

#[test]
fn the_observer_is_given_by_age_and_pigmentation_and_shown_by_info() {
    let dir = out_dir("observer");
    let exr = night_exr(&dir, 0.002);
    let e = exr.to_str().unwrap();
    // The defaults: CIE 146's young observer with brown eyes.
    let (code, out, err) = scotopia(&["display", e, "--info"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("observer      25 years, pigmentation 0.5 (CIE 146)"),
        "{out}"
    );
    let (code, out, err) =
        scotopia(&["display", e, "--info", "--age", "70", "--pigmentation", "1"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("observer      70 years, pigmentation 1 (CIE 146)"),
        "{out}"
    );
    // Out of range or not a number: usage errors (exit code 2) naming the
    // flag, with the observer's own reason.
    for (args, flag, reason) in [
        (vec!["--age", "-3"], "--age", "use years from 1 to 100"),
        (vec!["--age=0"], "--age", "use years from 1 to 100"),
        (vec!["--age", "NaN"], "--age", "use years"),
        (vec!["--age", "old"], "--age", "not a number of years"),
        (
            vec!["--pigmentation", "1.5"],
            "--pigmentation",
            "from 0 (dark eyes) to 1",
        ),
        (
            vec!["--pigmentation=-0.5"],
            "--pigmentation",
            "from 0 (dark eyes) to 1",
        ),
    ] {
        let mut argv = vec!["display", e, "--info"];
        argv.extend(&args);
        let (code, _, err) = scotopia(&argv);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(
            err.contains(flag) && err.contains(reason),
            "{args:?}: {err}"
        );
    }
    // `render --display` takes them too, checked before rendering.
    let scene = common::scenes().join("cornell-box.xml");
    let (code, _, err) = scotopia(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        dir.join("c.exr").to_str().unwrap(),
        "--display",
        dir.join("c.png").to_str().unwrap(),
        "--age",
        "200",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--age") && err.contains("age 200"), "{err}");
    // And the help says what they change and their defaults.
    let (_, help, _) = scotopia(&["display", "--help"]);
    for says in [
        "--age <YEARS>",
        "CIE 146:2002",
        "Pokorny",
        "[default: 25]",
        "--pigmentation <P>",
        "[default: 0.5]",
    ] {
        assert!(help.contains(says), "{says}: {help}");
    }
}

#[test]
fn numbers_out_of_range_are_usage_errors_naming_the_flag() {
    let dir = out_dir("numbers");
    let exr = night_exr(&dir, 0.01);
    let e = exr.to_str().unwrap();
    let scene = common::scenes().join("cornell-box.xml");
    let s = scene.to_str().unwrap();
    let out = dir.join("o.exr");
    let o = out.to_str().unwrap();
    // Rejected by the argument parser: exit code 2.
    for (args, flag) in [
        (vec!["render", s, "-o", o, "--time", "1e20"], "--time"),
        (vec!["render", s, "-o", o, "--time", "inf"], "--time"),
        (
            vec!["render", s, "-o", o, "--threads", "100000000"],
            "--threads",
        ),
        (vec!["display", e, "--info", "--fov", "1e300"], "--fov"),
        (vec!["display", e, "--info", "--fov", "NaN"], "--fov"),
    ] {
        let (code, _, err) = scotopia(&args);
        assert_eq!(code, 2, "{args:?}: {err}");
        assert!(err.contains(flag), "{args:?}: {err}");
    }
    // A field of view whose pixels are finer than the vision model takes
    // (given, or from the image's metadata) is an error naming the limit,
    // quickly, instead of a blur thousands of pixels wide.
    let tiny = dir.join("tiny-fov.exr");
    let px = vec![0.01f32; 64 * 48];
    scotopia_image::write_exr(
        &tiny,
        64,
        48,
        ["X", "Y", "Z", "V"]
            .map(|c| (c.to_string(), px.clone()))
            .to_vec(),
        &[("fovHorizontalDegrees", scotopia_image::Meta::F32(1e-30))],
    )
    .unwrap();
    for (args, expect) in [
        (
            vec!["display", e, "--info", "--fov", "1e-10"],
            "--fov 1e-10",
        ),
        (vec!["display", e, "--info", "--fov", "1e-6"], "--fov"),
        (
            vec!["display", tiny.to_str().unwrap(), "--info"],
            "the image's field of view",
        ),
    ] {
        let (code, _, err) = scotopia(&args);
        assert_ne!(code, 0, "{args:?}");
        assert!(
            err.contains(expect) && err.contains("0.0001° per pixel"),
            "{args:?}: {err}"
        );
        assert!(!err.contains("panicked"), "{err}");
    }
}

/// A 64 × 48 XYZV′ EXR of D65 grey at 20 cd/m² with a lamp, with
/// `broken` applied to its pixels.
fn grey_exr(dir: &Path, name: &str, broken: impl Fn(usize, &mut [f32; 4])) -> PathBuf {
    let (w, h) = (64, 48);
    let y = 20.0f32;
    let mut px = vec![[0.9505 * y, y, 1.089 * y, 2.4645 * y]; w * h];
    px[24 * w + 32] = [9.5e4, 1e5, 1.09e5, 2.4e5];
    for (i, p) in px.iter_mut().enumerate() {
        broken(i, p);
    }
    let chan = |c: usize| px.iter().map(|p| p[c]).collect::<Vec<f32>>();
    let path = dir.join(name);
    let chans = ["X", "Y", "Z", "V"]
        .iter()
        .enumerate()
        .map(|(c, n)| (n.to_string(), chan(c)))
        .collect();
    let meta = [("fovHorizontalDegrees", scotopia_image::Meta::F32(30.0))];
    scotopia_image::write_exr(&path, w, h, chans, &meta).unwrap();
    path
}

#[test]
fn nan_and_absurd_pixels_leave_the_rest_of_the_image_alone_and_are_named_once() {
    let dir = out_dir("leftout");
    let in_block = |i: usize| (8..12).contains(&(i % 64)) && (8..12).contains(&(i / 64));
    let clean = grey_exr(&dir, "clean.exr", |_, _| {});
    let broken = grey_exr(&dir, "broken.exr", |i, p| {
        if in_block(i) {
            *p = [f32::NAN; 4];
        }
        if i == 100 {
            *p = [2e38; 4];
        }
    });
    let show = |exr: &Path, png: &str| {
        let png = dir.join(png);
        let (code, out, err) = scotopia(&[
            "display",
            exr.to_str().unwrap(),
            "-o",
            png.to_str().unwrap(),
            "--info",
        ]);
        assert_eq!(code, 0, "{err}");
        (scotopia_image::read_rgb(&png).unwrap(), out, err)
    };
    let (a, out_a, err_a) = show(&clean, "clean.png");
    let (b, out_b, err_b) = show(&broken, "broken.png");
    // Said once on stderr (and in --info), and only when it happens.
    assert_eq!(err_b.matches("left out").count(), 1, "{err_b}");
    assert!(
        err_b.contains("16 non-finite") && err_b.contains("1 pixel(s) above"),
        "{err_b}"
    );
    assert!(!err_a.contains("left out"), "{err_a}");
    // Nearly the same adaptation (the absurd pixel counts in it at 1e10
    // cd/m², as it is shown: (1e10/20)^(1/3056) = 1.0066 at most), and
    // the same 8-bit code values elsewhere.
    let adaptation = |o: &str| -> f64 {
        o.lines()
            .next()
            .unwrap_or_default()
            .split_whitespace()
            .nth(1)
            .unwrap()
            .parse()
            .unwrap()
    };
    let (la, lb) = (adaptation(&out_a), adaptation(&out_b));
    assert!(lb >= la && lb / la < 1.0066, "{out_a}\n{out_b}");
    assert!(out_b.contains("left out"), "{out_b}");
    for i in (0..64 * 48).filter(|&i| !in_block(i) && i != 100) {
        for c in 0..3 {
            let d = (a.pixels[i][c] - b.pixels[i][c]).abs();
            assert!(
                d <= 1.0 / 255.0 + 1e-6,
                "pixel {i}: {:?} {:?}",
                a.pixels[i],
                b.pixels[i]
            );
        }
    }
    // Not black: the grey is shown as grey.
    assert!(b.pixels[0].iter().all(|&v| v > 0.05), "{:?}", b.pixels[0]);
}

#[test]
fn numbers_that_are_0_or_infinite_in_f32_are_errors_naming_the_flag() {
    let dir = out_dir("numbers-f32");
    let exr = grey_exr(&dir, "grey.exr", |_, _| {});
    let e = exr.to_str().unwrap();
    for (flag, value) in [
        ("--display-peak", "1e-300"),
        ("--display-peak", "1e-40"),
        ("--adaptation", "1e39"),
        ("--adaptation", "1e-300"),
        ("--scale", "1e39"),
        ("--scale", "1e38"),
        ("--scale", "1e-300"),
    ] {
        let (code, _, err) = scotopia(&["display", e, "--info", flag, value]);
        assert_eq!(code, 1, "{flag} {value}: {err}");
        assert!(
            err.contains(&format!("error: {flag} ")),
            "{flag} {value}: {err}"
        );
    }
}

#[test]
fn the_mode_reported_is_that_of_the_image_shown_and_negative_pixels_are_warned() {
    let dir = out_dir("mode-shown");
    let exr = grey_exr(&dir, "grey.exr", |i, p| {
        if i < 64 * 12 {
            *p = [0.0; 4];
        }
    });
    let png = dir.join("white.png");
    // 1e20 times a 20 cd/m² grey: shown white (above 1e10 cd/m²); not
    // "scotopic" from the black rows.
    let (code, out, err) = scotopia(&[
        "display",
        exr.to_str().unwrap(),
        "--scale",
        "1e20",
        "--info",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("mode          photopic"), "{out}");
    let shown = scotopia_image::read_rgb(&png).unwrap();
    assert!(
        shown.pixels[64 * 40].iter().all(|&v| v > 0.99),
        "{:?}",
        shown.pixels[64 * 40]
    );
    // Negative luminance: a warning, once.
    let negative = grey_exr(&dir, "negative.exr", |i, p| {
        if i % 2 == 0 {
            p[1] = -p[1];
        }
    });
    let (code, _, err) = scotopia(&["display", negative.to_str().unwrap(), "--info"]);
    assert_eq!(code, 0, "{err}");
    assert_eq!(err.matches("negative luminance").count(), 1, "{err}");
    assert!(err.contains("warning: 1536 pixel(s)"), "{err}");
}

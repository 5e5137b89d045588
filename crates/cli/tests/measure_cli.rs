//! `scotopia measure`: a points file in, a CSV of illuminance out; bad
//! points are errors naming the file and line.

mod common;

use common::{out_dir, scenes, scotopia};

#[test]
fn measures_the_night_street_and_writes_the_documented_columns() {
    let dir = out_dir("measure", "street");
    let points = dir.join("points.csv");
    std::fs::write(
        &points,
        "x,y,z,nx,ny,nz\n# under the sodium lamp, and under the LED\n-4,0.01,-8,0,1,0\n\n4,0.01,-16,0,1,0\n",
    )
    .unwrap();
    let out = dir.join("out.csv");
    let scene = scenes().join("night-street.xml");
    let (code, _, err) = scotopia(&[
        "measure",
        scene.to_str().unwrap(),
        "--points",
        points.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--spp",
        "64",
        "--reflectance",
        "0.1",
    ]);
    assert_eq!(code, 0, "{err}");
    let csv = std::fs::read_to_string(&out).unwrap();
    let lines: Vec<&str> = csv.lines().collect();
    assert_eq!(
        lines[0],
        "x,y,z,nx,ny,nz,E_lx,E_lx_se,Es_lx,Es_lx_se,SP,L_cdm2,m,Lmes_cdm2,\
         scEDI_lx,mcEDI_lx,lcEDI_lx,rhEDI_lx,mEDI_lx"
    );
    assert_eq!(lines.len(), 3, "{csv}");
    let row = |i: usize| -> Vec<f64> { lines[i].split(',').map(|v| v.parse().unwrap()).collect() };
    let (sodium, led) = (row(1), row(2));
    // Lit, with standard errors, and sodium light is poor for the rods.
    assert!(sodium[6] > 1.0 && sodium[7] > 0.0 && led[6] > 1.0, "{csv}");
    assert!(
        sodium[10] < led[10],
        "S/P sodium {} LED {}",
        sodium[10],
        led[10]
    );
    // CIE 191 on a road of reflectance 0.1: L = 0.1 E/π; the mesopic eye
    // sees the sodium-lit road darker than photopic L, the LED-lit brighter.
    for r in [&sodium, &led] {
        let l = 0.1 * r[6] / std::f64::consts::PI;
        assert!((r[11] / l - 1.0).abs() < 1e-4, "{csv}");
        assert!(r[12] > 0.0 && r[12] < 1.0, "m {}: {csv}", r[12]);
    }
    assert!(sodium[13] < sodium[11] && led[13] > led[11], "{csv}");
    // Melanopic light per lux (CIE S 026): where the sodium lamps light
    // the road (0.18, some of the LEDs' light reaching it too), under half
    // of where the LEDs do (0.44).
    let mel = |r: &Vec<f64>| r[18] / r[6];
    assert!(mel(&sodium) < 0.5 * mel(&led), "{csv}");
    assert!(mel(&led) > 0.3 && mel(&led) < 0.7, "{csv}");
}

#[test]
fn a_scene_without_a_sensor_can_be_measured() {
    // A lighting model need not have a camera.
    let dir = out_dir("measure", "no-sensor");
    let scene = dir.join("lamp.xml");
    std::fs::write(
        &scene,
        r#"<scene version="3.0.0"><emitter type="point"><point name="position" x="0" y="2" z="0"/>
          <spectrum name="intensity" type="d65"><float name="luminance" value="400"/></spectrum></emitter></scene>"#,
    )
    .unwrap();
    let points = dir.join("points.csv");
    // A header after comment lines is still a header.
    std::fs::write(&points, "# one point\nx,y,z,nx,ny,nz\n0,0,0,0,1,0\n").unwrap();
    let out = dir.join("out.csv");
    let (code, _, err) = scotopia(&[
        "measure",
        scene.to_str().unwrap(),
        "--points",
        points.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--spp",
        "256",
    ]);
    assert_eq!(code, 0, "{err}");
    let csv = std::fs::read_to_string(&out).unwrap();
    let row: Vec<f64> = csv
        .lines()
        .nth(1)
        .unwrap()
        .split(',')
        .map(|v| v.parse().unwrap())
        .collect();
    // 400 cd at 2 m: 100 lx (the noise is the wavelengths').
    assert!((row[6] - 100.0).abs() <= 4.0 * row[7] + 0.5, "{csv}");
    // render still needs a sensor.
    let (code, _, err) = scotopia(&[
        "render",
        scene.to_str().unwrap(),
        "-o",
        dir.join("x.exr").to_str().unwrap(),
    ]);
    assert_eq!(code, 1);
    assert!(err.contains("no <sensor>"), "{err}");
}

#[test]
fn a_bad_point_is_an_error_naming_the_file_and_line() {
    let dir = out_dir("measure", "bad");
    let scene = scenes().join("cornell-box.xml");
    for (text, line, what) in [
        ("0,0,0,0,1,0\n1,2,3\n", ":2:", "six numbers"),
        ("0,0,0,0,1,0\n0,0,0,0,0,0\n", ":2:", "zero"),
        ("0,0,0,0,1,0\n0,0,x,0,1,0\n", ":2:", "six numbers"),
        ("0,0,nan,0,1,0\n", ":1:", "finite"),
    ] {
        let points = dir.join("points.csv");
        std::fs::write(&points, text).unwrap();
        let (code, _, err) = scotopia(&[
            "measure",
            scene.to_str().unwrap(),
            "--points",
            points.to_str().unwrap(),
            "-o",
            dir.join("o.csv").to_str().unwrap(),
        ]);
        assert_eq!(code, 1, "{text}: {err}");
        assert!(
            err.contains(&format!("points.csv{line}")) && err.contains(what),
            "{text}: {err}"
        );
    }
}

#[test]
fn an_illuminance_image_becomes_a_false_colour_map_with_a_scale_bar() {
    let dir = out_dir("measure", "false-colour");
    let scene = scenes().join("cornell-box.xml");
    let (lux, png) = (dir.join("lux.exr"), dir.join("lux.png"));
    let s = |p: &std::path::Path| p.to_str().unwrap().to_string();
    let (code, _, err) = scotopia(&[
        "render",
        &s(&scene),
        "--res",
        "32",
        "--spp",
        "4",
        "--quantity",
        "illuminance",
        "-o",
        &s(&lux),
    ]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = scotopia(&[
        "display",
        &s(&lux),
        "--false-colour",
        "illuminance",
        "--log",
        "-o",
        &s(&png),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(err.contains("lx (log)"), "{err}");
    // The picture, then the scale bar below it (IHDR's width and height).
    let bytes = std::fs::read(&png).unwrap();
    let be = |i: usize| u32::from_be_bytes(bytes[i..i + 4].try_into().unwrap());
    assert!(be(16) == 32 && be(20) > 32 + 20, "{} × {}", be(16), be(20));
    // Luminance asked of an illuminance image: an error saying what it holds.
    let (code, _, err) = scotopia(&[
        "display",
        &s(&lux),
        "--false-colour",
        "luminance",
        "-o",
        &s(&png),
    ]);
    assert_eq!(code, 1);
    assert!(err.contains("holds illuminance"), "{err}");
    let (code, _, err) = scotopia(&[
        "display",
        &s(&lux),
        "--false-colour",
        "illuminance",
        "--range",
        "5:1",
        "-o",
        &s(&png),
    ]);
    assert_eq!(code, 1);
    assert!(err.contains("LO < HI"), "{err}");
}

#[test]
fn a_radiance_image_gives_a_mesopic_false_colour_map() {
    let dir = out_dir("measure", "mesopic");
    let scene = scenes().join("night-street.xml");
    let (exr, png) = (dir.join("street.exr"), dir.join("mesopic.png"));
    let s = |p: &std::path::Path| p.to_str().unwrap().to_string();
    let (code, _, err) = scotopia(&[
        "render",
        &s(&scene),
        "--res",
        "32",
        "--spp",
        "2",
        "-o",
        &s(&exr),
    ]);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = scotopia(&[
        "display",
        &s(&exr),
        "--false-colour",
        "mesopic",
        "--log",
        "-o",
        &s(&png),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("false colour of mesopic") && err.contains("cd/m2"),
        "{err}"
    );
    assert!(std::fs::metadata(&png).unwrap().len() > 100);
    let (code, _, err) = scotopia(&[
        "display",
        &s(&exr),
        "--false-colour",
        "photons",
        "-o",
        &s(&png),
    ]);
    assert_eq!(code, 1);
    assert!(
        err.contains("luminance, mesopic, illuminance or melanopic-edi"),
        "{err}"
    );
}

/// `scotopia measure` of a 400 cd point lamp 2 m above the origin, with
/// `text` as the points file: (exit code, output CSV rows, stderr).
fn measure_lamp(name: &str, text: &[u8]) -> (i32, Vec<Vec<f64>>, String) {
    let dir = out_dir("measure", name);
    let scene = dir.join("lamp.xml");
    std::fs::write(
        &scene,
        r#"<scene version="3.0.0"><emitter type="point"><point name="position" x="0" y="2" z="0"/>
          <spectrum name="intensity" type="d65"><float name="luminance" value="400"/></spectrum></emitter></scene>"#,
    )
    .unwrap();
    let points = dir.join("points.csv");
    std::fs::write(&points, text).unwrap();
    let out = dir.join("out.csv");
    let _ = std::fs::remove_file(&out);
    let (code, _, err) = scotopia(&[
        "measure",
        scene.to_str().unwrap(),
        "--points",
        points.to_str().unwrap(),
        "-o",
        out.to_str().unwrap(),
        "--spp",
        "16",
    ]);
    let rows = std::fs::read_to_string(&out)
        .unwrap_or_default()
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    (code, rows, err)
}

#[test]
fn points_files_are_read_as_written() {
    // A BOM, a header known by its words, CR, CRLF or LF line endings: the
    // same two points.
    for (name, text) in [
        ("lf", &b"x,y,z,nx,ny,nz\n0,0,0,0,1,0\n1,0,0,0,1,0\n"[..]),
        ("bom", b"\xef\xbb\xbf0,0,0,0,1,0\n1,0,0,0,1,0\n"),
        (
            "bom-header",
            b"\xef\xbb\xbf\"X\", \"Y\", \"Z\", NX, NY, NZ\r\n0,0,0,0,1,0\r\n1,0,0,0,1,0\r\n",
        ),
        ("cr", b"# grid\rx,y,z,nx,ny,nz\r0,0,0,0,1,0\r1,0,0,0,1,0\r"),
    ] {
        let (code, rows, err) = measure_lamp(name, text);
        assert_eq!(code, 0, "{name}: {err}");
        assert_eq!(rows.len(), 2, "{name}");
        // 400 cd at 2 m: 100 lx (the noise is the wavelengths').
        assert!((rows[0][6] - 100.0).abs() < 10.0, "{name}: {rows:?}");
    }
}

#[test]
fn a_row_that_does_not_parse_is_an_error_naming_its_line_even_first() {
    for (text, line) in [
        // A typo in the first row is not a header: the point is not lost.
        (&b"0,0,O,0,1,0\n1,0,0,0,1,0\n"[..], ":1:"),
        (
            b"# grid\n\nx,y,z,nx,ny,nz\n0,0,0,0,1,0\nx,y,z,nx,ny,nz\n",
            ":5:",
        ),
        (b"position,normal\n0,0,0,0,1,0\n", ":1:"),
        (b"0,0,0,0,1,0\r1,0,0,0,1,O\r", ":2:"),
        (b"0,0,0,0,1e39,0\n", ":1:"),
    ] {
        let (code, _, err) = measure_lamp("bad-row", text);
        assert_eq!(code, 1, "{:?}: {err}", String::from_utf8_lossy(text));
        assert!(err.contains(&format!("points.csv{line}")), "{err}");
    }
}

#[test]
fn a_very_large_normal_is_normalised_not_zero() {
    let (code, rows, err) = measure_lamp(
        "huge-normal",
        b"0,0,0,3e38,3e38,3e38\n0,0,0,0,1e-40,0\n0,0,0,0,1,0\n",
    );
    assert_eq!(code, 0, "{err}");
    // (1,1,1)/√3 sees the lamp at 54.7° from its normal: cos = 1/√3.
    assert!((rows[0][6] - 100.0 / 3f64.sqrt()).abs() < 10.0, "{rows:?}");
    // A subnormal normal is a normal too: 100 lx straight up.
    assert!((rows[1][6] - 100.0).abs() < 10.0, "{rows:?}");
}

#[cfg(target_os = "linux")]
#[test]
fn an_endless_points_file_is_refused_at_its_size_limit() {
    let dir = out_dir("measure", "dev-zero");
    let (code, _, err) = scotopia(&[
        "measure",
        common::scenes().join("cornell-box.xml").to_str().unwrap(),
        "--points",
        "/dev/zero",
        "-o",
        dir.join("o.csv").to_str().unwrap(),
    ]);
    assert_eq!(code, 1, "{err}");
    assert!(
        err.contains("/dev/zero") && err.contains("limit of 64 MiB"),
        "{err}"
    );
}

#[test]
fn a_melanopic_image_names_its_channel_and_is_mapped_not_seen() {
    let dir = out_dir("measure", "melanopic");
    let scene = scenes().join("cornell-box.xml");
    let (mel, png) = (dir.join("mel.exr"), dir.join("mel.png"));
    let s = |p: &std::path::Path| p.to_str().unwrap().to_string();
    let (code, _, err) = scotopia(&[
        "render",
        &s(&scene),
        "--res",
        "16",
        "--spp",
        "2",
        "--quantity",
        "melanopic-edi",
        "-o",
        &s(&mel),
    ]);
    assert_eq!(code, 0, "{err}");
    // X, Y, Z and mEDI: no V channel for anything to take it for V′. (In
    // the header's channel list each name ends in NUL, then its pixel type,
    // 2 for f32, and each entry in its y sampling, 1.)
    let header = std::fs::read(&mel).unwrap();
    let has = |name: &[u8]| header.windows(name.len()).any(|w| w == name);
    assert!(has(b"\x01\0\0\0mEDI\0\x02\0\0\0"), "no mEDI channel");
    assert!(has(b"\x01\0\0\0Z\0\x02\0\0\0") && !has(b"\x01\0\0\0V\0\x02\0\0\0"));
    for (map, ok) in [
        ("melanopic-edi", true),
        ("illuminance", true),
        ("luminance", false),
    ] {
        let (code, _, err) =
            scotopia(&["display", &s(&mel), "--false-colour", map, "-o", &s(&png)]);
        assert_eq!(code == 0, ok, "{map}: {err}");
    }
    // The eye model is for radiance.
    let (code, _, err) = scotopia(&["display", &s(&mel), "-o", &s(&png)]);
    assert_eq!(code, 1);
    assert!(err.contains("--false-colour melanopic-edi"), "{err}");
}

#[test]
fn cylinders_are_measured_along_up_and_a_bad_facing_names_its_line() {
    // 400 cd at (2, 2, 0), 2√2 m from the point at the origin, 45° up:
    // E_z = I sin θ/(π d²) = 400·0.7071/(8π) = 11.25 lx along y; along x
    // (--up 1,0,0) sin θ is the same, so is E_z.
    let dir = out_dir("measure", "cylinders");
    let scene = dir.join("lamp.xml");
    std::fs::write(
        &scene,
        r#"<scene version="3.0.0"><emitter type="point"><point name="position" x="2" y="2" z="0"/>
          <spectrum name="intensity" type="d65"><float name="luminance" value="400"/></spectrum></emitter></scene>"#,
    )
    .unwrap();
    let points = dir.join("points.csv");
    std::fs::write(&points, "x,y,z,nx,ny,nz\n# the point\n0,0,0,0,0,1\n").unwrap();
    let out = dir.join("out.csv");
    let s = |p: &std::path::Path| p.to_str().unwrap().to_string();
    for up in ["0,1,0", "1,0,0"] {
        let (code, _, err) = scotopia(&[
            "measure",
            &s(&scene),
            "--points",
            &s(&points),
            "-o",
            &s(&out),
            "--spp",
            "256",
            "--receiver",
            "cylindrical",
            "--up",
            up,
        ]);
        assert_eq!(code, 0, "{err}");
        let csv = std::fs::read_to_string(&out).unwrap();
        let row: Vec<&str> = csv.lines().nth(1).unwrap().split(',').collect();
        let (e, se): (f64, f64) = (row[6].parse().unwrap(), row[7].parse().unwrap());
        let want = 400.0 * 0.5f64.sqrt() / (8.0 * std::f64::consts::PI);
        assert!((e - want).abs() <= 4.0 * se + 5e-3 * want, "{up}: {csv}");
        // No surface's luminance for a cylinder.
        assert_eq!(&row[11..14], ["NaN"; 3], "{csv}");
    }
    // A half-cylinder along z facing z: the error names the file and line.
    let (code, _, err) = scotopia(&[
        "measure",
        &s(&scene),
        "--points",
        &s(&points),
        "-o",
        &s(&out),
        "--receiver",
        "semicylindrical",
        "--up",
        "0,0,2",
    ]);
    assert_eq!(code, 1);
    assert!(
        err.contains("points.csv:3:") && err.contains("along it"),
        "{err}"
    );
}

#[test]
fn an_observer_adds_the_luminance_it_sees_and_direct_light_is_less() {
    // The night street's road seen from a driver's eye 60 m before the
    // points, 1.5 m up: the columns the standard's luminance method needs.
    let dir = out_dir("measure", "observer");
    let points = dir.join("points.csv");
    std::fs::write(&points, "-4,0.0,-8,0,1,0\n4,0.0,-16,0,1,0\n").unwrap();
    let scene = scenes().join("night-street.xml");
    let run = |direct: bool| {
        let out = dir.join(format!("out-{direct}.csv"));
        let mut args = vec![
            "measure",
            scene.to_str().unwrap(),
            "--points",
            points.to_str().unwrap(),
            "-o",
            out.to_str().unwrap(),
            "--spp",
            "128",
            "--observer=0,1.5,50",
        ];
        if direct {
            args.push("--direct");
        }
        let (code, _, err) = scotopia(&args);
        assert_eq!(code, 0, "{err}");
        std::fs::read_to_string(&out).unwrap()
    };
    let full = run(false);
    let direct = run(true);
    let lines: Vec<&str> = full.lines().collect();
    assert!(
        lines[0].ends_with(",mEDI_lx,Lobs_cdm2,Lobs_cdm2_se,Lobs_SP,Lobs_mes_cdm2"),
        "{}",
        lines[0]
    );
    let last = |csv: &str, row: usize, col: usize| -> f64 {
        let line = csv.lines().nth(row).unwrap();
        let cells: Vec<f64> = line.split(',').map(|v| v.parse().unwrap()).collect();
        assert_eq!(cells.len(), 23, "{line}");
        cells[col]
    };
    for row in 1..=2 {
        let (l, se) = (last(&full, row, 19), last(&full, row, 20));
        let (ld, sed) = (last(&direct, row, 19), last(&direct, row, 20));
        assert!(l > 0.0 && se > 0.0 && ld > 0.0, "{full}");
        // Direct light alone is no more than all of it (within noise).
        assert!(
            ld <= l + 4.0 * (se * se + sed * sed).sqrt(),
            "{ld} ± {sed} against {l} ± {se}"
        );
        // The illuminance likewise.
        assert!(last(&direct, row, 6) <= last(&full, row, 6) + 4.0 * last(&full, row, 7));
    }
    let (code, _, err) = scotopia(&[
        "measure",
        scene.to_str().unwrap(),
        "--points",
        points.to_str().unwrap(),
        "-o",
        dir.join("x.csv").to_str().unwrap(),
        "--observer",
        "1,2",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("X,Y,Z"), "{err}");
}

//! `scotopia spectrum` end to end: the binary, its JSON, its errors.

mod common;

use common::scotopia;

#[test]
fn json_report_has_the_documented_fields() {
    let (code, out, _) = scotopia(&["spectrum", "--illuminant", "A", "--json"]);
    assert_eq!(code, 0);
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let keys: Vec<&str> = v.as_object().unwrap().keys().map(|k| k.as_str()).collect();
    assert_eq!(
        keys,
        [
            "xyz",
            "xy",
            "vprime",
            "sp_ratio",
            "cct",
            "duv",
            "wavelengths",
            "values"
        ]
    );
    let xy = v["xy"].as_array().unwrap();
    assert!((xy[0].as_f64().unwrap() - 0.44757).abs() < 2e-5);
    assert!((v["cct"].as_f64().unwrap() - 2855.5).abs() < 1.0);
    assert_eq!(v["wavelengths"].as_array().unwrap().len(), 471);
    assert_eq!(v["wavelengths"][0], 360);
    assert_eq!(v["wavelengths"][470], 830);
    assert_eq!(v["values"].as_array().unwrap().len(), 471);
    // X, Y, Z are the integrals: Y / V′ is consistent with the S/P ratio.
    let y = v["xyz"][1].as_f64().unwrap();
    let sp = v["sp_ratio"].as_f64().unwrap();
    assert!((v["vprime"].as_f64().unwrap() / y - sp).abs() < 1e-12);
}

#[test]
fn every_source_works() {
    let dir = std::env::temp_dir().join(format!("scotopia-cli-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("lamp.csv");
    std::fs::write(&file, "wavelength,value\n400,1\n700,1\n").unwrap();
    let plot = dir.join("plot.png");
    for args in [
        vec!["--blackbody", "2700"],
        vec!["--daylight", "6500"],
        vec!["--file", file.to_str().unwrap()],
        vec![
            "--rgb",
            "0.2,0.4,0.6",
            "--space",
            "rec2020",
            "--method",
            "smits",
            "--kind",
            "illuminant",
        ],
        vec!["--illuminant", "F11", "--plot", plot.to_str().unwrap()],
    ] {
        let mut all = vec!["spectrum"];
        all.extend(args.iter().copied());
        let (code, out, err) = scotopia(&all);
        assert_eq!(code, 0, "{args:?}: {err}");
        assert!(out.contains("CCT"), "{out}");
    }
    assert!(std::fs::read(&plot).unwrap().starts_with(b"\x89PNG"));
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn bad_input_is_reported_not_panicked() {
    let dir = std::env::temp_dir().join(format!("scotopia-cli-bad-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let file = dir.join("bad.spd");
    std::fs::write(&file, "400 1\n450 2\n440 3\n").unwrap();
    let (code, _, err) = scotopia(&["spectrum", "--file", file.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(
        err.contains("bad.spd:3: wavelength 440 nm does not increase"),
        "{err}"
    );
    assert!(!err.contains("panicked"));
    for (args, needle) in [
        (
            vec!["spectrum", "--illuminant", "Z9"],
            "unknown illuminant 'Z9'",
        ),
        (vec!["spectrum", "--blackbody", "-5"], "must be positive"),
        (vec!["spectrum", "--rgb", "2,0,0"], "above 1"),
        (vec!["spectrum", "--rgb", "1,x,0"], "'x' is not a number"),
        (
            vec!["spectrum", "--file", "/nonexistent.csv"],
            "/nonexistent.csv",
        ),
    ] {
        let (code, _, err) = scotopia(&args);
        assert_ne!(code, 0, "{args:?}");
        assert!(err.contains(needle), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{err}");
    }
    let (code, _, err) = scotopia(&["spectrum"]);
    assert_eq!(code, 2, "no source is a usage error: {err}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn info_describes_the_cornell_box() {
    let scene = concat!(env!("CARGO_MANIFEST_DIR"), "/../../scenes/cornell-box.xml");
    let (code, out, err) = scotopia(&["info", scene, "--json", "-D", "res=100"]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    assert_eq!(v["shapes"], 8);
    assert_eq!(v["triangles"], 24);
    assert_eq!(v["film"]["width"], 100);
    assert_eq!(v["lights"][0]["type"], "area");
    assert!(v["lights"][0]["lumens"].as_f64().unwrap() > 0.0);
    let (code, out, _) = scotopia(&["info", scene]);
    assert_eq!(code, 0);
    assert!(out.contains("pixel_format") && out.contains("lm"), "{out}");
    let (code, _, err) = scotopia(&["info", "/nonexistent/scene.xml"]);
    assert_eq!(code, 1);
    assert!(
        err.contains("/nonexistent/scene.xml") && !err.contains("panicked"),
        "{err}"
    );
    let (code, _, err) = scotopia(&["info", scene, "-D", "novalue"]);
    assert_eq!(code, 1);
    assert!(err.contains("NAME=VALUE"), "{err}");
}

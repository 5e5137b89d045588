//! `scotopia render` end to end: the EXR and its metadata, bad options,
//! and SIGTERM writing what was accumulated.

use std::path::PathBuf;
use std::process::Command;

mod common;

use common::{scenes, scotopia};

fn out_dir(name: &str) -> PathBuf {
    common::out_dir("render", name)
}

#[test]
fn renders_an_exr_with_channels_and_metadata() {
    let dir = out_dir("ok");
    let exr = dir.join("c.exr");
    let png = dir.join("c.png");
    let scene = scenes().join("cornell-box.xml");
    let (code, _, err) = scotopia(&[
        "render",
        scene.to_str().unwrap(),
        "-D",
        "res=16",
        "--spp",
        "4",
        "--wavelengths",
        "hero",
        "--cluster",
        "8",
        "--seed",
        "5",
        "-o",
        exr.to_str().unwrap(),
        "--preview",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    // No glass in the Cornell box: no cluster collapses, and it says so.
    assert!(
        err.contains("0.00 % of samples had their wavelength cluster collapsed"),
        "{err}"
    );
    let img = scotopia_image::read_exr(&exr).unwrap();
    assert_eq!((img.width, img.height), (16, 16));
    let names: Vec<&str> = img.channels.iter().map(|c| c.0.as_str()).collect();
    assert_eq!(names, ["V", "X", "Y", "Z"]);
    let meta = |k: &str| img.metadata.iter().find(|m| m.0 == k).map(|m| m.1.clone());
    assert_eq!(meta("samplesPerPixel").as_deref(), Some("4"));
    assert_eq!(meta("wavelengthStrategy").as_deref(), Some("hero"));
    assert_eq!(meta("clusterSize").as_deref(), Some("8"));
    assert_eq!(meta("seed").as_deref(), Some("5"));
    assert_eq!(meta("guiding").as_deref(), Some("off"));
    assert!(meta("fovHorizontalDegrees").is_some() && meta("sceneFile").is_some());
    // The Cornell box's light makes a bright image in absolute units.
    let y = &img.channels.iter().find(|c| c.0 == "Y").unwrap().1;
    assert!(y.iter().all(|v| v.is_finite()) && y.iter().sum::<f32>() > 0.0);
    assert!(png.exists());
}

#[test]
fn bad_options_are_clear_errors() {
    let scene = scenes().join("cornell-box.xml");
    let s = scene.to_str().unwrap();
    for (args, needle) in [
        (vec!["--wavelengths", "rgb"], "use swc, hero or single"),
        (vec!["--cluster", "3"], "use one of 1, 2, 4, 8, 16"),
        (vec!["--time=-1"], "positive number of seconds"),
        (vec!["--spp", "0"], "--spp must be positive"),
        (vec!["--guiding", "yes"], "use on or off"),
    ] {
        let mut all = vec!["render", s, "-o", "/nonexistent/x.exr"];
        all.extend(args);
        let (code, _, err) = scotopia(&all);
        assert_ne!(code, 0);
        assert!(err.contains(needle), "{err}");
    }
}

#[test]
fn a_time_limit_ends_the_render_by_itself() {
    // No --spp: render until the time is spent, then write normally with
    // the samples actually reached.
    let dir = out_dir("time");
    let exr = dir.join("t.exr");
    let scene = scenes().join("cornell-box.xml");
    let (code, _, err) = scotopia(&[
        "render",
        scene.to_str().unwrap(),
        "-D",
        "res=32",
        "--time",
        "1",
        "-o",
        exr.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let img = scotopia_image::read_exr(&exr).unwrap();
    let meta = |k: &str| {
        img.metadata
            .iter()
            .find(|m| m.0 == k)
            .map(|m| m.1.clone())
            .unwrap()
    };
    let spp: u32 = meta("samplesPerPixel").parse().unwrap();
    let secs: f32 = meta("renderSeconds").parse().unwrap();
    let rays: u64 = meta("raysTraced").parse().unwrap();
    // More samples than one pass, far fewer than unbounded; each sample
    // traced at least its camera ray.
    assert!(spp > 16 && spp < 10_000_000, "{spp}");
    assert!(rays >= spp as u64 * 32 * 32, "{rays}");
    assert!(secs >= 0.5, "{secs}");
    assert_eq!(meta("interrupted"), "0");
}

#[cfg(unix)]
#[test]
fn sigterm_writes_what_was_accumulated() {
    let dir = out_dir("term");
    let exr = dir.join("t.exr");
    let scene = scenes().join("cornell-box.xml");
    let mut child = Command::new(env!("CARGO_BIN_EXE_scotopia"))
        .args([
            "render",
            scene.to_str().unwrap(),
            "-D",
            "res=64",
            "--spp",
            "1000000",
            "-o",
            exr.to_str().unwrap(),
        ])
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(1500));
    let _ = Command::new("kill")
        .args(["-TERM", &child.id().to_string()])
        .status();
    let status = child.wait().unwrap();
    assert!(!status.success());
    let img = scotopia_image::read_exr(&exr).expect("the partial image is written");
    let spp: u32 = img
        .metadata
        .iter()
        .find(|m| m.0 == "samplesPerPixel")
        .unwrap()
        .1
        .parse()
        .unwrap();
    assert!(spp > 0 && spp < 1_000_000, "{spp}");
    assert!(img
        .metadata
        .iter()
        .any(|m| m.0 == "interrupted" && m.1 == "1"));
}

#[test]
fn spectral_exr_follows_fichet_2021_and_integrates_to_y() {
    let dir = out_dir("spectral");
    let (exr, spectral) = (dir.join("c.exr"), dir.join("s.exr"));
    let scene = scenes().join("cornell-box.xml");
    let (code, _, err) = scotopia(&[
        "render",
        scene.to_str().unwrap(),
        "-D",
        "res=12",
        "--spp",
        "64",
        "-o",
        exr.to_str().unwrap(),
        "--spectral",
        spectral.to_str().unwrap(),
        "--bands",
        "94",
    ]);
    assert_eq!(code, 0, "{err}");
    let s = scotopia_image::read_exr(&spectral).unwrap();
    assert_eq!(s.channels.len(), 94);
    assert!(
        s.channels.iter().any(|c| c.0 == "S0.362,500000nm"),
        "{:?}",
        s.channels[0].0
    );
    assert!(s
        .metadata
        .iter()
        .any(|m| m.0 == "emissiveUnits" && m.1 == "W.m^-2.sr^-1"));
    // 683 Σ L_band ȳ(λ_band) Δλ reproduces the Y image (5 nm bands).
    let xyz = scotopia_image::read_exr(&exr).unwrap();
    let y = &xyz.channels.iter().find(|c| c.0 == "Y").unwrap().1;
    let mean_y = y.iter().map(|v| *v as f64).sum::<f64>() / y.len() as f64;
    let mut from_bands = 0.0;
    for (name, values) in &s.channels {
        let lambda: f64 = name[3..name.len() - 2].replace(',', ".").parse().unwrap();
        let mean = values.iter().map(|v| *v as f64).sum::<f64>() / values.len() as f64;
        from_bands += 683.0 * mean * scotopia_color::cie::xyz_bar(lambda as f32)[1] as f64 * 5.0;
    }
    assert!(
        (from_bands / mean_y - 1.0).abs() < 0.01,
        "{from_bands} vs {mean_y}"
    );
}

#[test]
fn a_checkpointed_render_resumes_to_the_same_bits() {
    let dir = out_dir("checkpoint");
    let (a, b) = (dir.join("a.exr"), dir.join("b.exr"));
    let ckpt = dir.join("a.exr.ckpt");
    let _ = std::fs::remove_file(&ckpt);
    let scene = scenes().join("cornell-box.xml");
    let run = |out: &PathBuf, extra: &[&str]| {
        let mut args = vec![
            "render",
            scene.to_str().unwrap(),
            "-D",
            "res=10",
            "--seed",
            "9",
            "-o",
            out.to_str().unwrap(),
        ];
        args.extend_from_slice(extra);
        scotopia(&args)
    };
    let (code, _, err) = run(&a, &["--spp", "8", "--checkpoint", "0"]);
    assert_eq!(code, 0, "{err}");
    assert!(ckpt.exists());
    let (code, _, err) = run(&a, &["--spp", "24", "--resume"]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("resuming from") && err.contains("(8 spp)"),
        "{err}"
    );
    let (code, _, err) = run(&b, &["--spp", "24"]);
    assert_eq!(code, 0, "{err}");
    let (ea, eb) = (
        scotopia_image::read_exr(&a).unwrap(),
        scotopia_image::read_exr(&b).unwrap(),
    );
    assert!(!ea.channels.is_empty());
    assert_eq!(
        ea.channels, eb.channels,
        "resumed and uninterrupted renders differ"
    );
    // Other options make another render: refused, naming the checkpoint.
    let (code, _, err) = run(&a, &["--spp", "24", "--resume", "--cluster", "8"]);
    assert_ne!(code, 0);
    assert!(
        err.contains("a.exr.ckpt") && err.contains("another scene"),
        "{err}"
    );
}

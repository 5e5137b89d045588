//! `scotopia view`: the server's routes, spoken to over plain HTTP by
//! hand while a real render runs: the status grows as the film
//! converges, the picture follows the query's settings (named as
//! `display`'s flags), bad settings are errors, a pixel's values are the
//! film's, saving and Ctrl-C write the film, a busy port is an error.

use std::net::TcpListener;
use std::path::Path;
use std::time::{Duration, Instant};

mod common;
mod viewer;

use common::{out_dir, scenes, scotopia};
use scotopia_image::{read_xyzv, RgbInput};
use viewer::{decode, Viewer};

fn cornell(extra: &[&str], out: &Path) -> Vec<String> {
    let scene = scenes().join("cornell-box.xml");
    let mut args: Vec<String> = vec![scene.display().to_string(), "-o".into()];
    args.push(out.display().to_string());
    args.extend(["-D", "res=24"].map(String::from));
    args.extend(extra.iter().map(|s| s.to_string()));
    args
}

#[test]
fn the_status_grows_while_the_film_converges() {
    let dir = out_dir("view", "grows");
    let args = cornell(&["--time", "4"], &dir.join("c.exr"));
    let v = Viewer::start(&args.iter().map(String::as_str).collect::<Vec<_>>());
    let mut seen = Vec::new();
    let deadline = Instant::now() + Duration::from_secs(120);
    loop {
        let s = v.status();
        if s["phase"] == "rendering" {
            seen.push(s["spp"].as_u64().unwrap());
            // The picture is there while the render runs.
            let (code, head, _) = v.request("GET", "/image.png");
            assert_eq!(code, 200);
            assert!(head.contains("x-scotopia-spp"), "{head}");
        } else {
            assert_eq!(s["phase"], "done", "{s}");
            assert!(s["spp"].as_u64().unwrap() >= *seen.last().unwrap_or(&0));
            break;
        }
        assert!(Instant::now() < deadline, "a 4 s render did not end");
        std::thread::sleep(Duration::from_millis(100));
    }
    seen.dedup();
    let growing: Vec<u64> = seen.iter().copied().filter(|&n| n > 0).collect();
    assert!(
        growing.len() >= 2 && growing.windows(2).all(|w| w[0] < w[1]),
        "the page saw the film at {seen:?} spp"
    );
}

#[test]
fn the_picture_follows_the_settings_and_bad_settings_are_errors() {
    let dir = out_dir("view", "settings");
    let exr = dir.join("c.exr");
    let args = cornell(&["--spp", "16", "--adaptation", "local"], &exr);
    let v = Viewer::start(&args.iter().map(String::as_str).collect::<Vec<_>>());
    let s = v.wait_until_done();
    // The command line's settings are the page's first.
    assert_eq!(s["settings"]["adaptation"], "local", "{s}");
    assert_eq!(
        (s["width"].as_u64(), s["height"].as_u64()),
        (Some(24), Some(24))
    );

    let (code, head, bright) = v.request("GET", "/image.png?scale=1000&adaptation=global");
    assert_eq!(code, 200);
    assert!(head.contains("content-type: image/png"), "{head}");
    let (_, dark_head, dark) = v.request("GET", "/image.png?scale=0.0000001&adaptation=global");
    let ((w, h, a), (_, _, b)) = (decode(&bright), decode(&dark));
    assert_eq!((w, h), (24, 24));
    let mean = |p: &[u8]| p.iter().map(|&c| c as f64).sum::<f64>() / p.len() as f64;
    assert!(mean(&a) > mean(&b) + 10.0, "{} vs {}", mean(&a), mean(&b));
    // The headers say what the eye did: cones by day, rods too at 1e-7
    // (at full power the box is lit like a sunny day).
    assert!(head.contains("x-scotopia-mode: photopic"), "{head}");
    assert!(
        dark_head.contains("x-scotopia-mode: mesopic"),
        "{dark_head}"
    );
    // A picture asked for changes nothing: the settings are still the
    // command line's.
    assert_eq!(v.status()["settings"]["scale"], "1");

    // The stages side by side, and a false-colour map with its legend.
    let (_, _, stages) = v.request("GET", "/image.png?view=stages");
    assert!(decode(&stages).0 > 4 * 24);
    let (code, head, _) = v.request("GET", "/image.png?view=false-colour&log=on");
    assert_eq!(code, 200);
    assert!(head.contains("x-scotopia-legend"), "{head}");

    // The observer: an older eye is accepted (and not kept).
    let (code, _, _) = v.request("GET", "/image.png?age=70&pigmentation=1");
    assert_eq!(code, 200);
    assert_eq!(v.status()["settings"]["age"], "25");

    for (query, says) in [
        ("adaptation=sideways", "--adaptation sideways"),
        ("age=-3", "--age"),
        ("age=old", "--age"),
        ("pigmentation=1.5", "--pigmentation"),
        ("colour=blue", "unknown setting 'colour'"),
        ("scale=-2", "--scale -2"),
        ("scale=abc", "--scale"),
        ("night_shift=maybe", "--night-shift maybe"),
        (
            "view=false-colour&false-colour=illuminance",
            "holds radiance",
        ),
    ] {
        let (code, _, body) = v.request("GET", &format!("/image.png?{query}"));
        let body = String::from_utf8_lossy(&body);
        assert_eq!(code, 400, "{query}: {body}");
        assert!(body.contains(says), "{query}: {body}");
    }
    let (code, _, _) = v.request("GET", "/nothing");
    assert_eq!(code, 404);
    let (code, _, _) = v.request("GET", "/save");
    assert_eq!(code, 405);

    // A pixel's values are the film's, times the light level.
    let (code, _, body) = v.save(serde_json::json!({"scale": 1}));
    assert_eq!(code, 200, "{}", String::from_utf8_lossy(&body));
    let film = read_xyzv(&exr, RgbInput::default()).unwrap();
    assert!(dir.join("c.png").exists());
    let p = v.json("/pixel?x=5&y=7&scale=2");
    let want = film.pixels[7 * 24 + 5];
    for (i, c) in ["X", "Y", "Z", "V"].into_iter().enumerate() {
        assert_eq!(p[c].as_f64().unwrap() as f32, want[i] * 2.0, "{c}: {p}");
    }
    let sp = p["sp_ratio"].as_f64().unwrap();
    assert!((sp - f64::from(want[3] / want[1])).abs() < 1e-6, "{p}");
    let (code, _, body) = v.request("GET", "/pixel?x=24&y=0");
    assert_eq!(code, 400);
    assert!(String::from_utf8_lossy(&body).contains("outside the 24×24 image"));

    // Ctrl-C after the render: the page goes, nothing is lost.
    let (code, _) = v.interrupt();
    assert_eq!(code, 0);

    // The saved EXR opens as an image.
    let v = Viewer::start(&[
        exr.to_str().unwrap(),
        "-o",
        dir.join("again.exr").to_str().unwrap(),
    ]);
    let s = v.status();
    assert_eq!(s["phase"], "image", "{s}");
    let (code, _, png) = v.request("GET", "/image.png");
    assert_eq!(code, 200);
    assert_eq!(decode(&png).0, 24);
}

#[test]
fn ctrl_c_during_the_render_writes_the_film() {
    let dir = out_dir("view", "interrupt");
    let exr = dir.join("c.exr");
    let args = cornell(&["--time", "600"], &exr);
    let v = Viewer::start(&args.iter().map(String::as_str).collect::<Vec<_>>());
    let deadline = Instant::now() + Duration::from_secs(60);
    while v.status()["spp"].as_u64().unwrap() == 0 {
        assert!(Instant::now() < deadline);
        std::thread::sleep(Duration::from_millis(50));
    }
    let (code, said) = v.interrupt();
    assert_ne!(code, 0, "an interrupted render says so: {said}");
    assert!(said.contains("interrupted: wrote the"), "{said}");
    let film = read_xyzv(&exr, RgbInput::default()).unwrap();
    assert!(film.pixels.iter().any(|p| p[1] > 0.0));
}

#[test]
fn a_busy_port_is_an_error_naming_it() {
    let taken = TcpListener::bind("127.0.0.1:0").unwrap();
    let port = taken.local_addr().unwrap().port().to_string();
    let scene = scenes().join("cornell-box.xml");
    let (code, _, err) = scotopia(&[
        "view",
        scene.to_str().unwrap(),
        "--no-open",
        "--port",
        &port,
    ]);
    assert_ne!(code, 0);
    assert!(
        err.contains(&format!("--port {port}: cannot listen")),
        "{err}"
    );
    // Bad starting settings are errors before anything starts.
    let (code, _, err) = scotopia(&["view", scene.to_str().unwrap(), "--scale", "0"]);
    assert_ne!(code, 0);
    assert!(err.contains("--scale 0"), "{err}");
}

//! `scotopia glare` on fisheye pictures made here: a uniform sky, and a
//! sky with a bright disc, against the figures' own formulas.

mod common;

use common::{out_dir, scotopia};
use scotopia_image::{write_exr, Meta};

/// A 180° angular fisheye EXR of `n` × `n` pixels: a sky of `sky` cd/m²
/// and a disc of `lamp` cd/m², 3° in radius, 30° above the centre.
fn fisheye(path: &std::path::Path, n: usize, sky: f32, lamp: f32, meta: &[(&str, Meta)]) {
    let y = fisheye_luminance(n, sky, lamp);
    let chans = ["X", "Y", "Z", "V"]
        .map(|c| (c.to_string(), y.clone()))
        .to_vec();
    write_exr(path, n, n, chans, meta).unwrap();
}

/// The luminance of [`fisheye`]'s picture, row-major.
fn fisheye_luminance(n: usize, sky: f32, lamp: f32) -> Vec<f32> {
    let (mut y, up) = (Vec::with_capacity(n * n), 30f64.to_radians());
    let c = [0.0, up.sin(), up.cos()];
    for j in 0..n {
        for i in 0..n {
            let a = ((i as f64 + 0.5) - 0.5 * n as f64) / (0.5 * n as f64);
            let b = (0.5 * n as f64 - (j as f64 + 0.5)) / (0.5 * n as f64);
            let rho = (a * a + b * b).sqrt();
            let t = rho * std::f64::consts::FRAC_PI_2;
            let v = if rho > 1.0 {
                0.0
            } else {
                let s = if rho > 0.0 { t.sin() / rho } else { 0.0 };
                let d = [a * s, b * s, t.cos()];
                let cos = d[0] * c[0] + d[1] * c[1] + d[2] * c[2];
                if cos >= 3f64.to_radians().cos() {
                    lamp
                } else {
                    sky
                }
            };
            y.push(v);
        }
    }
    y
}

#[test]
fn glare_reads_a_fisheyes_sources_and_ratings() {
    let dir = out_dir("glare", "lamp");
    let exr = dir.join("eye.exr");
    let meta = [
        ("projection", Meta::Text("angular".into())),
        ("fovHorizontalDegrees", Meta::F32(180.0)),
    ];
    fisheye(&exr, 300, 100.0, 2e4, &meta);
    let png = dir.join("sources.png");
    let (code, out, err) = scotopia(&[
        "glare",
        exr.to_str().unwrap(),
        "--json",
        "-o",
        png.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let sources = v["sources"].as_array().unwrap();
    assert_eq!(sources.len(), 1, "{out}");
    let s = &sources[0];
    let omega = s["solid_angle_sr"].as_f64().unwrap();
    let disc = 2.0 * std::f64::consts::PI * (1.0 - 3f64.to_radians().cos());
    assert!((omega / disc - 1.0).abs() < 0.06, "{omega} against {disc}");
    assert!(
        (s["sigma_deg"].as_f64().unwrap() - 30.0).abs() < 0.3,
        "{out}"
    );
    // E_v: the sky's π·100 and what the disc adds over it.
    let ev = std::f64::consts::PI * 100.0 + (2e4 - 100.0) * omega * 30f64.to_radians().cos();
    let got = v["Ev_lx"].as_f64().unwrap();
    assert!((got / ev - 1.0).abs() < 3e-3, "{got} against {ev}");
    // UGR from its formula with the source found.
    let p = s["position_index"].as_f64().unwrap();
    let lb = v["background_cdm2"].as_f64().unwrap();
    assert!((lb / 100.0 - 1.0).abs() < 3e-3, "{out}");
    let ugr = 8.0 * (0.25 / lb * (2e4 / p).powi(2) * omega).log10();
    assert!((v["UGR"].as_f64().unwrap() - ugr).abs() < 1e-6, "{out}");
    for key in ["DGP", "Lveil_cdm2"] {
        assert!(v[key].as_f64().unwrap() > 0.0, "{key}: {out}");
    }
    assert!(std::fs::metadata(&png).unwrap().len() > 100);
    // Text, for people.
    let (code, out, _) = scotopia(&["glare", exr.to_str().unwrap()]);
    assert_eq!(code, 0);
    assert!(
        out.contains("E_v =") && out.contains("UGR (CIE 117)") && out.contains("source 1"),
        "{out}"
    );
}

#[test]
fn a_picture_that_does_not_say_its_projection_needs_it_given() {
    let dir = out_dir("glare", "plain");
    let exr = dir.join("eye.exr");
    fisheye(&exr, 64, 50.0, 50.0, &[]);
    let (code, _, err) = scotopia(&["glare", exr.to_str().unwrap()]);
    assert_eq!(code, 1);
    assert!(err.contains("--projection"), "{err}");
    let (code, _, err) = scotopia(&["glare", exr.to_str().unwrap(), "--projection", "angular"]);
    assert_eq!(code, 1);
    assert!(err.contains("--fov"), "{err}");
    // Given both: a uniform sky of 50 cd/m² is π·50 lx and glares nowhere.
    let (code, out, err) = scotopia(&[
        "glare",
        exr.to_str().unwrap(),
        "--projection",
        "angular",
        "--fov",
        "180",
        "--json",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).unwrap();
    let ev = v["Ev_lx"].as_f64().unwrap();
    assert!(
        (ev / (std::f64::consts::PI * 50.0) - 1.0).abs() < 2e-3,
        "{ev}"
    );
    assert!(v["UGR"].is_null() && v["sources"].as_array().unwrap().is_empty());
    let (code, _, err) = scotopia(&["glare", exr.to_str().unwrap(), "--projection", "stereo"]);
    assert_eq!(code, 1);
    assert!(err.contains("angular or equisolid"), "{err}");
}

#[test]
fn a_radiance_fisheye_gives_the_figures_of_the_same_exr() {
    // The same picture as an angular Radiance picture (`-vta -vh 180`,
    // as rpict writes a fisheye): its view gives the geometry, its RGBE
    // the luminance within a per cent or two.
    let dir = out_dir("glare", "radiance");
    let (exr, hdr) = (dir.join("eye.exr"), dir.join("eye.hdr"));
    let meta = [
        ("projection", Meta::Text("angular".into())),
        ("fovHorizontalDegrees", Meta::F32(180.0)),
    ];
    fisheye(&exr, 200, 100.0, 2e4, &meta);
    let y = fisheye_luminance(200, 100.0, 2e4);
    // X, Y, Z of an equal-energy grey of luminance Y.
    let px: Vec<[f32; 4]> = y.iter().map(|&v| [v, v, v, 0.0]).collect();
    scotopia_image::radiance::write_radiance_hdr(&hdr, 200, 200, &px, Some("-vta -vh 180 -vv 180"))
        .unwrap();
    let json = |p: &std::path::Path| {
        let (code, out, err) = scotopia(&["glare", p.to_str().unwrap(), "--json"]);
        assert_eq!(code, 0, "{err}");
        serde_json::from_str::<serde_json::Value>(&out).unwrap()
    };
    let (a, b) = (json(&exr), json(&hdr));
    assert_eq!(b["projection"], "angular");
    assert_eq!(b["sources"].as_array().unwrap().len(), 1);
    for key in ["Ev_lx", "UGR", "DGP"] {
        let (x, y) = (a[key].as_f64().unwrap(), b[key].as_f64().unwrap());
        assert!((x / y - 1.0).abs() < 0.02, "{key}: {x} against {y}");
    }
}

#[test]
fn a_rendered_fisheye_of_a_uniform_sky_gives_pi_times_its_luminance() {
    // scotopia's own fisheye sensor (`<sensor type="fisheye">`): the EXR
    // says its projection and field, so `glare` needs no options, and
    // the Radiance picture says `-vta`.
    let dir = out_dir("glare", "rendered");
    let scene = dir.join("sky.xml");
    std::fs::write(
        &scene,
        r#"<scene version="3.0.0">
    <sensor type="fisheye">
        <transform name="to_world"><lookat origin="0, 1, 0" target="0, 1, 1" up="0, 1, 0"/></transform>
        <film type="hdrfilm"><integer name="width" value="96"/><integer name="height" value="96"/><rfilter type="box"/></film>
    </sensor>
    <emitter type="constant"><rgb name="radiance" value="0.01, 0.01, 0.01"/></emitter>
</scene>"#,
    )
    .unwrap();
    let (exr, hdr) = (dir.join("sky.exr"), dir.join("sky.hdr"));
    let (code, _, err) = scotopia(&[
        "render",
        scene.to_str().unwrap(),
        "--spp",
        "4",
        "-o",
        exr.to_str().unwrap(),
        "--radiance",
        hdr.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let header = std::fs::read(&hdr).unwrap();
    let header = String::from_utf8_lossy(&header[..200.min(header.len())]).to_string();
    assert!(header.contains("VIEW= -vta -vh 180 -vv 180"), "{header}");
    let picture = scotopia_image::read_xyzv(&exr, Default::default()).unwrap();
    // The sky's luminance: the mean over the circle's inner part (each
    // pixel's few wavelengths make the spectrum's luminance noisy).
    let inner: Vec<f64> = (0..96 * 96)
        .filter(|i| {
            let (x, y) = ((i % 96) as f64 - 47.5, (i / 96) as f64 - 47.5);
            (x * x + y * y).sqrt() < 0.9 * 48.0
        })
        .map(|i| f64::from(picture.pixels[i][1]))
        .collect();
    let l = inner.iter().sum::<f64>() / inner.len() as f64;
    for file in [&exr, &hdr] {
        let (code, out, err) = scotopia(&["glare", file.to_str().unwrap(), "--json"]);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value = serde_json::from_str(&out).unwrap();
        let ev = v["Ev_lx"].as_f64().unwrap();
        // The EXR within 0.2 % (the noise of the means, and the rim's
        // pixels, which the circle covers in part); the Radiance picture
        // within RGBE's 1 %.
        let tol = if file == &exr { 2e-3 } else { 1e-2 };
        assert!(
            (ev / (std::f64::consts::PI * l) - 1.0).abs() < tol,
            "{}: E_v {ev}, π·L {}",
            file.display(),
            std::f64::consts::PI * l
        );
        assert!(v["sources"].as_array().unwrap().is_empty());
    }
}

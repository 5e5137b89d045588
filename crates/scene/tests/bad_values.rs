//! Values that would silently change the image are errors at load (or a
//! warning where the image is still what was asked for): non-finite light
//! power, spectra scaled beyond single precision, reflectances above 1
//! between grid points.

use std::path::PathBuf;

use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

fn dir(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("scotopia-{name}-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
}

/// Loads a scene of a sensor and `body` (written on line 3 of `s.xml`).
fn load(d: &std::path::Path, body: &str) -> Result<scotopia_render::scene::Scene, String> {
    let f = d.join("s.xml");
    let sensor = r#"<sensor type="perspective"><float name="fov" value="40"/></sensor>"#;
    std::fs::write(
        &f,
        format!("<scene version=\"3.0.0\">\n{sensor}\n{body}\n</scene>"),
    )
    .unwrap();
    load_scene(&f, &Parameters::new()).map_err(|e| e.to_string())
}

#[test]
fn a_subnormal_spectrum_scaled_to_a_luminance_is_an_error_naming_the_file() {
    let d = dir("subnormal");
    // Values of 1e-45 (the smallest subnormal) need a factor beyond f32.
    std::fs::write(
        d.join("tiny.csv"),
        "400,1e-45\n500,1e-45\n600,1e-45\n700,0\n",
    )
    .unwrap();
    let e = load(
        &d,
        r#"<shape type="sphere"><emitter type="area"><spectrum name="radiance" filename="tiny.csv"><float name="luminance" value="100"/></spectrum></emitter></shape>"#,
    )
    .unwrap_err();
    assert!(
        e.contains("tiny.csv: ") && e.contains("s.xml:3:") && e.contains("single precision"),
        "{e}"
    );
    // The same shape in ordinary units loads.
    std::fs::write(d.join("ok.csv"), "400,1\n500,1\n600,1\n700,0\n").unwrap();
    let s = load(
        &d,
        r#"<shape type="sphere"><emitter type="area"><spectrum name="radiance" filename="ok.csv"><float name="luminance" value="100"/></spectrum></emitter></shape>"#,
    );
    assert!(s.is_ok(), "{s:?}");
}

#[test]
fn a_light_of_non_finite_power_is_an_error_and_of_zero_power_a_warning() {
    let d = dir("power");
    let cases = [
        // A scale that overflows single precision.
        r#"<emitter type="point"><spectrum name="intensity" value="3e38"><float name="scale" value="10"/></spectrum></emitter>"#,
        // Values each finite whose power (× 4π) overflows the light sampler's f32.
        r#"<emitter type="point"><spectrum name="intensity" value="400:3e38, 800:3e38"/></emitter>"#,
        r#"<shape type="sphere"><emitter type="area"><spectrum name="radiance" value="1e38"/></emitter></shape>"#,
    ];
    for body in cases {
        let e = load(&d, body).unwrap_err();
        assert!(
            e.contains("s.xml:3:") && e.contains("must be") && e.contains("finite"),
            "{body}\n→ {e}"
        );
    }
    let s = load(
        &d,
        r#"<emitter type="point"><spectrum name="intensity" value="0"/></emitter>"#,
    )
    .unwrap();
    assert!(
        s.warnings.iter().any(|w| w.contains("power is zero")),
        "{:?}",
        s.warnings
    );
}

#[test]
fn a_reflectance_spike_between_grid_points_is_an_error() {
    let d = dir("spike");
    for spike in ["5", "3.4e38"] {
        let body = format!(
            r#"<shape type="sphere"><bsdf type="diffuse"><spectrum name="reflectance" value="500:0.5, 502:{spike}, 504:0.5"/></bsdf></shape>"#
        );
        let e = load(&d, &body).unwrap_err();
        assert!(
            e.contains("s.xml:3:") && e.contains("must lie in [0, 1]") && e.contains("502 nm"),
            "{body}\n→ {e}"
        );
    }
    // A fluorescent BSDF: reflectance 0.5 plus an excitation spike of 0.9
    // at 500.5 nm (between the 1 nm grid points) takes 1.4 of the light.
    let e = load(
        &d,
        r#"<shape type="sphere"><bsdf type="fluorescent"><float name="reflectance" value="0.5"/><spectrum name="excitation" value="500:0, 500.5:0.9, 501:0"/><spectrum name="emission" value="520:0, 550:1, 600:0"/></bsdf></shape>"#,
    )
    .unwrap_err();
    assert!(
        e.contains("s.xml:3:") && e.contains("reflectance + excitation is 1.4000"),
        "{e}"
    );
    // The same with a textured reflectance (checked on a 5 nm grid): the
    // checkerboard's spectrum spikes to 0.9 at 502.5 nm, between grid
    // points, where 0.9 + 0.3 of excitation exceeds 1.
    let e = load(
        &d,
        r#"<shape type="sphere"><bsdf type="fluorescent"><texture type="checkerboard" name="reflectance"><spectrum name="color0" value="500:0.5, 502.5:0.9, 505:0.5"/><float name="color1" value="0.1"/></texture><spectrum name="excitation" value="0.3"/><spectrum name="emission" value="520:0, 550:1, 600:0"/></bsdf></shape>"#,
    )
    .unwrap_err();
    assert!(
        e.contains("s.xml:3:") && e.contains("reflectance + excitation is 1.2000 at 502 nm"),
        "{e}"
    );
    // The same curve below 1 loads.
    let ok = load(
        &d,
        r#"<shape type="sphere"><bsdf type="diffuse"><spectrum name="reflectance" value="500:0.5, 502:0.9, 504:0.5"/></bsdf></shape>"#,
    );
    assert!(ok.is_ok(), "{ok:?}");
}

//! Participating media as the loader reads them (issue 25; not traced
//! yet): Mitsuba 3's homogeneous medium, its phase function, and where it
//! is attached — a shape's interior and exterior, the sensor.

use scotopia_color::SampledWavelengths;
use scotopia_render::medium::{Medium, Phase, ShapeMedia};
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

fn write(name: &str, body: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("scotopia-media-{}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    let f = d.join(name);
    std::fs::write(&f, format!("<scene version=\"3.0.0\">\n{body}\n</scene>")).unwrap();
    f
}

const FOG: &str = r#"<medium type="homogeneous" id="fog">
  <rgb name="albedo" value="0.9"/>
  <float name="sigma_t" value="0.02"/>
  <float name="scale" value="2"/>
  <phase type="hg"><float name="g" value="0.7"/></phase>
</medium>"#;

#[test]
fn a_homogeneous_fog_is_read_and_attached_where_mitsuba_attaches_it() {
    let f = write(
        "fog.xml",
        &format!(
            r#"{FOG}
<sensor type="perspective"><ref id="fog"/><film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film></sensor>
<shape type="sphere"><ref name="exterior" id="fog"/></shape>
<shape type="cube"><medium type="homogeneous" name="interior"><float name="sigma_t" value="3"/></medium><ref name="exterior" id="fog"/></shape>
<shape type="disk"><medium type="homogeneous" name="interior"><volume type="constvolume" name="sigma_t"><float name="value" value="0.25"/></volume></medium></shape>"#
        ),
    );
    let s = load_scene(&f, &Parameters::new()).unwrap();
    // The fog once (shared by id), the cube's and the disk's own media.
    assert_eq!(s.media.len(), 3, "{:?}", s.media);
    assert_eq!(s.camera_medium, Some(0));
    assert_eq!(
        s.shape_media,
        vec![
            ShapeMedia {
                interior: None,
                exterior: Some(0)
            },
            ShapeMedia {
                interior: Some(1),
                exterior: Some(0)
            },
            ShapeMedia {
                interior: Some(2),
                exterior: None
            },
        ]
    );
    let wl = SampledWavelengths::<4>::new([450.0, 520.0, 600.0, 650.0], [1.0 / 300.0; 4]);
    let Medium::Homogeneous(fog) = &s.media[0];
    // σ_t × scale; the albedo's RGB grey upsampled flat.
    assert!(fog.sigma_t(&wl).0.iter().all(|v| (v - 0.04).abs() < 1e-7));
    assert!(fog
        .albedo
        .sample(&wl)
        .0
        .iter()
        .all(|v| (v - 0.9).abs() < 2e-3));
    assert_eq!(fog.phase, Phase::HenyeyGreenstein { g: 0.7 });
    // Mitsuba's constvolume holds a constant coefficient.
    let Medium::Homogeneous(disk) = &s.media[2];
    assert_eq!(disk.sigma_t(&wl).0, [0.25; 4]);
    let Medium::Homogeneous(inside) = &s.media[1];
    assert_eq!(inside.phase, Phase::Isotropic);
    // `info`: at 550 nm, and the optical thickness across the scene's
    // bounding sphere (the unit sphere and cube: a diameter of 2√3).
    let info = scotopia_scene::SceneInfo::of(&s);
    assert_eq!(info.media.len(), 3);
    let m = &info.media[1];
    assert_eq!((m.kind, m.sigma_t, m.g), ("homogeneous", 3.0, 0.0));
    assert!(
        (m.optical_thickness - 3.0 * 2.0 * 3f32.sqrt()).abs() < 1e-4,
        "{m:?}"
    );
    // Still said: media are read, not yet rendered.
    assert!(s
        .warnings
        .iter()
        .any(|w| w.contains("does not render participating media yet")));
    assert!(
        !s.warnings.iter().any(|w| w.contains("not read")),
        "{:?}",
        s.warnings
    );
}

#[test]
fn bad_media_are_errors_naming_the_line() {
    for (body, what) in [
        (
            r#"<medium type="homogeneous"><float name="sigma_t" value="-1"/></medium>"#,
            "sigma_t must not be negative",
        ),
        (
            r#"<medium type="homogeneous"><rgb name="albedo" value="1.5"/></medium>"#,
            "has a component above 1",
        ),
        (
            r#"<medium type="homogeneous"><float name="scale" value="-2"/></medium>"#,
            "scale must be finite",
        ),
        (
            r#"<medium type="homogeneous"><phase type="hg"><float name="g" value="1"/></phase></medium>"#,
            "g must lie in (−1, 1)",
        ),
        (
            r#"<medium type="homogeneous"><phase type="rayleigh"/></medium>"#,
            "phase function 'rayleigh'",
        ),
    ] {
        let f = write(
            "bad.xml",
            &format!(
                "<shape type=\"sphere\">\n{}</shape>",
                body.replace("<medium ", "<medium name=\"interior\" ")
            ),
        );
        let e = load_scene(&f, &Parameters::new()).unwrap_err().to_string();
        assert!(e.contains(what) && e.contains("bad.xml:3"), "{what}: {e}");
    }
    // An unnamed medium in a shape says which names it takes.
    let f = write(
        "unnamed.xml",
        &format!("{FOG}\n<shape type=\"sphere\"><ref id=\"fog\"/></shape>"),
    );
    let e = load_scene(&f, &Parameters::new()).unwrap_err().to_string();
    assert!(e.contains("'interior' or 'exterior'"), "{e}");
}

//! Participating media as the loader reads them (issue 25; their
//! transport is tested in media_transport.rs): Mitsuba 3's homogeneous and heterogeneous media (grids from
//! `.vol` files, constvolumes), phase functions, and where media are
//! attached — a shape's interior and exterior, the sensor.

mod common;

use common::vol;
use scotopia_color::{SampledSpectrum, SampledWavelengths};
use scotopia_render::math::Vec3;
use scotopia_render::medium::{Field, Medium, Phase, ShapeMedia};
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
    let Medium::Homogeneous(fog) = &s.media[0] else {
        panic!("{:?}", &s.media[0])
    };
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
    let Medium::Homogeneous(disk) = &s.media[2] else {
        panic!("{:?}", &s.media[2])
    };
    assert_eq!(disk.sigma_t(&wl).0, [0.25; 4]);
    let Medium::Homogeneous(inside) = &s.media[1] else {
        panic!("{:?}", &s.media[1])
    };
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
    // Without volpath (or bdpt) the media are said to be left out.
    assert!(s
        .warnings
        .iter()
        .any(|w| w.contains("media are not rendered: its integrator ignores them")));
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

/// Mitsuba's `participating_media` test grids, as its
/// `create_volume_data.py` defines them: σ_t a wavy sheet with a block of
/// 5, the albedo three colour patterns (16³ cells).
fn mitsuba_grids(dir: &std::path::Path) {
    let n = 16usize;
    let sigma = |x: f32, y: f32, z: f32| -> f32 {
        if x > 0.2 && y > 0.7 && z < 0.5 {
            return 5.0;
        }
        (((16.0 * (x + 4.0 * ((y - 0.5).powi(2) - 0.25))).sin() + 1.0) * 0.5).max(0.0)
    };
    let albedo = |x: f32, y: f32| ((45.0 * (x + ((y - 0.7).powi(2) - 0.25))).cos() + 1.0) * 0.5;
    let u = |i: usize| i as f32 / n as f32;
    std::fs::create_dir_all(dir.join("textures")).unwrap();
    std::fs::write(
        dir.join("textures/sigmat.vol"),
        vol(n, 1, |x, y, z| vec![sigma(u(x), u(y), u(z))]),
    )
    .unwrap();
    std::fs::write(
        dir.join("textures/albedo.vol"),
        vol(n, 3, |x, y, z| {
            let (x, y, z) = (u(x), u(y), u(z));
            [
                albedo(x, y) + 0.5 * y.cos() + 0.5,
                sigma((x + 0.3) % 1.0, (y + 0.7) % 1.0, z),
                albedo(x, y),
            ]
            .map(|v| v.clamp(0.0, 1.0))
            .to_vec()
        }),
    )
    .unwrap();
}

/// The medium of Mitsuba's `test_hetero_sigmat_albedo_volpath.xml`, in a
/// cube as its scene has it (its unit_cube_centered.obj scaled by 1.5).
const HETERO: &str = r#"<sensor type="perspective"/>
<medium id="medium1" type="heterogeneous">
    <float name="scale" value="5"/>
    <volume name="sigma_t" type="gridvolume">
        <transform name="to_world">
            <scale x="1.5" y="1.5" z="1.5"/>
            <translate x="-0.5" y="-0.5" z="-0.5"/>
        </transform>
        <boolean name="use_grid_bbox" value="false"/>
        <string name="filename" value="textures/sigmat.vol"/>
    </volume>
    <volume name="albedo" type="gridvolume">
        <transform name="to_world">
            <scale x="1.5" y="1.5" z="1.5"/>
            <translate x="-0.5" y="-0.5" z="-0.5"/>
        </transform>
        <boolean name="use_grid_bbox" value="false"/>
        <string name="filename" value="textures/albedo.vol"/>
    </volume>
    <phase type="isotropic" />
</medium>
<shape type="cube">
    <transform name="to_world"><scale value="0.75"/></transform>
    <bsdf type="null"/>
    <ref id="medium1" name="interior"/>
</shape>"#;

#[test]
fn mitsubas_heterogeneous_test_medium_is_read_with_its_grids() {
    let f = write("hetero.xml", HETERO);
    mitsuba_grids(f.parent().unwrap());
    let s = load_scene(&f, &Parameters::new()).unwrap();
    assert_eq!(s.media.len(), 1);
    assert_eq!(s.shape_media[0].interior, Some(0));
    let Medium::Heterogeneous(h) = &s.media[0] else {
        panic!("{:?}", s.media[0])
    };
    assert_eq!(h.scale(), 5.0);
    assert_eq!(h.phase, Phase::Isotropic);
    // Mitsuba's transform: scale, then translate: the grid spans
    // [−0.5, 1]³. σ_t is 5 × the grid there, 0 outside (though inside the
    // cube, which reaches −0.75).
    let wl = SampledWavelengths::<4>::new([450.0, 520.0, 600.0, 650.0], [1.0 / 300.0; 4]);
    let Field::Grid(g) = h.sigma_t_field() else {
        panic!("sigma_t is a grid")
    };
    for w in [
        Vec3::new(0.1, 0.2, 0.3),
        Vec3::new(0.9, 0.6, -0.4),
        Vec3::new(-0.45, 0.95, 0.0),
    ] {
        let local = (w + Vec3::splat(0.5)) * (1.0 / 1.5);
        let expected = 5.0 * g.grid().lookup(local, 0);
        let got = h.sigma_t(w, &wl);
        assert!(
            got.0.iter().all(|v| (v - expected).abs() < 1e-4),
            "{w:?}: {got:?}, {expected}"
        );
    }
    // The block of 5 (x > 0.2, y > 0.7, z < 0.5 of the grid): σ_t 25.
    let block = Vec3::new(0.5, 0.9, 0.2) * 1.5 - Vec3::splat(0.5);
    assert!((h.sigma_t(block, &wl).0[0] - 25.0).abs() < 1e-3);
    assert_eq!(
        h.sigma_t(Vec3::new(-0.6, 0.0, 0.0), &wl),
        SampledSpectrum::splat(0.0)
    );
    // The albedo's RGB became spectra in [0, 1].
    let a = h.albedo(Vec3::new(0.2, 0.1, 0.3), &wl);
    assert!(a.0.iter().all(|v| (0.0..=1.0).contains(v)), "{a:?}");
    // `info`: both grids, σ_t's largest, the optical thickness bounded by
    // the box's diagonal (1.5 √3).
    let info = scotopia_scene::SceneInfo::of(&s);
    let m = &info.media[0];
    assert_eq!(m.kind, "heterogeneous");
    assert_eq!(m.albedo, None);
    assert!((m.sigma_t - 25.0).abs() < 1e-4, "{m:?}");
    let diagonal = 1.5 * 3f32.sqrt();
    assert!(
        (m.optical_thickness - 25.0 * diagonal).abs() < 1e-3,
        "{m:?}"
    );
    let grids: Vec<_> = m
        .grids
        .iter()
        .map(|g| (g.parameter, g.cells, g.channels))
        .collect();
    assert_eq!(grids, vec![("sigma_t", [16; 3], 1), ("albedo", [16; 3], 3)]);
    assert!(
        s.warnings
            .iter()
            .any(|w| w.contains("media are not rendered: its integrator ignores them")),
        "{:?}",
        s.warnings
    );
    assert!(
        !s.warnings.iter().any(|w| w.contains("not used")),
        "{:?}",
        s.warnings
    );
}

#[test]
fn heterogeneous_media_take_constants_constvolumes_and_referenced_volumes() {
    let f = write(
        "hetero_const.xml",
        r#"<sensor type="perspective"/>
<volume type="constvolume" id="thick">
    <rgb name="value" value="0.5, 1.0, 2.0"/>
    <transform name="to_world"><scale value="4"/></transform>
</volume>
<shape type="sphere"><medium type="heterogeneous" name="interior">
    <ref name="sigma_t" id="thick"/>
    <float name="albedo" value="0.4"/>
</medium></shape>
<shape type="sphere"><medium type="heterogeneous" name="interior">
    <float name="sigma_t" value="3"/>
</medium></shape>"#,
    );
    let s = load_scene(&f, &Parameters::new()).unwrap();
    assert_eq!(s.media.len(), 2);
    let wl = SampledWavelengths::<4>::new([450.0, 520.0, 600.0, 650.0], [1.0 / 300.0; 4]);
    let (Medium::Heterogeneous(a), Medium::Heterogeneous(b)) = (&s.media[0], &s.media[1]) else {
        panic!("{:?}", s.media)
    };
    // The constvolume's RGB, upsampled (blue largest), over [0, 4]³.
    let inside = a.sigma_t(Vec3::splat(3.5), &wl);
    assert!(inside.0[0] > inside.0[3], "{inside:?}");
    assert_eq!(
        a.sigma_t(Vec3::splat(4.5), &wl),
        SampledSpectrum::splat(0.0)
    );
    assert_eq!(a.albedo(Vec3::splat(1.0), &wl), SampledSpectrum::splat(0.4));
    // A plain σ_t is Mitsuba's default constvolume: [0, 1]³; albedo 0.75.
    assert_eq!(
        b.sigma_t(Vec3::splat(0.5), &wl),
        SampledSpectrum::splat(3.0)
    );
    assert_eq!(
        b.sigma_t(Vec3::splat(1.5), &wl),
        SampledSpectrum::splat(0.0)
    );
    assert_eq!(
        b.albedo(Vec3::splat(0.5), &wl),
        SampledSpectrum::splat(0.75)
    );
    // Transmittance through it is Beer–Lambert over the part inside.
    let ray = scotopia_render::math::Ray::new(Vec3::new(-1.0, 0.5, 0.5), Vec3::new(1.0, 0.0, 0.0));
    let mut rng = scotopia_render::sampling::splitmix::SplitMix(3);
    let t = b.transmittance(&ray, 10.0, &wl, &mut rng);
    assert!((t.0[0] - (-3.0f32).exp()).abs() < 1e-6, "{t:?}");
}

#[test]
fn bad_heterogeneous_media_are_errors_naming_the_file_and_line() {
    let dir = std::env::temp_dir().join(format!("scotopia-media-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let grey = vol(2, 1, |_, _, _| vec![0.5]);
    let bright = vol(2, 1, |_, _, _| vec![1.5]);
    let six = vol(2, 6, |_, _, _| vec![0.5; 6]);
    let rgb = vol(2, 3, |_, _, _| vec![0.5; 3]);
    let mut negative = grey.clone();
    negative[48 + 4 * 5..48 + 4 * 6].copy_from_slice(&(-1.0f32).to_le_bytes());
    let truncated = grey[..60].to_vec();
    for (name, bytes) in [
        ("grey.vol", &grey),
        ("bright.vol", &bright),
        ("six.vol", &six),
        ("rgb.vol", &rgb),
        ("negative.vol", &negative),
        ("truncated.vol", &truncated),
    ] {
        std::fs::write(dir.join(name), bytes).unwrap();
    }
    let grid = |name: &str, file: &str, extra: &str| {
        format!(
            r#"<volume type="gridvolume" name="{name}"><string name="filename" value="{file}"/>{extra}</volume>"#
        )
    };
    for (body, what) in [
        (
            grid("sigma_t", "missing.vol", ""),
            "volume file 'missing.vol' not found",
        ),
        (
            grid("sigma_t", "truncated.vol", ""),
            "truncated.vol: byte 60",
        ),
        (grid("sigma_t", "negative.vol", ""), "negative.vol: byte 68"),
        (
            grid("albedo", "bright.vol", ""),
            "albedo must lie in [0, 1]",
        ),
        (grid("sigma_t", "six.vol", ""), "6 channels"),
        (
            grid(
                "sigma_t",
                "rgb.vol",
                r#"<boolean name="raw" value="true"/>"#,
            ),
            "raw 3-channel grid",
        ),
        (
            grid(
                "sigma_t",
                "grey.vol",
                r#"<string name="filter_type" value="cubic"/>"#,
            ),
            "filter_type 'cubic'",
        ),
        (
            grid(
                "sigma_t",
                "grey.vol",
                r#"<boolean name="use_grid_bbox" value="yes"/>"#,
            ),
            "'yes' is not true or false",
        ),
        (
            r#"<float name="sigma_t" value="-1"/>"#.into(),
            "sigma_t must not be negative",
        ),
        (
            r#"<float name="albedo" value="1.5"/>"#.into(),
            "a reflectance must lie in [0, 1]",
        ),
        (
            r#"<float name="scale" value="-2"/>"#.into(),
            "scale must be finite",
        ),
        (
            r#"<volume type="checkerboard" name="sigma_t"/>"#.into(),
            "volume 'checkerboard' is not supported",
        ),
    ] {
        let f = write(
            "bad_hetero.xml",
            &format!(
                "<shape type=\"sphere\">\n<medium type=\"heterogeneous\" name=\"interior\">\n{body}</medium></shape>"
            ),
        );
        let e = load_scene(&f, &Parameters::new()).unwrap_err().to_string();
        assert!(
            e.contains(what) && e.contains("bad_hetero.xml:"),
            "{what}: {e}"
        );
    }
}

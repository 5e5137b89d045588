//! Road luminance (EN 13201-3, CIE 140): a single lamp over a CIE r-table
//! road (`<bsdf type="roadsurface">`) seen by `measure`'s observer gives
//! L = I·r(β, tan γ)/h² (CIE 140:2000, eq. 2.1) at the table's nodes, with
//! r read here from the data file on its own; the full transport adds
//! what a façade reflects.

mod common;

use std::sync::atomic::AtomicBool;

use common::inline;
use scotopia_render::integrator::{measure_setup, Measured, Receiver, RenderOptions, Setup};
use scotopia_render::math::Vec3;

const HEIGHT: f32 = 10.0;

/// A point lamp of 1000 W/(sr·nm) at every wavelength, `HEIGHT` m over
/// the origin, above a road of class `class`; with a white façade along
/// z = −8 when `facade`.
fn road(class: &str, facade: bool) -> String {
    let wall = if facade {
        r#"<shape type="rectangle">
        <transform name="to_world"><scale x="100" y="10"/><translate y="10" z="-8"/></transform>
        <bsdf type="diffuse"><float name="reflectance" value="0.8"/></bsdf>
    </shape>"#
    } else {
        ""
    };
    format!(
        r#"<scene version="3.0.0">
    <integrator type="path"><integer name="max_depth" value="6"/></integrator>
    <sensor type="perspective"><film type="hdrfilm"><integer name="width" value="4"/><integer name="height" value="4"/></film></sensor>
    <emitter type="point">
        <point name="position" x="0" y="{HEIGHT}" z="0"/>
        <spectrum name="intensity" value="1000"/>
    </emitter>
    <shape type="rectangle">
        <transform name="to_world"><scale value="200"/><rotate x="1" angle="-90"/></transform>
        <bsdf type="roadsurface"><string name="class" value="{class}"/></bsdf>
    </shape>
    {wall}
</scene>"#
    )
}

/// r of `class` at table node (β, tan γ), from the data file.
fn table_r(class: &str, beta: f32, tan_gamma: f32) -> f64 {
    let text = include_str!("../../../data/cie/cie_road_r_tables.csv");
    let mut lines = text.lines().filter(|l| !l.starts_with('#'));
    let header: Vec<f32> = lines
        .next()
        .unwrap()
        .split(',')
        .skip(2)
        .map(|v| v.parse().unwrap())
        .collect();
    let col = header.iter().position(|&t| t == tan_gamma).unwrap();
    for line in lines {
        let cells: Vec<&str> = line.split(',').collect();
        if cells[0] == class && cells[1].parse::<f32>().unwrap() == beta {
            return cells[2 + col].parse::<f64>().unwrap() * 1e-4;
        }
    }
    panic!("{class} has no row β = {beta}")
}

/// The observer: far along −x, 1° above the road (the tables' α), so that
/// every point sees it in the same direction.
fn observer() -> Vec3 {
    let d = 10_000.0f32;
    Vec3::new(-d, d * 1f32.to_radians().tan(), 0.0)
}

/// A point of the road whose lamp lies at angle `beta` from the
/// observer's line of sight through it and at `tan_gamma` from its zenith.
fn point(beta: f32, tan_gamma: f32) -> Receiver {
    let (d, b) = (HEIGHT * tan_gamma, beta.to_radians());
    Receiver {
        p: Vec3::new(-d * b.cos(), 0.0, -d * b.sin()),
        n: Vec3::new(0.0, 1.0, 0.0),
    }
}

fn measured(name: &str, xml: &str, points: &[Receiver], direct: bool) -> Vec<Measured> {
    let s = inline(name, xml);
    let setup = Setup {
        observer: Some(observer()),
        direct,
        ..Setup::default()
    };
    let options = RenderOptions {
        spp: Some(256),
        ..RenderOptions::default()
    };
    measure_setup(
        &s,
        points,
        setup,
        &options,
        &AtomicBool::new(false),
        &|_, _| {},
    )
    .unwrap()
}

#[test]
fn a_single_lamp_over_an_r_table_road_gives_i_r_over_h_squared() {
    // The lamp's luminous intensity: 683 lm/W × 1000 × ∫ȳ dλ.
    let y_bar =
        scotopia_color::photometry::integrate_observers(&scotopia_color::Spectrum::Constant(1.0))
            [1];
    let intensity = 683.0 * 1000.0 * y_bar;
    let nodes: Vec<(f32, f32)> = [0.0f32, 30.0, 90.0, 180.0]
        .iter()
        .flat_map(|&b| [0.0f32, 0.5, 1.0, 2.0, 3.0].map(move |t| (b, t)))
        .collect();
    let points: Vec<Receiver> = nodes.iter().map(|&(b, t)| point(b, t)).collect();
    for class in ["R1", "R3", "C2"] {
        let m = measured(&format!("road-{class}"), &road(class, false), &points, true);
        for (&(b, t), m) in nodes.iter().zip(&m) {
            let want = intensity * table_r(class, b, t) / f64::from(HEIGHT * HEIGHT);
            assert!(
                (m.lobs - want).abs() <= 4.0 * m.lobs_se + 1e-4 * want,
                "{class} at β {b}°, tan γ {t}: L = {} ± {} cd/m², I·r/h² = {want}",
                m.lobs,
                m.lobs_se
            );
        }
    }
}

#[test]
fn the_full_transport_adds_what_a_facade_reflects() {
    let points: Vec<Receiver> = [(90.0, 0.25f32), (90.0, 0.5), (0.0, 1.0)]
        .iter()
        .map(|&(b, t)| point(b, t))
        .collect();
    let xml = road("R3", true);
    let direct = measured("facade-direct", &xml, &points, true);
    let full = measured("facade-full", &xml, &points, false);
    for (d, f) in direct.iter().zip(&full) {
        let se = (d.lobs_se.powi(2) + f.lobs_se.powi(2)).sqrt();
        eprintln!(
            "direct {:.1} ± {:.1}, full {:.1} ± {:.1} cd/m²",
            d.lobs, d.lobs_se, f.lobs, f.lobs_se
        );
        assert!(
            f.lobs - d.lobs > 4.0 * se,
            "the façade added nothing: {} against {}",
            f.lobs,
            d.lobs
        );
        // And illuminance likewise, the direct part being I·cos³γ/h².
        assert!(f.e > d.e);
    }
    // Without an observer there is no luminance.
    let s = inline("road-plain", &xml);
    let m = measure_setup(
        &s,
        &points,
        Setup::default(),
        &RenderOptions {
            spp: Some(4),
            ..RenderOptions::default()
        },
        &AtomicBool::new(false),
        &|_, _| {},
    )
    .unwrap();
    assert!(m[0].lobs.is_nan());
}

#[test]
fn each_lamps_illuminance_at_the_eye_is_its_intensity_over_d_squared_unless_shielded() {
    use scotopia_render::integrator::lights_at_eye;
    // The lamp 10 m up over the origin; an eye 40 m away, 1.5 m up,
    // looking at the lamp's foot: E = I·cos φ/d² on the plane facing the
    // line of sight, φ between it and the lamp.
    let s = inline("eye-lamp", &road("R3", false));
    let y_bar =
        scotopia_color::photometry::integrate_observers(&scotopia_color::Spectrum::Constant(1.0))
            [1];
    let intensity = 683.0 * 1000.0 * y_bar;
    let eye = Vec3::new(-40.0, 1.5, 0.0);
    let look = (Vec3::new(0.0, 0.0, 0.0) - eye).normalize();
    let options = RenderOptions {
        spp: Some(256),
        ..RenderOptions::default()
    };
    let seen = lights_at_eye(&s, eye, look, &options).unwrap();
    assert_eq!(seen.len(), 1);
    eprintln!("E = {} ± {} lx", seen[0].e, seen[0].e_se);
    let to = Vec3::new(0.0, HEIGHT, 0.0) - eye;
    let want = intensity * f64::from(to.normalize().dot(look)) / f64::from(to.length_squared());
    assert!(
        (seen[0].e / want - 1.0).abs() < 1e-3,
        "{} against {want}",
        seen[0].e
    );
    assert!((seen[0].direction - to.normalize()).length() < 1e-5);
    // A wall between them hides it; looking away, it is behind the plane.
    let wall = road("R3", false).replace(
        "</scene>",
        r#"<shape type="rectangle"><transform name="to_world"><scale value="20"/><rotate y="1" angle="90"/><translate x="-20"/></transform></shape></scene>"#,
    );
    let hidden = inline("eye-lamp-hidden", &wall);
    assert!(lights_at_eye(&hidden, eye, look, &options)
        .unwrap()
        .is_empty());
    assert!(lights_at_eye(&s, eye, -look, &options).unwrap().is_empty());
}

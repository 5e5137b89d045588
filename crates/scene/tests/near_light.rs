//! A thin lamp close to a wall lights it as the form factor says, even
//! where its light arrives at a grazing angle: the shadow ray must not
//! count the lamp's own surface as an occluder (measured from the
//! unoffset point it did: the wall just under the lamp got 1.6 % of its
//! light).

use std::sync::atomic::AtomicBool;

use scotopia_color::photometry::spectrum_to_xyzv;
use scotopia_color::Spectrum;
use scotopia_render::integrator::{render, RenderOptions};
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

/// A white wall at z = 0 and a 60 cm × 2.6 cm lamp 15 cm in front of it
/// at y = 0.3, facing the wall; a narrow camera looks at the wall at
/// height `y`. Direct light only (the wall cannot see itself and the lamp
/// is black).
fn scene(y: f32) -> String {
    format!(
        r#"<scene version="3.0.0">
<integrator type="path"><integer name="max_depth" value="2"/></integrator>
<sensor type="perspective"><float name="fov" value="0.4"/>
  <transform name="to_world"><lookat origin="0, {y}, 1" target="0, {y}, 0" up="0, 1, 0"/></transform>
  <film type="hdrfilm"><integer name="width" value="6"/><integer name="height" value="6"/><rfilter type="box"/></film>
</sensor>
<shape type="rectangle"><transform name="to_world"><scale value="2"/></transform>
  <bsdf type="diffuse"><float name="reflectance" value="1"/></bsdf></shape>
<shape type="rectangle">
  <transform name="to_world"><scale x="0.3" y="0.013"/><rotate x="1" angle="180"/><translate y="0.3" z="0.15"/></transform>
  <bsdf type="diffuse"><float name="reflectance" value="0"/></bsdf>
  <emitter type="area"><spectrum name="radiance" value="400:0.5, 700:1.5"/></emitter>
</shape>
</scene>"#
    )
}

/// (1/π)·∫ cos θ_wall cos θ_lamp / d² dA over the lamp, seen from (0, y, 0):
/// the wall's radiance per unit lamp radiance (midpoint rule, 600 × 26).
fn radiance_factor(y: f64) -> f64 {
    let (w, h, z) = (0.6, 0.026, 0.15);
    let (nx, ny) = (600, 26);
    let da = (w / nx as f64) * (h / ny as f64);
    let mut sum = 0.0;
    for i in 0..nx {
        for j in 0..ny {
            let x = -w / 2.0 + (i as f64 + 0.5) * w / nx as f64;
            let ly = 0.3 - h / 2.0 + (j as f64 + 0.5) * h / ny as f64;
            let d2 = x * x + (ly - y) * (ly - y) + z * z;
            // Both cosines are z/d: the wall faces +z, the lamp −z.
            sum += z * z / (d2 * d2) * da;
        }
    }
    sum / std::f64::consts::PI
}

#[test]
fn a_lamp_close_to_a_wall_lights_it_as_the_form_factor_says() {
    let dir = std::env::temp_dir().join(format!("scotopia-near-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let lamp = Spectrum::tabulated(
        scotopia_color::Tabulated::new(vec![400.0, 700.0], vec![0.5, 1.5]).unwrap(),
    );
    let lamp_y = spectrum_to_xyzv(&lamp).y;
    // Below the lamp (steep), and far down the wall (grazing: the light
    // arrives 8° above the wall).
    for y in [0.25f32, 0.1, -0.75] {
        let f = dir.join("near.xml");
        std::fs::write(&f, scene(y)).unwrap();
        let s = load_scene(&f, &Parameters::new()).unwrap();
        let options = RenderOptions {
            spp: Some(256),
            seed: 5,
            ..RenderOptions::default()
        };
        let r = render(&s, &options, &AtomicBool::new(false), &|_, _| {}).unwrap();
        let px: Vec<f64> = r.film.xyzv().iter().map(|p| p[1] as f64).collect();
        let n = px.len() as f64;
        let mean = px.iter().sum::<f64>() / n;
        let se = (px.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
        let want = lamp_y * radiance_factor(y as f64);
        assert!(
            (mean - want).abs() < 4.0 * se + 0.01 * want,
            "y = {y}: {mean} ± {se} cd/m², the form factor says {want}"
        );
    }
}

//! The three wavelength strategies converge to the same image of the
//! bundled Cornell box: per channel, the mean over pixels of the difference
//! between two renders is zero within its standard error (pixel differences
//! are independent, and their expectations cancel).

use std::path::Path;
use std::sync::atomic::AtomicBool;

use scotopia_render::integrator::{render, RenderOptions};
use scotopia_render::wavelength::WavelengthStrategy;
use scotopia_scene::load_scene;
use scotopia_scene::mitsuba::Parameters;

#[test]
fn swc_hero_and_single_agree_on_the_cornell_box() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/cornell-box.xml");
    let mut params = Parameters::new();
    params.insert("res".into(), "24".into());
    let scene = load_scene(&path, &params).unwrap();
    let image = |strategy, seed| {
        let options = RenderOptions {
            spp: Some(64),
            seed,
            strategy,
            ..RenderOptions::default()
        };
        render(&scene, &options, &AtomicBool::new(false), &|_, _| {})
            .unwrap()
            .film
            .xyzv()
    };
    let swc = image(WavelengthStrategy::Swc, 1);
    for (other, seed) in [
        (WavelengthStrategy::Hero, 2),
        (WavelengthStrategy::Single, 3),
    ] {
        let b = image(other, seed);
        for c in 0..4 {
            let d: Vec<f64> = swc
                .iter()
                .zip(&b)
                .map(|(p, q)| (p[c] - q[c]) as f64)
                .collect();
            let n = d.len() as f64;
            let mean = d.iter().sum::<f64>() / n;
            let se = (d.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0) / n).sqrt();
            let level = swc.iter().map(|p| p[c] as f64).sum::<f64>() / n;
            assert!(
                mean.abs() < 4.0 * se,
                "{} vs swc, channel {c}: difference {mean} ± {se} (level {level})",
                other.name()
            );
        }
    }
}

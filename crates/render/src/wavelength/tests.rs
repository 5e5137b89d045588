//! Every strategy's cluster estimator converges to the exact X, Y, Z, V′ of
//! a spectrum — smooth (D65) and a line spectrum (low-pressure sodium).

use std::path::Path;

use scotopia_color::photometry::{estimate_xyzv, spectrum_to_xyzv};
use scotopia_color::{cie, io, Spectrum};

use super::*;
use crate::light::{ConstantLight, PointLight, SceneExtent};
use crate::math::Vec3;

fn sodium() -> Spectrum {
    let p =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/lamps/low-pressure-sodium.csv");
    Spectrum::from(io::read_spectrum_file(&p).unwrap())
}

/// SplitMix64 in [0, 1).
struct Rng(u64);
impl Rng {
    fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }
}

/// Mean and standard error of each channel's estimate over `n` clusters.
fn estimate(sampler: &WavelengthSampler, s: &Spectrum, n: usize, seed: u64) -> [(f64, f64); 4] {
    let mut rng = Rng(seed);
    let (mut sum, mut sum2) = ([0.0f64; 4], [0.0f64; 4]);
    for _ in 0..n {
        let wl: SampledWavelengths<4> = sampler.sample(rng.next(), rng.next());
        let e = estimate_xyzv(&s.sample(&wl), &wl);
        for c in 0..4 {
            sum[c] += e[c] as f64;
            sum2[c] += (e[c] as f64).powi(2);
        }
    }
    std::array::from_fn(|c| {
        let m = sum[c] / n as f64;
        (m, ((sum2[c] / n as f64 - m * m).max(0.0) / n as f64).sqrt())
    })
}

fn samplers() -> Vec<(&'static str, WavelengthSampler)> {
    // A scene lit by a sodium lamp (≈ 3.8 W) and a dim D65 sky (≈ 1.6 W).
    let lights = vec![
        Light::Point(PointLight {
            position: Vec3::ZERO,
            intensity: sodium(),
        }),
        Light::Constant(ConstantLight {
            radiance: cie::illuminant("d65").unwrap().scaled(1e-6),
        }),
    ];
    let extent = SceneExtent {
        shapes: &[],
        center: Vec3::ZERO,
        radius: 1.0,
    };
    let power: Vec<f32> = lights
        .iter()
        .map(|l| l.power(&extent).watts as f32)
        .collect();
    WavelengthStrategy::ALL
        .into_iter()
        .map(|s| (s.name(), WavelengthSampler::new(s, &lights, &power)))
        .collect()
}

#[test]
fn every_strategy_is_unbiased() {
    for (name, sampler) in samplers() {
        for (what, s) in [
            ("d65", cie::illuminant("d65").unwrap()),
            ("sodium", sodium()),
        ] {
            let exact = spectrum_to_xyzv(&s);
            let exact = [exact.x, exact.y, exact.z, exact.v];
            let got = estimate(&sampler, &s, 200_000, 7);
            for c in 0..4 {
                let (m, se) = got[c];
                assert!(
                    (m - exact[c]).abs() < 4.0 * se + 1e-6 * exact[c].abs(),
                    "{name} / {what} channel {c}: {m} ± {se} vs {}",
                    exact[c]
                );
            }
        }
    }
}

#[test]
fn swc_follows_the_lamps_and_pays_off_on_line_spectra() {
    let all = samplers();
    let swc = &all[0].1;
    let hero = &all[1].1;
    // A cluster drawn for the sodium lamp sits on its lines.
    let WavelengthSampler::Swc(s) = swc else {
        panic!("swc")
    };
    let mut on_lines = 0;
    let mut rng = Rng(3);
    for _ in 0..1000 {
        let wl: SampledWavelengths<4> = s.sample(rng.next(), rng.next());
        on_lines += wl
            .lambdas()
            .iter()
            .filter(|l| (588.5..589.9).contains(*l))
            .count();
    }
    assert!(
        on_lines > 1000,
        "{on_lines} of 4000 wavelengths on the sodium lines"
    );
    // Seeing the sodium lamp: SWC's error is far below hero's.
    let (a, b) = (
        estimate(swc, &sodium(), 20_000, 1),
        estimate(hero, &sodium(), 20_000, 1),
    );
    assert!(
        a[1].1 < 0.2 * b[1].1,
        "swc SE {} vs hero SE {}",
        a[1].1,
        b[1].1
    );
}

#[test]
fn hero_rotates_and_single_keeps_one() {
    let wl: SampledWavelengths<4> = WavelengthSampler::Hero.sample(0.0, 0.3);
    let l = wl.lambdas();
    for k in 1..4 {
        let d = (l[k] - l[0]).rem_euclid(470.0);
        assert!((d - 117.5 * k as f32).abs() < 1e-3, "{l:?}");
    }
    let one: SampledWavelengths<4> = WavelengthSampler::Single.sample(0.0, 0.3);
    assert!(one.secondary_terminated());
    assert_eq!(
        WavelengthStrategy::from_name("hero"),
        Some(WavelengthStrategy::Hero)
    );
    assert_eq!(WavelengthStrategy::from_name("rgb"), None);
}

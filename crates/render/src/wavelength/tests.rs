//! Every strategy's cluster estimator converges to the exact X, Y, Z, V′ of
//! a spectrum — smooth (D65) and a line spectrum (low-pressure sodium).

use std::path::Path;

use scotopia_color::photometry::{estimate_xyzv, spectrum_to_xyzv};
use scotopia_color::{cie, io, Spectrum};

use super::*;
use crate::light::{ConstantLight, PointLight, SceneExtent};
use crate::math::Vec3;
use crate::test_rng::Rng;

fn sodium() -> Spectrum {
    let p =
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/lamps/low-pressure-sodium.csv");
    Spectrum::from(io::read_spectrum_file(&p).unwrap())
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
        casters: &[],
    };
    let power: Vec<f32> = lights
        .iter()
        .map(|l| l.power(&extent).watts as f32)
        .collect();
    WavelengthStrategy::ALL
        .into_iter()
        .map(|s| (s.name(), WavelengthSampler::new(s, &lights, &power, &[])))
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

/// SWC's table is the mixture it was made of: 0.9 of the lights' spectra
/// as seen (times the visible density), by the power they then carry, and
/// 0.1 of the visible density, bin by bin up to the two cells
/// that straddle a bin's ends; its cells stratify each cluster, and each
/// member carries the table's density at its wavelength.
#[test]
fn swc_table_is_the_mixture_of_the_lights() {
    let all = samplers();
    let WavelengthSampler::Swc(s) = &all[0].1 else {
        panic!("swc")
    };
    let (na, d65) = (sodium(), cie::illuminant("d65").unwrap().scaled(1e-6));
    let (pa, pb) = (
        SpectralPdf::seen(&na).unwrap(),
        SpectralPdf::seen(&d65).unwrap(),
    );
    // Weights by power as seen: the point light emits 4π·∫I·v, the
    // constant one π·∫L·v per unit area of the sphere of radius 1 (4π m²).
    let (wa, wb) = (
        pa.integral() * 4.0,
        pb.integral() * 4.0 * std::f64::consts::PI,
    );
    let (wa, wb) = (wa / (wa + wb), wb / (wa + wb));
    let cells = 2.0 / inverse_cdf::CELLS as f64;
    let mut edges: Vec<f32> = (0..=47).map(|i| 360.0 + 10.0 * i as f32).collect();
    edges.extend([588.895, 589.095, 589.492, 589.692]);
    edges.sort_by(f32::total_cmp);
    for e in edges.windows(2) {
        let (a, b) = (e[0], e[1]);
        let lights =
            wa * (pa.mass_below(b) - pa.mass_below(a)) + wb * (pb.mass_below(b) - pb.mass_below(a));
        let m = 10_000;
        let visible: f64 = (0..m)
            .map(|i| visible_pdf(a + (b - a) * (i as f32 + 0.5) / m as f32) as f64)
            .sum::<f64>()
            * (b - a) as f64
            / m as f64;
        let want = 0.9 * lights + 0.1 * visible;
        let got = s.mass_between(a, b);
        assert!(
            (got - want).abs() < cells + 1e-5,
            "{a}–{b}: {got} vs {want}"
        );
    }
    let mut rng = Rng(4);
    for _ in 0..10_000 {
        let u = rng.next();
        let wl: SampledWavelengths<4> = s.sample(rng.next(), u);
        for k in 0..4 {
            let l = wl.lambda(k);
            // Member k sits at (k + u)/4 of the mixture's CDF (up to the
            // rounding of λ to f32, a fraction of a cell in a line).
            let below = s.mass_between(360.0, l);
            assert!(
                (below - (k as f64 + u as f64) / 4.0).abs() < 0.5 * cells,
                "member {k} at {l}: mass below {below}"
            );
            // Its density is the table's (the last f32 step of a cell may
            // hold the next one's start, see `InverseCdf::pdf`).
            // Inside a sodium line a cell is 2–3 f32 steps wide.
            let p = wl.pdf(k);
            assert!(
                (0..4).any(|i| p == s.pdf(f32::from_bits(l.to_bits() - i))),
                "{l}: {p} vs {}",
                s.pdf(l)
            );
        }
    }
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

#[test]
fn swc_covers_what_a_uv_lit_fluorescent_paint_emits() {
    // A black light (360–390 nm only) and a paint that turns it green:
    // without the paint in the mixture, clusters reach 520 nm only through
    // the defensive share; with it, most of the non-defensive mass goes
    // there, and the mixture still integrates to 1.
    use crate::bsdf::Fluorescent;
    use crate::texture::Texture;
    use scotopia_color::Tabulated;
    let uv = Spectrum::tabulated(
        Tabulated::new(vec![360.0, 365.0, 385.0, 390.0], vec![0.0, 1.0, 1.0, 0.0]).unwrap(),
    );
    let lights = vec![Light::Constant(ConstantLight { radiance: uv })];
    let paint = Fluorescent::new(
        Texture::Constant(Spectrum::Constant(0.1)),
        &Spectrum::tabulated(Tabulated::new(vec![360.0, 480.0], vec![0.8, 0.0]).unwrap()),
        &Spectrum::tabulated(
            Tabulated::new(vec![490.0, 520.0, 560.0], vec![0.0, 1.0, 0.0]).unwrap(),
        ),
        0.9,
    )
    .unwrap();
    let plain = Swc::new(&lights, &[1.0], &[]);
    let with = Swc::new(&lights, &[1.0], &[&paint]);
    assert!(
        with.pdf(520.0) > 20.0 * plain.pdf(520.0),
        "{} vs {}",
        with.pdf(520.0),
        plain.pdf(520.0)
    );
    // r = Q·∫ p_lamp·e·(Stokes share): the lamp's density is its trapezoid normalised
    // (area 25 nm), e = 0.8·(480 − λ)/120. The paint takes r/(1 + r) of
    // the non-defensive mass; the defensive share adds its own bit.
    let lamp = |l: f32| ((l - 360.0) / 5.0).min(1.0).min((390.0 - l) / 5.0).max(0.0) / 25.0;
    // Energy re-emitted per unit absorbed at λ: Q·∫ η(λo)·λ/λo dλo with
    // η the triangle 490–520–560 nm normalised (area 35 nm).
    let eta = |l: f32| ((l - 490.0) / 30.0).min((560.0 - l) / 40.0).max(0.0) / 35.0;
    let stokes = |l: f32| -> f32 {
        (0..7000)
            .map(|i| {
                let lo = 490.0 + (i as f32 + 0.5) * 0.01;
                eta(lo) * l / lo * 0.01
            })
            .sum()
    };
    let r: f32 = (0..300)
        .map(|i| {
            let l = 360.0 + (i as f32 + 0.5) * 0.1;
            lamp(l) * 0.8 * (480.0 - l) / 120.0 * stokes(l) * 0.1
        })
        .sum::<f32>()
        * 0.9;
    let defensive: f32 = (4900..5600)
        .map(|i| visible_pdf(i as f32 * 0.1) * 0.1)
        .sum();
    let want = 0.9 * r / (1.0 + r) + 0.1 * defensive;
    let band: f32 = (4900..5600).map(|i| with.pdf(i as f32 * 0.1) * 0.1).sum();
    assert!((band - want).abs() < 0.005, "{band} vs {want} (r = {r})");
    let total: f32 = (0..47_000)
        .map(|i| with.pdf(360.0 + (i as f32 + 0.5) * 0.01) * 0.01)
        .sum();
    assert!((total - 1.0).abs() < 1e-3, "{total}");
    // Clusters drawn from it land in the paint's band about as often.
    let mut rng = Rng(9);
    let n = 20_000;
    let hits = (0..n)
        .filter(|_| {
            let wl: SampledWavelengths<1> = with.sample(rng.next(), rng.next());
            (490.0..560.0).contains(&wl.lambda(0))
        })
        .count();
    assert!((hits as f32 / n as f32 - band).abs() < 0.02, "{hits}");
    // The shares are stratified within a cluster: with r ≈ 0.5 a cluster
    // of 4 carries 1 or 2 emission wavelengths every time it is not
    // defensive (drawn per cluster, these clusters would be all-UV with
    // probability 1/(1 + r)); each member's marginal is still the mixture.
    let mut members_in_band = 0;
    let with_band = (0..n)
        .filter(|_| {
            let wl: SampledWavelengths<4> = with.sample(rng.next(), rng.next());
            let m = (0..4)
                .filter(|&k| (490.0..560.0).contains(&wl.lambda(k)))
                .count();
            members_in_band += m;
            m > 0
        })
        .count();
    assert!(
        with_band as f32 / n as f32 > 0.9,
        "{with_band} of {n} clusters reach the paint's band"
    );
    let share = members_in_band as f32 / (4 * n) as f32;
    assert!((share - band).abs() < 0.01, "{share} vs {band}");
}

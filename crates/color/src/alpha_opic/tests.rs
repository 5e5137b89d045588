use super::*;
use crate::photometry::spectrum_to_xyzv;
use crate::sampled::SampledWavelengths;

/// α-opic efficacy of luminous radiation (mW/lm) of `s`: its α-opic
/// irradiance per lux.
fn elr(s: &Spectrum) -> [f64; 5] {
    let lux = spectrum_to_xyzv(s).y;
    integrate(s).map(|e| 1000.0 * e / lux)
}

fn assert_close(got: [f64; 5], want: [f64; 5], tolerance: f64, what: &str) {
    for k in 0..5 {
        let err = got[k] / want[k] - 1.0;
        assert!(
            err.abs() < tolerance,
            "{what} {}: {} against {}",
            NAMES[k],
            got[k],
            want[k]
        );
    }
}

#[test]
fn d65s_efficacies_are_the_standards() {
    // CIE S 026 toolbox v1.049a (and luxpy 1.12.5's spd_to_aopicELR, the
    // same to 6 digits): D65's α-opic ELR, sc mc lc rh mel, mW/lm.
    let k = d65_efficacy().map(|v| 1000.0 * v);
    assert_close(
        k,
        [0.817289, 1.455826, 1.628907, 1.449703, 1.326213],
        2e-4,
        "D65",
    );
}

#[test]
fn d65_of_any_illuminance_has_every_edi_equal_to_it() {
    let d65 = cie::illuminant("D65").unwrap();
    let lux = spectrum_to_xyzv(&d65).y;
    for scale in [1e-3, 1.0, 250.0] {
        let e = integrate(&d65).map(|v| v * scale);
        for (k, v) in edi(e).into_iter().enumerate() {
            assert!((v / (lux * scale) - 1.0).abs() < 1e-9, "{}: {v}", NAMES[k]);
        }
    }
}

#[test]
fn illuminant_a_and_an_led_agree_with_luxpy() {
    // luxpy 1.12.5 (an independent implementation), spd_to_aopicELR of
    // the same spectra on 360–830 nm at 1 nm, sc mc lc rh mel, mW/lm.
    let a = cie::illuminant("A").unwrap();
    assert_close(
        elr(&a),
        [0.254149, 1.174203, 1.656715, 0.830718, 0.657464],
        5e-4,
        "A",
    );
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../../scenes/lamps/led-4000k.csv"
    ))
    .unwrap();
    let t = parse_table(&text, "led-4000k.csv", 1, false).unwrap();
    let led = Spectrum::tabulated(
        crate::spectrum::Tabulated::new(
            t.wavelengths.iter().map(|&w| w as f32).collect(),
            t.columns[0].iter().map(|&v| v as f32).collect(),
        )
        .unwrap(),
    );
    assert_close(
        elr(&led),
        [0.460343, 1.275304, 1.623322, 0.976452, 0.800969],
        5e-4,
        "LED",
    );
    // Illuminant A's melanopic daylight efficacy ratio is under half of
    // D65's: 0.496 (its mEDI per lux).
    let der = elr(&a)[4] / (1000.0 * d65_efficacy()[4]);
    assert!((der - 0.4957).abs() < 1e-3, "{der}");
}

#[test]
fn the_cluster_estimate_is_unbiased() {
    // Illuminant A sampled by stratified uniform clusters: the mean of the
    // estimates is ∫ E·s_α dλ, within a few standard errors.
    let a = cie::illuminant("A").unwrap();
    let want = integrate(&a);
    let n = 20_000;
    let mut sum = [0.0f64; 5];
    let mut sq = [0.0f64; 5];
    for i in 0..n {
        let wl = SampledWavelengths::<4>::sample_uniform((i as f32 + 0.5) / n as f32);
        let e = SampledSpectrum::from_fn(|k| a.eval(wl.lambda(k)));
        for (k, v) in estimate(&e, &wl).into_iter().enumerate() {
            sum[k] += f64::from(v);
            sq[k] += f64::from(v) * f64::from(v);
        }
    }
    for k in 0..5 {
        let mean = sum[k] / n as f64;
        let se = ((sq[k] / n as f64 - mean * mean) / n as f64).sqrt();
        assert!(
            (mean - want[k]).abs() < 4.0 * se + 1e-9 * want[k],
            "{}: {mean} against {} (se {se})",
            NAMES[k],
            want[k]
        );
    }
}

//! Hot-path costs: evaluating a spectrum on a wavelength cluster, turning an
//! RGB colour into a spectrum, and the cluster's XYZV′ estimate.

use std::hint::black_box;

use criterion::{criterion_group, criterion_main, Criterion};
use scotopia_color::photometry::estimate_xyzv;
use scotopia_color::{
    cie, rgb_to_spectrum, RgbSpace, SampledWavelengths, Spectrum, SpectrumKind, Tabulated,
    UpsampleMethod,
};

/// Clusters with jitters spread over [0, 1), so lookups do not hit one cache line.
fn clusters() -> Vec<SampledWavelengths<4>> {
    (0..256)
        .map(|i| SampledWavelengths::sample_uniform((i as f32 + 0.5) / 256.0))
        .collect()
}

fn bench_cluster_eval(c: &mut Criterion) {
    let wl = clusters();
    let irregular = Tabulated::new(
        (0..200)
            .map(|i| 360.0 + i as f32 * 2.3 + (i % 3) as f32 * 0.4)
            .collect(),
        (0..200).map(|i| (i as f32 * 0.1).sin() + 1.0).collect(),
    )
    .unwrap();
    let spectra = [
        ("tabulated_uniform_d65", cie::illuminant("D65").unwrap()),
        ("tabulated_irregular", irregular.into()),
        ("blackbody", Spectrum::blackbody(3000.0).unwrap()),
        (
            "sigmoid_reflectance",
            rgb_to_spectrum(
                [0.7, 0.3, 0.2],
                RgbSpace::Srgb,
                UpsampleMethod::Jakob2019,
                SpectrumKind::Reflectance,
            )
            .unwrap(),
        ),
        (
            "sigmoid_illuminant",
            rgb_to_spectrum(
                [2.0, 1.0, 0.5],
                RgbSpace::Srgb,
                UpsampleMethod::Jakob2019,
                SpectrumKind::Illuminant,
            )
            .unwrap(),
        ),
    ];
    let mut group = c.benchmark_group("cluster_eval_k4");
    for (name, s) in &spectra {
        group.bench_function(*name, |b| {
            let mut i = 0;
            b.iter(|| {
                i = (i + 1) & 255;
                black_box(s.sample(black_box(&wl[i])))
            })
        });
    }
    group.finish();

    let s = Spectrum::blackbody(3000.0).unwrap();
    c.bench_function("estimate_xyzv_k4", |b| {
        let mut i = 0;
        b.iter(|| {
            i = (i + 1) & 255;
            let v = s.sample(&wl[i]);
            black_box(estimate_xyzv(black_box(&v), &wl[i]))
        })
    });
}

fn bench_rgb_to_spectrum(c: &mut Criterion) {
    // Warm the table (decoded once on first use).
    let _ = rgb_to_spectrum(
        [0.5; 3],
        RgbSpace::Srgb,
        UpsampleMethod::Jakob2019,
        SpectrumKind::Reflectance,
    );
    let colours: Vec<[f32; 3]> = (0..256)
        .map(|i| {
            [
                (i % 7) as f32 / 7.0,
                (i % 11) as f32 / 11.0,
                (i % 13) as f32 / 13.0 + 0.01,
            ]
        })
        .collect();
    let mut group = c.benchmark_group("rgb_to_spectrum");
    for (name, method, kind) in [
        (
            "jakob2019_reflectance",
            UpsampleMethod::Jakob2019,
            SpectrumKind::Reflectance,
        ),
        (
            "jakob2019_illuminant",
            UpsampleMethod::Jakob2019,
            SpectrumKind::Illuminant,
        ),
        (
            "smits_reflectance",
            UpsampleMethod::Smits,
            SpectrumKind::Reflectance,
        ),
    ] {
        group.bench_function(name, |b| {
            let mut i = 0;
            b.iter(|| {
                i = (i + 1) & 255;
                black_box(
                    rgb_to_spectrum(black_box(colours[i]), RgbSpace::Srgb, method, kind).unwrap(),
                )
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench_cluster_eval, bench_rgb_to_spectrum);
criterion_main!(benches);

//! The checks every BSDF's tests run: sampling against the density (χ²),
//! sample weights against eval/pdf, and the directional albedo.

use super::{chi2_directions, Rng};
use scotopia_color::SampledWavelengths;
use scotopia_render::bsdf::{Bsdf, ShadingPoint, Transport};
use scotopia_render::math::Vec3;

/// The χ² p-value of 200 000 directions `bsdf.sample` draws from `wi`
/// against `pdf_at`. A delta sample (a pass-through) counts as no
/// direction: its probability is the mass the density leaves out.
pub fn sampling_p_value(
    bsdf: &Bsdf,
    wl: &SampledWavelengths<4>,
    uv: impl Into<ShadingPoint> + Copy,
    wi: Vec3,
    seed: u64,
) -> f64 {
    chi2_directions(
        200_000,
        &mut Rng(seed),
        |r| {
            let (u1, u2) = (r.next(), r.pair());
            bsdf.sample(wl, uv, wi, u1, u2, Transport::Radiance)
                .filter(|s| !s.delta)
                .map(|s| s.wo)
        },
        |wo| bsdf.pdf_at(wl, uv, wi, wo) as f64,
    )
}

/// `n` samples from `wi`: each non-delta sample's weight is eval/pdf and
/// its pdf is `pdf_at`, to `rel_tol` relative (absolute below 1). With
/// `allow_delta` false a delta sample fails the check.
#[allow(clippy::too_many_arguments)]
pub fn assert_weights_are_eval_over_pdf(
    name: &str,
    bsdf: &Bsdf,
    wl: &SampledWavelengths<4>,
    uv: impl Into<ShadingPoint> + Copy,
    wi: Vec3,
    mode: Transport,
    n: usize,
    rng: &mut Rng,
    rel_tol: f32,
    allow_delta: bool,
) {
    for _ in 0..n {
        let Some(s) = bsdf.sample(wl, uv, wi, rng.next(), rng.pair(), mode) else {
            continue;
        };
        if s.delta {
            assert!(allow_delta, "{name} {mode:?}: a delta sample {s:?}");
            continue;
        }
        let pdf = bsdf.pdf_at(wl, uv, wi, s.wo);
        let expected = bsdf.eval(wl, uv, wi, s.wo, mode) / pdf;
        for k in 0..4 {
            assert!(
                (s.weight[k] - expected[k]).abs() <= rel_tol * expected[k].max(1.0),
                "{name} {mode:?}: {s:?} vs {expected:?}"
            );
        }
        assert!(
            (s.pdf - pdf).abs() <= rel_tol * pdf,
            "{name} {mode:?}: pdf {} vs {pdf}",
            s.pdf
        );
    }
}

/// The directional albedo ∫ f·cos dω = E[weight] at the first wavelength
/// from `n` samples: (mean, standard error). Importance mode leaves out
/// the 1/η² that radiance legitimately gains leaving a denser medium.
pub fn albedo(
    bsdf: &Bsdf,
    wl: &SampledWavelengths<4>,
    uv: impl Into<ShadingPoint> + Copy,
    wi: Vec3,
    mode: Transport,
    n: usize,
    rng: &mut Rng,
) -> (f64, f64) {
    let (mut sum, mut sum2) = (0.0f64, 0.0f64);
    for _ in 0..n {
        let v = bsdf
            .sample(wl, uv, wi, rng.next(), rng.pair(), mode)
            .map_or(0.0, |s| s.weight[0] as f64);
        sum += v;
        sum2 += v * v;
    }
    let mean = sum / n as f64;
    (
        mean,
        ((sum2 / n as f64 - mean * mean).max(0.0) / n as f64).sqrt(),
    )
}

//! What the principled BSDFs' tests share: the configurations their
//! Mitsuba 3.9.1 measurements were taken at, and the comparison.

use scotopia_color::{SampledWavelengths, Spectrum, Tabulated};
use scotopia_render::bsdf::{mitsuba_wavelength_pdf, Bsdf, Transport};
use scotopia_render::math::Vec3;
use scotopia_render::texture::{FloatTexture, Texture};

pub const UV: [f32; 2] = [0.3, 0.6];

pub fn dir(theta_deg: f32, phi_deg: f32) -> Vec3 {
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos())
}

/// The wavelengths the Mitsuba measurements were taken on.
pub fn wl() -> SampledWavelengths<4> {
    let lambda = [450.0, 520.0, 580.0, 650.0];
    SampledWavelengths::new(lambda, lambda.map(mitsuba_wavelength_pdf))
}

/// Mitsuba's `{'type': 'spectrum', 'value': [(360, 0.9), (500, 0.3),
/// (600, 0.6), (830, 0.2)]}`: piecewise linear.
pub fn base() -> Texture {
    let t = Tabulated::new(vec![360.0, 500.0, 600.0, 830.0], vec![0.9, 0.3, 0.6, 0.2]).unwrap();
    Texture::Constant(Spectrum::tabulated(t))
}

pub fn c(v: f32) -> Option<FloatTexture> {
    Some(FloatTexture::Constant(v))
}

/// Relative difference, with an absolute floor for values near zero.
fn rel(got: f32, want: f32) -> f32 {
    (got - want).abs() / want.abs().max(1e-4)
}

/// Each row (θi, φi, θo, φo in degrees, eval·cos on `wl()`'s four
/// wavelengths, pdf) as Mitsuba 3.9.1 gave it: scotopia agrees to 1e-3.
pub fn assert_matches_mitsuba(cases: Vec<(&str, Bsdf, [[f32; 9]; 12])>) {
    let w = wl();
    let mut worst = 0.0f32;
    for (name, bsdf, rows) in cases {
        for row in rows {
            let (wi, wo) = (dir(row[0], row[1]), dir(row[2], row[3]));
            let f = bsdf.eval(&w, UV, wi, wo, Transport::Radiance);
            let pdf = bsdf.pdf_at(&w, UV, wi, wo);
            for k in 0..4 {
                let e = rel(f[k], row[4 + k]);
                worst = worst.max(e);
                assert!(
                    e < 1e-3,
                    "{name} {row:?}: eval[{k}] {} vs {}",
                    f[k],
                    row[4 + k]
                );
            }
            let e = rel(pdf, row[8]);
            worst = worst.max(e);
            assert!(e < 1e-3, "{name} {row:?}: pdf {pdf} vs {}", row[8]);
        }
    }
    eprintln!("largest relative difference to Mitsuba 3.9.1: {worst:e}");
}

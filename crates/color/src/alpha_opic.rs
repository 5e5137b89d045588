//! α-opic quantities (CIE S 026/E:2018): the light each of the eye's
//! five photoreceptor types receives — the S, M and L cones (sc, mc,
//! lc), the rods (rh) and the melanopsin-containing retinal ganglion
//! cells (mel, which drive circadian responses) — weighed by its action
//! spectrum s_α(λ) (`data/cie/cie_s026_alpha_opic_action_spectra.csv`).
//!
//! The α-opic irradiance is E_α = ∫ E_e,λ·s_α(λ) dλ (W/m²); its
//! equivalent daylight (D65) illuminance is E_α over D65's α-opic
//! efficacy K_α,v^D65 = ∫ D65·s_α dλ / (K_m ∫ D65·ȳ dλ) (W/lm), the
//! illuminance of D65 that gives the same E_α: so D65 of any illuminance
//! has every EDI equal to it (S 026 §3.5).

use std::sync::OnceLock;

use crate::cie;
use crate::io::parse_table;
use crate::photometry::{estimate_weighted, integrate_observers, integrate_weighted, K_M};
use crate::sampled::{SampledSpectrum, SampledWavelengths};
use crate::spectrum::Spectrum;
use crate::LAMBDA_MIN;

const CSV: &str = include_str!("../../../data/cie/cie_s026_alpha_opic_action_spectra.csv");

/// The five α-opic quantities, in the order of every array here.
pub const NAMES: [&str; 5] = ["sc", "mc", "lc", "rh", "mel"];

/// s_α at every nm of 360–830 (zero outside the table's 380–780).
fn table() -> &'static [[f32; 5]] {
    static TABLE: OnceLock<Vec<[f32; 5]>> = OnceLock::new();
    TABLE.get_or_init(|| {
        // The embedded table is part of the build; a parse failure is a bug.
        let t = parse_table(
            CSV,
            "data/cie/cie_s026_alpha_opic_action_spectra.csv",
            5,
            false,
        )
        .expect("embedded CIE S 026 table");
        (0..cie::SAMPLES_1NM)
            .map(|i| {
                let lambda = LAMBDA_MIN as f64 + i as f64;
                t.wavelengths
                    .iter()
                    .position(|&w| w == lambda)
                    .map_or([0.0; 5], |j| {
                        std::array::from_fn(|k| t.columns[k][j] as f32)
                    })
            })
            .collect()
    })
}

/// s_sc, s_mc, s_lc, s_rh, s_mel at `lambda` nm, linear between the 1 nm
/// samples, zero outside the table.
#[inline]
pub fn action_spectra(lambda: f32) -> [f32; 5] {
    let table = table();
    let x = lambda - LAMBDA_MIN;
    if !(x >= 0.0 && x <= (table.len() - 1) as f32) {
        return [0.0; 5];
    }
    let i = (x as usize).min(table.len() - 2);
    let t = x - i as f32;
    let (a, b) = (table[i], table[i + 1]);
    std::array::from_fn(|k| a[k] + t * (b[k] - a[k]))
}

/// ∫ S(λ)·s_α(λ) dλ over 360–830 nm, by the trapezoid rule on the nodes
/// `photometry::integrate_observers` uses.
pub fn integrate(s: &Spectrum) -> [f64; 5] {
    integrate_weighted(s, action_spectra)
}

/// D65's α-opic efficacies K_α,v^D65 (W/lm): the α-opic irradiance of 1 lx
/// of D65.
pub fn d65_efficacy() -> [f64; 5] {
    static K: OnceLock<[f64; 5]> = OnceLock::new();
    *K.get_or_init(|| {
        let d65 = cie::illuminant("D65").expect("D65 is built in");
        let e = integrate(&d65);
        let lux = K_M * integrate_observers(&d65)[1];
        e.map(|a| a / lux)
    })
}

/// The five α-opic equivalent daylight (D65) illuminances (lx) of α-opic
/// irradiances (W/m²).
pub fn edi(irradiance: [f64; 5]) -> [f64; 5] {
    let k = d65_efficacy();
    std::array::from_fn(|i| irradiance[i] / k[i])
}

/// Monte Carlo estimate of the α-opic irradiances (W/m²) from one
/// wavelength cluster of spectral irradiance: (1/K) Σₖ s_α(λₖ)·E(λₖ)/p(λₖ),
/// as `photometry::estimate_xyzv` estimates X, Y, Z, V′.
#[inline]
pub fn estimate<const K: usize>(
    irradiance: &SampledSpectrum<K>,
    wavelengths: &SampledWavelengths<K>,
) -> [f32; 5] {
    estimate_weighted(irradiance, wavelengths, action_spectra)
}

#[cfg(test)]
mod tests;

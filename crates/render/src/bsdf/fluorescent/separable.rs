//! The separable reradiation model: an excitation spectrum e(λi) (the
//! fraction of light absorbed for re-emission), an emission shape η(λo)
//! normalised to ∫η dλ = 1, and a quantum yield Q (photons out per photon
//! absorbed). Per nm of excitation wavelength,
//!
//!   F(λi → λo) = Q·e(λi)·η(λo)·(λi/λo)·[λi ≤ λo]
//!
//! where λi/λo is the Stokes factor (energy per photon falls as the
//! wavelength grows). Light is re-emitted only at wavelengths at least as
//! long as the one absorbed (scotopia's choice, Stokes' rule): photons
//! whose emission would land below the excitation wavelength are lost, so
//! the energy re-emitted never exceeds Q times the energy absorbed.

use scotopia_color::{Spectrum, LAMBDA_MAX, LAMBDA_MIN};

use crate::sampling::spectral_pdf::SpectralPdf;

#[derive(Debug, Clone, PartialEq)]
pub struct Separable {
    /// e normalised to a density over wavelength (`None`: nothing excites).
    excitation: Option<SpectralPdf>,
    /// ∫ e dλ, nm: e(λ) = excitation.pdf(λ)·excitation_total.
    excitation_total: f64,
    /// η, the emission shape as a density (per nm).
    emission: SpectralPdf,
    /// Q.
    quantum_yield: f32,
    /// ∫ from λmin to λ of e(x)·x dx at 1 nm steps from λmin: how much
    /// excitation, Stokes-weighted, can feed emission at λ.
    stokes_mass: Vec<f64>,
    /// ∫ from λ to λmax of η(x)/x dx at 1 nm steps from λmin: the share
    /// of a photon absorbed at λ that leaves, times 1/λ per unit energy.
    emission_tail: Vec<f64>,
}

/// Running integral from λmin of `f`, sampled at 1 nm steps (midpoint rule
/// on quarter-nanometres).
fn cumulative(f: impl Fn(f32) -> f64) -> Vec<f64> {
    let steps = (LAMBDA_MAX - LAMBDA_MIN) as usize;
    let mut out = vec![0.0f64; steps + 1];
    for k in 0..steps {
        let lo = LAMBDA_MIN + k as f32;
        let piece: f64 = (0..4).map(|j| f(lo + (j as f32 + 0.5) * 0.25) * 0.25).sum();
        out[k + 1] = out[k] + piece;
    }
    out
}

/// `table` (1 nm steps from λmin) linearly interpolated at `lambda`.
fn lookup(table: &[f64], lambda: f32) -> f64 {
    let x = (lambda - LAMBDA_MIN).clamp(0.0, (table.len() - 1) as f32);
    let i = (x as usize).min(table.len() - 2);
    let t = (x - i as f32) as f64;
    table[i] * (1.0 - t) + table[i + 1] * t
}

impl Separable {
    /// `None` when the emission spectrum has no positive value.
    pub fn new(excitation: &Spectrum, emission: &Spectrum, quantum_yield: f32) -> Option<Self> {
        let emission = SpectralPdf::new(emission)?;
        let excitation = SpectralPdf::new(excitation);
        // The density's own normaliser, so e = pdf·total exactly.
        let excitation_total = excitation.as_ref().map_or(0.0, |p| p.integral());
        let stokes_mass = cumulative(|l| match &excitation {
            Some(p) => p.pdf(l) as f64 * excitation_total * l as f64,
            None => 0.0,
        });
        let below = cumulative(|l| emission.pdf(l) as f64 / l as f64);
        let total = below[below.len() - 1];
        let emission_tail = below.iter().map(|b| total - b).collect();
        Some(Self {
            excitation,
            excitation_total,
            emission,
            quantum_yield,
            stokes_mass,
            emission_tail,
        })
    }

    /// e(λ).
    pub fn excitation(&self, lambda: f32) -> f32 {
        self.excitation.as_ref().map_or(0.0, |p| {
            (p.pdf(lambda) as f64 * self.excitation_total) as f32
        })
    }

    /// η(λ), per nm, ∫η dλ = 1.
    pub fn emission(&self, lambda: f32) -> f32 {
        self.emission.pdf(lambda)
    }

    pub fn emission_density(&self) -> &SpectralPdf {
        &self.emission
    }

    pub fn quantum_yield(&self) -> f32 {
        self.quantum_yield
    }

    /// F(λi → λo), per nm of λi.
    pub fn eval(&self, lambda_i: f32, lambda_o: f32) -> f32 {
        if lambda_i > lambda_o {
            return 0.0;
        }
        self.quantum_yield * self.excitation(lambda_i) * self.emission(lambda_o) * lambda_i
            / lambda_o
    }

    /// ∫ F(λi → λo) dλi: the light re-emitted at λo under a flat spectrum.
    pub fn albedo(&self, lambda_o: f32) -> f32 {
        let mass = lookup(&self.stokes_mass, lambda_o);
        (self.quantum_yield as f64 * self.emission(lambda_o) as f64 * mass / lambda_o as f64) as f32
    }

    /// ∫ F(λi → λo) dλo: the share of the energy arriving at λi that is
    /// re-emitted (at any wavelength).
    pub fn reemitted(&self, lambda_i: f32) -> f32 {
        (self.quantum_yield as f64
            * self.excitation(lambda_i) as f64
            * lambda_i as f64
            * lookup(&self.emission_tail, lambda_i)) as f32
    }

    /// An excitation wavelength λi for emission at λo, drawn ∝ e(λi) on
    /// [λmin, λo], and F(λi → λo)/p(λi).
    pub fn sample(&self, u: f32, lambda_o: f32) -> Option<(f32, f32)> {
        let ex = self.excitation.as_ref()?;
        let below = ex.mass_below(lambda_o) * self.excitation_total;
        if below <= 0.0 {
            return None;
        }
        let lambda_i = ex.sample_below(u, lambda_o);
        // Q·e(λi)·η(λo)·(λi/λo) over p(λi) = e(λi)/∫_{λmin}^{λo} e.
        let weight = self.quantum_yield as f64
            * self.emission(lambda_o) as f64
            * (lambda_i / lambda_o) as f64
            * below;
        Some((lambda_i, weight as f32))
    }

    /// An emission wavelength λo for light absorbed at λi, drawn ∝ η(λo)
    /// on [λi, λmax], and F(λi → λo)/p(λo) (light paths run this way).
    pub fn sample_emission(&self, u: f32, lambda_i: f32) -> Option<(f32, f32)> {
        let e = self.excitation(lambda_i);
        let below = self.emission.mass_below(lambda_i);
        let above = 1.0 - below;
        if e <= 0.0 || above <= 0.0 {
            return None;
        }
        let lambda_o = self
            .emission
            .sample((below + u.clamp(0.0, 1.0) as f64 * above) as f32)
            .max(lambda_i);
        // Q·e(λi)·η(λo)·(λi/λo) over p(λo) = η(λo)/∫_{λi}^{λmax} η.
        let weight = self.quantum_yield as f64 * e as f64 * (lambda_i / lambda_o) as f64 * above;
        Some((lambda_o, weight as f32))
    }
}

//! A Lambertian surface that fluoresces: it reflects ρ(λ) of the light at
//! the same wavelength and absorbs e(λ) for re-emission at longer ones.
//! The bispectral BRDF (per nm of excitation wavelength λi):
//!
//!   f(λi → λo) = [ρ(λo)·δ(λi − λo) + Q·e(λi)·η(λo)·(λi/λo)·[λi ≤ λo]] / π
//!
//! with Q the quantum yield (photons out per photon absorbed), η the
//! emission shape normalised to ∫η dλ = 1 (the emitted photons' spectrum)
//! and λi/λo the Stokes factor: energy per photon falls as the wavelength
//! grows. Light is re-emitted only at wavelengths at least as long as the
//! one absorbed (scotopia's choice, Stokes' rule): photons whose emission
//! would land below the excitation wavelength are lost, so the energy
//! re-emitted never exceeds Q times the energy absorbed.
//!
//! In the path tracer a path arriving at λo continues, per member of its
//! cluster, either elastically (at λo) or from an excitation wavelength λi
//! drawn ∝ e(λi) on [λmin, λo] ([`Fluorescent::reradiate`]); after that
//! the surface scatters like a white Lambertian (`eval`, `sample`).

use std::f32::consts::FRAC_1_PI;

use scotopia_color::{SampledSpectrum, SampledWavelengths, Spectrum, LAMBDA_MAX, LAMBDA_MIN};

use super::BsdfSample;
use crate::math::Vec3;
use crate::sampling::warp::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};
use crate::texture::Texture;
use crate::wavelength::SpectralPdf;

#[derive(Debug, Clone, PartialEq)]
pub struct Fluorescent {
    /// ρ: elastic reflectance.
    pub reflectance: Texture,
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
}

impl Fluorescent {
    /// `None` when the emission spectrum has no positive value.
    pub fn new(
        reflectance: Texture,
        excitation: &Spectrum,
        emission: &Spectrum,
        quantum_yield: f32,
    ) -> Option<Self> {
        let emission = SpectralPdf::new(emission)?;
        let excitation_pdf = SpectralPdf::new(excitation);
        // The density's own normaliser, so e = pdf·total exactly.
        let excitation_total = excitation_pdf.as_ref().map_or(0.0, |p| p.integral());
        let steps = (LAMBDA_MAX - LAMBDA_MIN) as usize;
        let mut stokes_mass = vec![0.0f64; steps + 1];
        if let Some(p) = &excitation_pdf {
            // e·λ integrated by the midpoint rule on quarter-nanometres.
            for k in 0..steps {
                let lo = LAMBDA_MIN + k as f32;
                let piece: f64 = (0..4)
                    .map(|j| {
                        let l = lo + (j as f32 + 0.5) * 0.25;
                        p.pdf(l) as f64 * excitation_total * l as f64 * 0.25
                    })
                    .sum();
                stokes_mass[k + 1] = stokes_mass[k] + piece;
            }
        }
        Some(Self {
            reflectance,
            excitation: excitation_pdf,
            excitation_total,
            emission,
            quantum_yield,
            stokes_mass,
        })
    }

    /// The excitation e(λ) (fraction absorbed for re-emission).
    pub fn excitation(&self, lambda: f32) -> f32 {
        self.excitation.as_ref().map_or(0.0, |p| {
            (p.pdf(lambda) as f64 * self.excitation_total) as f32
        })
    }

    /// The emission shape η(λ), per nm, ∫η dλ = 1.
    pub fn emission(&self, lambda: f32) -> f32 {
        self.emission.pdf(lambda)
    }

    /// η as a density to sample wavelengths from.
    pub fn emission_density(&self) -> &SpectralPdf {
        &self.emission
    }

    pub fn quantum_yield(&self) -> f32 {
        self.quantum_yield
    }

    /// The fluorescent albedo at λo under a flat spectrum of excitation:
    /// Q·η(λo)/λo·∫ from λmin to λo of e(λ)·λ dλ, per nm of λo.
    pub fn fluorescent_albedo(&self, lambda_o: f32) -> f32 {
        let x = (lambda_o - LAMBDA_MIN).clamp(0.0, (self.stokes_mass.len() - 1) as f32);
        let i = (x as usize).min(self.stokes_mass.len() - 2);
        let t = (x - i as f32) as f64;
        let mass = self.stokes_mass[i] * (1.0 - t) + self.stokes_mass[i + 1] * t;
        (self.quantum_yield as f64 * self.emission(lambda_o) as f64 * mass / lambda_o as f64) as f32
    }

    /// Chooses, per live member of the cluster, whether the light leaving
    /// at its wavelength λo was reflected (the path stays at λo) or
    /// re-emitted from light absorbed at λi (the member moves to λi), and
    /// returns the factor the path's throughput takes: the chosen term of
    /// the bispectral BRDF over the probability of choosing it (times π,
    /// the white Lambertian that follows carries 1/π). One `u` serves the
    /// members, shifted by k/K each (each member's choice is uniform).
    pub fn reradiate<const K: usize>(
        &self,
        wl: &mut SampledWavelengths<K>,
        uv: [f32; 2],
        u: f32,
    ) -> SampledSpectrum<K> {
        let rho = self.reflectance.eval(wl, uv);
        let mut factor = SampledSpectrum::splat(0.0);
        for k in 0..K {
            if wl.pdf(k) == 0.0 {
                continue;
            }
            let lambda_o = wl.lambda(k);
            let a = rho.0[k].max(0.0);
            let b = self.fluorescent_albedo(lambda_o);
            if a + b <= 0.0 {
                continue;
            }
            let p_fluoresce = b / (a + b);
            let uk = (u + k as f32 / K as f32).fract();
            factor.0[k] = if uk < p_fluoresce {
                let Some(ex) = &self.excitation else {
                    continue;
                };
                let below = ex.mass_below(lambda_o) * self.excitation_total;
                let lambda_i = ex.sample_below(uk / p_fluoresce, lambda_o);
                wl.set_lambda(k, lambda_i);
                // Q·e(λi)·η(λo)·(λi/λo) over p(λi) = e(λi)/∫_{λmin}^{λo} e.
                (self.quantum_yield as f64
                    * self.emission(lambda_o) as f64
                    * (lambda_i / lambda_o) as f64
                    * below
                    / p_fluoresce as f64) as f32
            } else {
                a / (1.0 - p_fluoresce)
            };
        }
        factor
    }

    /// The white Lambertian that follows `reradiate`: cos θ_o / π.
    pub fn eval<const K: usize>(&self, wi: Vec3, wo: Vec3) -> SampledSpectrum<K> {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return SampledSpectrum::splat(0.0);
        }
        SampledSpectrum::splat(FRAC_1_PI * wo.z)
    }

    pub fn pdf(&self, wi: Vec3, wo: Vec3) -> f32 {
        if wi.z <= 0.0 || wo.z <= 0.0 {
            return 0.0;
        }
        cosine_hemisphere_pdf(wo.z)
    }

    pub fn sample<const K: usize>(&self, wi: Vec3, u: [f32; 2]) -> Option<BsdfSample<K>> {
        if wi.z <= 0.0 {
            return None;
        }
        let wo = square_to_cosine_hemisphere(u);
        let pdf = cosine_hemisphere_pdf(wo.z);
        (pdf > 0.0).then_some(BsdfSample {
            wo,
            weight: SampledSpectrum::splat(1.0),
            pdf,
            delta: false,
            collapse: false,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use scotopia_color::Tabulated;

    fn brightener() -> Fluorescent {
        // Absorbs in the near UV, emits in the blue.
        let excitation = Spectrum::tabulated(
            Tabulated::new(vec![360.0, 380.0, 410.0, 420.0], vec![0.6, 0.5, 0.1, 0.0]).unwrap(),
        );
        let emission = Spectrum::tabulated(
            Tabulated::new(vec![400.0, 440.0, 500.0], vec![0.0, 1.0, 0.0]).unwrap(),
        );
        Fluorescent::new(
            Texture::Constant(Spectrum::Constant(0.3)),
            &excitation,
            &emission,
            0.9,
        )
        .unwrap()
    }

    #[test]
    fn reradiation_is_unbiased_for_each_member() {
        // E[factor · g(λ after)] over u equals the bispectral integral
        // ρ(λo)·g(λo) + Q·η(λo)/λo·∫ e(λi)·λi·g(λi) dλi for a test g.
        let f = brightener();
        let g = |l: f32| 1.0 + (l - 360.0) / 100.0;
        let lambda_o = 450.0;
        let n = 200_000;
        let mut sum = 0.0f64;
        for i in 0..n {
            let mut wl = SampledWavelengths::<1>::new([lambda_o], [1.0]);
            let factor = f.reradiate(&mut wl, [0.0, 0.0], (i as f32 + 0.5) / n as f32);
            sum += factor.0[0] as f64 * g(wl.lambda(0)) as f64;
        }
        let m = 100_000;
        let h = (lambda_o - 360.0) as f64 / m as f64;
        let integral: f64 = (0..m)
            .map(|j| {
                let l = 360.0 + (j as f64 + 0.5) * h;
                f.excitation(l as f32) as f64 * l * g(l as f32) as f64 * h
            })
            .sum();
        let want = 0.3 * g(lambda_o) as f64
            + 0.9 * f.emission(lambda_o) as f64 / lambda_o as f64 * integral;
        let got = sum / n as f64;
        assert!((got / want - 1.0).abs() < 2e-3, "{got} vs {want}");
        // Below the excitation band nothing fluoresces: the factor is ρ.
        let mut wl = SampledWavelengths::<1>::new([380.0], [1.0]);
        let factor = f.reradiate(&mut wl, [0.0, 0.0], 0.5);
        assert!(f.emission(380.0) == 0.0 && (factor.0[0] - 0.3).abs() < 1e-6);
        assert_eq!(wl.lambda(0), 380.0);
    }

    #[test]
    fn energy_is_conserved_with_reflectance_plus_excitation_one() {
        // ρ + e = 1 and Q = 1; light enters in a narrow band at 380 nm.
        // Measured with the estimator itself: at each λo the mean of
        // factor · g(λ after) is the radiance leaving at λo. The light out
        // of the band is only the Stokes-weighted emission, and the total
        // out is below the total in.
        let e = Spectrum::tabulated(
            Tabulated::new(vec![360.0, 400.0, 430.0], vec![0.8, 0.6, 0.0]).unwrap(),
        );
        let rho = Spectrum::tabulated(Tabulated::from_fn(360.0, 830.0, 1.0, |l| 1.0 - e.eval(l)));
        let emission = Spectrum::tabulated(
            Tabulated::new(vec![370.0, 450.0, 520.0], vec![0.0, 1.0, 0.0]).unwrap(),
        );
        let f = Fluorescent::new(Texture::Constant(rho.clone()), &e, &emission, 1.0).unwrap();
        let g = |l: f32| (-((l - 380.0) / 2.0).powi(2)).exp();
        let n = 4000;
        let (mut total_in, mut total_out, mut emitted) = (0.0f64, 0.0f64, 0.0f64);
        for lo in 360..830 {
            let lambda_o = lo as f32 + 0.5;
            let out: f64 = (0..n)
                .map(|i| {
                    let mut wl = SampledWavelengths::<1>::new([lambda_o], [1.0]);
                    let factor = f.reradiate(&mut wl, [0.0, 0.0], (i as f32 + 0.5) / n as f32);
                    factor.0[0] as f64 * g(wl.lambda(0)) as f64
                })
                .sum::<f64>()
                / n as f64;
            let reflected = rho.eval(lambda_o) as f64 * g(lambda_o) as f64;
            total_in += g(lambda_o) as f64;
            total_out += out;
            emitted += out - reflected;
            // Beyond the input band only emission leaves, and only where η > 0.
            if (lambda_o - 380.0).abs() > 20.0 && f.emission(lambda_o) == 0.0 {
                assert!(out.abs() < 1e-9, "{lambda_o}: {out}");
            }
        }
        let absorbed: f64 = (360..830)
            .map(|l| e.eval(l as f32 + 0.5) as f64 * g(l as f32 + 0.5) as f64)
            .sum();
        assert!(total_out < total_in, "{total_out} vs {total_in}");
        assert!(
            emitted > 0.0 && emitted < absorbed,
            "{emitted} vs {absorbed}"
        );
        // What is lost is the Stokes shift and the emission below 380 nm:
        // about ∫ η(λo)·380/λo over λo ≥ 380 of what was absorbed.
        let stokes: f64 = (0..15_000)
            .map(|i| {
                let l = 380.0 + (i as f32 + 0.5) * 0.01;
                f.emission(l) as f64 * 380.0 / l as f64 * 0.01
            })
            .sum();
        assert!(
            (emitted / absorbed - stokes).abs() < 0.02,
            "{} vs {stokes}",
            emitted / absorbed
        );
    }

    #[test]
    fn the_normalised_emission_integrates_to_one() {
        let f = brightener();
        let total: f64 = (0..47_000)
            .map(|i| f.emission(360.0 + (i as f32 + 0.5) * 0.01) as f64 * 0.01)
            .sum();
        assert!((total - 1.0).abs() < 1e-4, "{total}");
        assert!((f.excitation(370.0) - 0.55).abs() < 1e-3);
    }
}

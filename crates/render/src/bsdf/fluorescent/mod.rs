//! A Lambertian surface that fluoresces: it reflects ρ(λ) of the light at
//! the same wavelength and re-emits some of what it absorbs at other
//! wavelengths. The bispectral BRDF (per nm of excitation wavelength λi):
//!
//!   f(λi → λo) = [ρ(λo)·δ(λi − λo) + F(λi → λo)] / π
//!
//! with the reradiation F given either by an excitation spectrum, an
//! emission shape and a quantum yield ([`Separable`], with the Stokes
//! factor λi/λo) or by a measured Donaldson matrix ([`Donaldson`]).
//!
//! In the path tracer a path arriving at λo continues, per member of its
//! cluster, either elastically (at λo) or from an excitation wavelength λi
//! drawn ∝ F(λi → λo) as well as the model allows ([`Fluorescent::reradiate`]);
//! after that the surface scatters like a white Lambertian (`eval`, `sample`).

mod donaldson;
mod separable;

use std::f32::consts::FRAC_1_PI;
use std::sync::Arc;

use scotopia_color::{SampledSpectrum, SampledWavelengths, Spectrum};

pub use donaldson::Donaldson;
pub use separable::Separable;

use super::BsdfSample;
use crate::math::Vec3;
use crate::sampling::spectral_pdf::SpectralPdf;
use crate::sampling::warp::{cosine_hemisphere_pdf, square_to_cosine_hemisphere};
use crate::texture::{TexPoint, Texture};

/// How absorbed light is re-emitted.
#[derive(Debug, Clone, PartialEq)]
/// Both are shared: the tables are large and materials are cloned.
pub enum Reradiation {
    Separable(Arc<Separable>),
    Matrix(Arc<Donaldson>),
}

#[derive(Debug, Clone, PartialEq)]
pub struct Fluorescent {
    /// ρ: elastic reflectance.
    pub reflectance: Texture,
    pub reradiation: Reradiation,
}

impl Fluorescent {
    /// The separable model; `None` when the emission spectrum has no
    /// positive value.
    pub fn new(
        reflectance: Texture,
        excitation: &Spectrum,
        emission: &Spectrum,
        quantum_yield: f32,
    ) -> Option<Self> {
        Some(Self {
            reflectance,
            reradiation: Reradiation::Separable(Arc::new(Separable::new(
                excitation,
                emission,
                quantum_yield,
            )?)),
        })
    }

    /// A measured reradiation matrix.
    pub fn from_matrix(reflectance: Texture, matrix: Arc<Donaldson>) -> Self {
        Self {
            reflectance,
            reradiation: Reradiation::Matrix(matrix),
        }
    }

    /// F(λi → λo), per nm of λi.
    pub fn eval_reradiation(&self, lambda_i: f32, lambda_o: f32) -> f32 {
        match &self.reradiation {
            Reradiation::Separable(s) => s.eval(lambda_i, lambda_o),
            Reradiation::Matrix(m) => m.eval(lambda_i, lambda_o),
        }
    }

    /// The fluorescent albedo at λo under a flat spectrum of excitation,
    /// ∫ F(λi → λo) dλi, per nm of λo.
    pub fn fluorescent_albedo(&self, lambda_o: f32) -> f32 {
        match &self.reradiation {
            Reradiation::Separable(s) => s.albedo(lambda_o),
            Reradiation::Matrix(m) => m.albedo(lambda_o),
        }
    }

    /// ∫ F(λi → λo) dλo: the share of the energy arriving at λi that is
    /// re-emitted at any wavelength.
    pub fn reemitted(&self, lambda_i: f32) -> f32 {
        match &self.reradiation {
            Reradiation::Separable(s) => s.reemitted(lambda_i),
            Reradiation::Matrix(m) => m.reemitted(lambda_i),
        }
    }

    /// The density of the re-emitted light over λo, to sample
    /// wavelengths from.
    pub fn emission_density(&self) -> &SpectralPdf {
        match &self.reradiation {
            Reradiation::Separable(s) => s.emission_density(),
            Reradiation::Matrix(m) => m.emission_density(),
        }
    }

    /// The separable model's parts, when the material uses it.
    pub fn separable(&self) -> Option<&Separable> {
        match &self.reradiation {
            Reradiation::Separable(s) => Some(s),
            Reradiation::Matrix(_) => None,
        }
    }

    fn sample_excitation(&self, u: f32, lambda_o: f32) -> Option<(f32, f32)> {
        match &self.reradiation {
            Reradiation::Separable(s) => s.sample(u, lambda_o),
            Reradiation::Matrix(m) => m.sample(u, lambda_o),
        }
    }

    fn sample_emission(&self, u: f32, lambda_i: f32) -> Option<(f32, f32)> {
        match &self.reradiation {
            Reradiation::Separable(s) => s.sample_emission(u, lambda_i),
            Reradiation::Matrix(m) => m.sample_emission(u, lambda_i),
        }
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
        uv: impl Into<TexPoint>,
        u: f32,
    ) -> SampledSpectrum<K> {
        let uv: TexPoint = uv.into();
        let live = SampledSpectrum::from_fn(|k| wl.pdf(k));
        let albedo = |l| self.fluorescent_albedo(l);
        self.choose(wl, &live, uv, u, albedo, |u, l| {
            self.sample_excitation(u, l)
        })
        .0
    }

    /// Light travelling the other way (a light path): per live member with
    /// β ≠ 0, whether the light arriving at its wavelength λi is reflected
    /// (stays at λi) or re-emitted at a λo drawn ∝ F(λi → λo). Returns the
    /// throughput factor (times π, as in `reradiate`) and which members
    /// were re-emitted.
    pub fn reradiate_forward<const K: usize>(
        &self,
        wl: &mut SampledWavelengths<K>,
        alive: &SampledSpectrum<K>,
        uv: impl Into<TexPoint>,
        u: f32,
    ) -> (SampledSpectrum<K>, [bool; K]) {
        let uv: TexPoint = uv.into();
        let albedo = |l| self.reemitted(l);
        self.choose(wl, alive, uv, u, albedo, |u, l| self.sample_emission(u, l))
    }

    /// Both directions' choice, per member k with `live[k]` ≠ 0: elastic
    /// (ρ) or shifted (`albedo` of the member's wavelength, the other
    /// wavelength drawn by `sample`, which returns it and F/p), chosen in
    /// proportion to the two.
    fn choose<const K: usize>(
        &self,
        wl: &mut SampledWavelengths<K>,
        live: &SampledSpectrum<K>,
        uv: TexPoint,
        u: f32,
        albedo: impl Fn(f32) -> f32,
        sample: impl Fn(f32, f32) -> Option<(f32, f32)>,
    ) -> (SampledSpectrum<K>, [bool; K]) {
        let rho = self.reflectance.eval(wl, uv);
        let mut factor = SampledSpectrum::splat(0.0);
        let mut moved = [false; K];
        for k in (0..K).filter(|&k| live.0[k] != 0.0) {
            let lambda = wl.lambda(k);
            let a = rho.0[k].max(0.0);
            let b = albedo(lambda);
            if a + b <= 0.0 {
                continue;
            }
            let p_shift = b / (a + b);
            let uk = (u + k as f32 / K as f32).fract();
            factor.0[k] = if uk < p_shift {
                let Some((other, weight)) = sample(uk / p_shift, lambda) else {
                    continue;
                };
                wl.set_lambda(k, other);
                moved[k] = true;
                weight / p_shift
            } else {
                a / (1.0 - p_shift)
            };
        }
        (factor, moved)
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

    fn sep(f: &Fluorescent) -> &Separable {
        f.separable().unwrap()
    }

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

    /// Σ factor·g(λ after) over `n` stratified numbers, for one member
    /// arriving at `lambda_o` and reradiated backwards.
    pub(super) fn backward_sum(
        f: &Fluorescent,
        lambda_o: f32,
        g: impl Fn(f32) -> f32,
        n: usize,
    ) -> f64 {
        (0..n)
            .map(|i| {
                let mut wl = SampledWavelengths::<1>::new([lambda_o], [1.0]);
                let factor = f.reradiate(&mut wl, [0.0, 0.0], (i as f32 + 0.5) / n as f32);
                factor.0[0] as f64 * g(wl.lambda(0)) as f64
            })
            .sum()
    }

    #[test]
    fn forward_reradiation_is_unbiased() {
        // E[factor · g(λ after)] from λi equals ρ(λi)·g(λi) + ∫F(λi → λo)·g(λo) dλo,
        // for the separable model and a matrix.
        let g = |l: f32| 1.0 + (l - 360.0) / 100.0;
        let grid: Vec<f32> = (0..31).map(|i| 400.0 + 10.0 * i as f32).collect();
        let mut cells = vec![0.0; 31 * 31];
        for (r, &lo) in grid.iter().enumerate() {
            for (c, &li) in grid.iter().enumerate() {
                if li <= 440.0 && (460.0..=520.0).contains(&lo) {
                    cells[r * 31 + c] = 0.01 * (1.0 + (lo - 460.0) / 60.0);
                }
            }
        }
        let matrix = Donaldson::new(&grid, &grid, &cells).unwrap().0;
        let cases = [
            (brightener(), 380.0f32),
            (
                Fluorescent::from_matrix(
                    Texture::Constant(Spectrum::Constant(0.3)),
                    Arc::new(matrix),
                ),
                421.0,
            ),
        ];
        for (f, lambda_i) in cases {
            let n = 200_000;
            let mut sum = 0.0f64;
            for i in 0..n {
                let mut wl = SampledWavelengths::<1>::new([lambda_i], [1.0]);
                let (factor, _) = f.reradiate_forward(
                    &mut wl,
                    &SampledSpectrum::splat(1.0),
                    [0.0, 0.0],
                    (i as f32 + 0.5) / n as f32,
                );
                sum += factor.0[0] as f64 * g(wl.lambda(0)) as f64;
            }
            let m = 47_000;
            let h = 470.0 / m as f64;
            let integral: f64 = (0..m)
                .map(|j| {
                    let lo = 360.0 + (j as f64 + 0.5) * h;
                    f.eval_reradiation(lambda_i, lo as f32) as f64 * g(lo as f32) as f64 * h
                })
                .sum();
            let want = 0.3 * g(lambda_i) as f64 + integral;
            let got = sum / n as f64;
            assert!(integral > 0.01, "{integral}");
            assert!(
                (got / want - 1.0).abs() < 3e-3,
                "{lambda_i}: {got} vs {want}"
            );
        }
    }

    #[test]
    fn reradiation_is_unbiased_for_each_member() {
        // E[factor · g(λ after)] over u equals the bispectral integral
        // ρ(λo)·g(λo) + Q·η(λo)/λo·∫ e(λi)·λi·g(λi) dλi for a test g.
        let f = brightener();
        let g = |l: f32| 1.0 + (l - 360.0) / 100.0;
        let lambda_o = 450.0;
        let n = 200_000;
        let sum = backward_sum(&f, lambda_o, g, n);
        let m = 100_000;
        let h = (lambda_o - 360.0) as f64 / m as f64;
        let integral: f64 = (0..m)
            .map(|j| {
                let l = 360.0 + (j as f64 + 0.5) * h;
                sep(&f).excitation(l as f32) as f64 * l * g(l as f32) as f64 * h
            })
            .sum();
        let want = 0.3 * g(lambda_o) as f64
            + 0.9 * sep(&f).emission(lambda_o) as f64 / lambda_o as f64 * integral;
        let got = sum / n as f64;
        assert!((got / want - 1.0).abs() < 2e-3, "{got} vs {want}");
        // Below the excitation band nothing fluoresces: the factor is ρ.
        let mut wl = SampledWavelengths::<1>::new([380.0], [1.0]);
        let factor = f.reradiate(&mut wl, [0.0, 0.0], 0.5);
        assert!(sep(&f).emission(380.0) == 0.0 && (factor.0[0] - 0.3).abs() < 1e-6);
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
            if (lambda_o - 380.0).abs() > 20.0 && sep(&f).emission(lambda_o) == 0.0 {
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
                sep(&f).emission(l) as f64 * 380.0 / l as f64 * 0.01
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
            .map(|i| sep(&f).emission(360.0 + (i as f32 + 0.5) * 0.01) as f64 * 0.01)
            .sum();
        assert!((total - 1.0).abs() < 1e-4, "{total}");
        assert!((sep(&f).excitation(370.0) - 0.55).abs() < 1e-3);
    }
}

#[cfg(test)]
mod reemission_tests {
    use super::*;
    use scotopia_color::Tabulated;

    #[test]
    fn reemitted_is_the_integral_over_emission_wavelengths() {
        let e = Spectrum::tabulated(Tabulated::new(vec![360.0, 420.0], vec![0.7, 0.0]).unwrap());
        let emission = Spectrum::tabulated(
            Tabulated::new(vec![380.0, 440.0, 520.0], vec![0.0, 1.0, 0.0]).unwrap(),
        );
        let f = Fluorescent::new(Texture::constant(0.2), &e, &emission, 0.8).unwrap();
        for lambda_i in [365.0f32, 390.0, 410.0] {
            let want: f64 = (0..47_000)
                .map(|i| {
                    let lo = 360.0 + (i as f32 + 0.5) * 0.01;
                    f.eval_reradiation(lambda_i, lo) as f64 * 0.01
                })
                .sum();
            let got = f.reemitted(lambda_i) as f64;
            assert!(
                (got - want).abs() < 1e-3 * want.max(1e-3),
                "{lambda_i}: {got} vs {want}"
            );
        }
    }

    #[test]
    fn a_matrix_reradiates_without_bias() {
        // A band 400–430 nm re-emitted at 480–560 nm on a 5 nm grid; the
        // estimator's mean of factor·g(λ after) is ρ·g(λo) + ∫F·g.
        let grid: Vec<f32> = (0..61).map(|i| 380.0 + 5.0 * i as f32).collect();
        let n = grid.len();
        let mut v = vec![0.0f32; n * n];
        for (r, &lo) in grid.iter().enumerate() {
            for (c, &li) in grid.iter().enumerate() {
                if (400.0..=430.0).contains(&li) && (480.0..=560.0).contains(&lo) {
                    v[r * n + c] = 0.02 * (li - 395.0) / 35.0;
                }
            }
        }
        let (m, _) = Donaldson::new(&grid, &grid, &v).unwrap();
        let f = Fluorescent::from_matrix(Texture::constant(0.4), Arc::new(m));
        let g = |l: f32| 2.0 - (l - 380.0) / 300.0;
        let lambda_o = 512.5;
        let samples = 100_000;
        let sum = super::tests::backward_sum(&f, lambda_o, g, samples);
        let integral: f64 = (0..10_000)
            .map(|i| {
                let l = 380.0 + (i as f32 + 0.5) * 0.01;
                (f.eval_reradiation(l, lambda_o) * g(l)) as f64 * 0.01
            })
            .sum();
        let want = 0.4 * g(lambda_o) as f64 + integral;
        let got = sum / samples as f64;
        assert!(
            integral > 0.05 * want,
            "the test needs fluorescence: {integral}"
        );
        assert!((got / want - 1.0).abs() < 2e-3, "{got} vs {want}");
    }
}

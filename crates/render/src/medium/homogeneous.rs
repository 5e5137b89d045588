//! A homogeneous medium (Mitsuba's `homogeneous`): σ_t and albedo spectra,
//! times `scale`, the same everywhere. Transmittance follows Beer–Lambert,
//! T(t) = exp(−σ_t t); distances are drawn from the first wavelength's
//! free-flight density σ_t e^{−σ_t t}.

use scotopia_color::{SampledSpectrum, SampledWavelengths, Spectrum};

use super::{densities_from_logs, MediumEvent, Phase};

#[derive(Debug, Clone, PartialEq)]
pub struct Homogeneous {
    /// Extinction coefficient per scene unit (before `scale`).
    pub sigma_t: Spectrum,
    /// Single-scattering albedo σ_s / σ_t, in [0, 1].
    pub albedo: Spectrum,
    /// Multiplies σ_t (Mitsuba's `scale`: the density of the medium).
    pub scale: f32,
    pub phase: Phase,
}

impl Homogeneous {
    /// σ_t on the wavelengths (scaled).
    pub fn sigma_t<const K: usize>(&self, wl: &SampledWavelengths<K>) -> SampledSpectrum<K> {
        self.sigma_t.sample(wl).map(|s| (s * self.scale).max(0.0))
    }

    /// Beer–Lambert transmittance over a distance `t`.
    pub fn transmittance<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        t: f32,
    ) -> SampledSpectrum<K> {
        self.sigma_t(wl).map(|s| beer(s, t))
    }

    /// The next event along a segment of length `t_max` (`f32::INFINITY`
    /// for a ray leaving the scene): a free flight drawn from the first
    /// wavelength's density σ_t e^{−σ_t t} with `u`. Scattering at t has
    /// density σ_t,k e^{−σ_t,k t} for wavelength k, passing the segment
    /// probability e^{−σ_t,k t_max}.
    pub fn sample_event<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        t_max: f32,
        u: f32,
    ) -> MediumEvent<K> {
        let st = self.sigma_t(wl);
        let t = if st.0[0] > 0.0 {
            -(1.0 - u).ln() / st.0[0]
        } else {
            f32::INFINITY
        };
        if t < t_max {
            let logs = std::array::from_fn(|k| {
                if st.0[k] > 0.0 {
                    st.0[k].ln() - st.0[k] * t
                } else {
                    f32::NEG_INFINITY
                }
            });
            MediumEvent {
                t,
                scattered: true,
                own: self.albedo.sample(wl).map(|a| a.clamp(0.0, 1.0)),
                density: densities_from_logs(logs),
            }
        } else {
            let logs = std::array::from_fn(|k| if st.0[k] > 0.0 { -st.0[k] * t_max } else { 0.0 });
            MediumEvent {
                t: t_max,
                scattered: false,
                own: SampledSpectrum::splat(1.0),
                density: densities_from_logs(logs),
            }
        }
    }
}

/// e^{−σt}, 1 in clear air whatever the distance (0 · ∞ is not a number).
fn beer(sigma: f32, t: f32) -> f32 {
    if sigma > 0.0 {
        (-sigma * t).exp()
    } else {
        1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::{mean_and_se, uniforms};
    use scotopia_color::spectrum::Tabulated;

    /// σ_t rising fourfold from red to blue (haze: more extinction at
    /// short wavelengths), albedo falling from 0.95 to 0.6.
    fn haze() -> Homogeneous {
        Homogeneous {
            sigma_t: Spectrum::tabulated(
                Tabulated::new(vec![400.0, 700.0], vec![0.8, 0.2]).unwrap(),
            ),
            albedo: Spectrum::tabulated(
                Tabulated::new(vec![400.0, 700.0], vec![0.6, 0.95]).unwrap(),
            ),
            scale: 1.5,
            phase: Phase::Isotropic,
        }
    }

    /// A path of one event's estimate per wavelength: f_k / mean(p), the
    /// balance heuristic over the cluster (own · density / mean density).
    fn one_event_weight(e: &MediumEvent<4>) -> SampledSpectrum<4> {
        let mean = e.density.average();
        SampledSpectrum::from_fn(|k| e.own.0[k] * e.density.0[k] / mean)
    }

    fn cluster() -> SampledWavelengths<4> {
        SampledWavelengths::new([430.0, 510.0, 590.0, 680.0], [1.0 / 300.0; 4])
    }

    #[test]
    fn transmittance_is_beer_lambert_per_wavelength() {
        let m = haze();
        let wl = cluster();
        let t = m.transmittance(&wl, 2.0);
        for k in 0..4 {
            let lambda = wl.lambda(k);
            let sigma = 1.5 * (0.8 + (lambda - 400.0) / 300.0 * (0.2 - 0.8));
            assert!((t.0[k] - (-sigma * 2.0).exp()).abs() < 1e-6, "{lambda} nm");
        }
    }

    #[test]
    fn distance_sampling_with_cluster_mis_is_unbiased_for_every_wavelength() {
        // Along a segment of length L: the probability of passing is
        // T_k(L), and the scattered weight integrates to
        // ∫₀^L T_k σ_s,k dt = α_k (1 − T_k(L)). Each wavelength in turn
        // is the sampled one (the cluster's rotation makes that choice
        // uniform), and the estimates use the mean density over the four.
        let m = haze();
        let base = cluster();
        let length = 1.3f32;
        let n = 200_000;
        let mut u = uniforms(5);
        let (mut passed, mut scattered) = (vec![[0.0f64; 4]; n], vec![[0.0f64; 4]; n]);
        for i in 0..n {
            let mut wl = base;
            let first = i % 4;
            wl.rotate_to_front(first);
            let s = m.sample_event(&wl, length, u());
            let w = one_event_weight(&s);
            for k in 0..4 {
                // Back to the unrotated order.
                let j = (k + first) % 4;
                if s.scattered {
                    scattered[i][j] = w.0[k] as f64;
                } else {
                    passed[i][j] = w.0[k] as f64;
                }
            }
        }
        let st = m.sigma_t(&base);
        let albedo = m.albedo.sample(&base);
        for k in 0..4 {
            let tr = (-(st.0[k] as f64) * length as f64).exp();
            let col = |v: &Vec<[f64; 4]>| v.iter().map(|x| x[k]).collect::<Vec<f64>>();
            let (p, p_se) = mean_and_se(&col(&passed));
            let (s, s_se) = mean_and_se(&col(&scattered));
            assert!(
                (p - tr).abs() < 4.0 * p_se,
                "λ {k}: passed {p} ± {p_se}, T {tr}"
            );
            let expected = albedo.0[k] as f64 * (1.0 - tr);
            assert!(
                (s - expected).abs() < 4.0 * s_se,
                "λ {k}: scattered {s} ± {s_se}, {expected}"
            );
        }
    }

    #[test]
    fn a_clear_medium_is_passed_through() {
        let m = Homogeneous {
            sigma_t: Spectrum::Constant(0.0),
            albedo: Spectrum::Constant(1.0),
            scale: 1.0,
            phase: Phase::Isotropic,
        };
        let s = m.sample_event(&cluster(), f32::INFINITY, 0.5);
        assert!(!s.scattered);
        assert_eq!(one_event_weight(&s), SampledSpectrum::splat(1.0));
    }
}

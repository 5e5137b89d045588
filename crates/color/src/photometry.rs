//! Absolute photometry: spectral radiance (W·sr⁻¹·m⁻²·nm⁻¹) to CIE X, Y, Z
//! in cd/m² and scotopic V′ in scotopic cd/m².

use crate::cie;
use crate::sampled::{SampledSpectrum, SampledWavelengths};
use crate::spectrum::Spectrum;
use crate::{LAMBDA_MAX, LAMBDA_MIN};

/// Maximum luminous efficacy of photopic vision, lm/W (CIE 015:2018; the SI
/// definition of the candela fixes 683 lm/W at 540 THz).
pub const K_M: f64 = 683.0;
/// Maximum luminous efficacy of scotopic vision, lm/W (CIE 1951 V′; the
/// exact value consistent with 683 lm/W at 540 THz is 1700.06, rounded to 1700
/// as CIE 015 and lighting practice use).
pub const K_M_SCOTOPIC: f64 = 1700.0;

/// Absolute tristimulus values X, Y, Z (Y in cd/m²) and scotopic luminance V′.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Xyzv {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub v: f64,
}

impl Xyzv {
    pub fn xyz(&self) -> [f64; 3] {
        [self.x, self.y, self.z]
    }

    /// Chromaticity (x, y); `None` for black.
    pub fn xy(&self) -> Option<[f64; 2]> {
        xyz_to_xy(self.xyz())
    }

    /// S/P ratio V′/Y, the scotopic-to-photopic ratio quoted for lamps.
    pub fn sp_ratio(&self) -> Option<f64> {
        (self.y > 0.0).then(|| self.v / self.y)
    }
}

/// Chromaticity x = X/(X+Y+Z), y = Y/(X+Y+Z); `None` when X+Y+Z is not positive.
pub fn xyz_to_xy([x, y, z]: [f64; 3]) -> Option<[f64; 2]> {
    let sum = x + y + z;
    (sum > 0.0).then(|| [x / sum, y / sum])
}

/// Scale that puts Pattanaik et al. 1998's rod-signal fit on the scotopic
/// cd/m² scale (K′m = 1700 lm/W): the fit gives R/Y = 0.8433 for D65, whose
/// true V′/Y is 2.4645, so 2.4645 / 0.8433. (scotopia's calibration; the
/// fit itself is on a scale the paper does not state.)
pub const ROD_FIT_SCALE: f64 = 2.9225;

/// Estimates V′ (scotopic cd/m²) from X, Y, Z (cd/m²) when only those are
/// known, with the linear fit R = −0.702X + 1.039Y + 0.433Z (Pattanaik et
/// al. 1998) scaled by [`ROD_FIT_SCALE`]. Exact for D65; about 13 % low for
/// illuminant A (test below); never negative.
pub fn estimate_scotopic([x, y, z]: [f64; 3]) -> f64 {
    (ROD_FIT_SCALE * (-0.702 * x + 1.039 * y + 0.433 * z)).max(0.0)
}

/// The wavelengths at which to integrate `s` over 360–830 nm: the 1 nm grid
/// merged with the spectrum's own tabulated wavelengths (trapezoid nodes).
pub fn integration_nodes(s: &Spectrum) -> Vec<f32> {
    let mut nodes: Vec<f32> = (LAMBDA_MIN as u32..=LAMBDA_MAX as u32)
        .map(|l| l as f32)
        .collect();
    let extra = s.breakpoints();
    if !extra.is_empty() {
        nodes.extend(
            extra
                .iter()
                .filter(|&&l| (LAMBDA_MIN..=LAMBDA_MAX).contains(&l)),
        );
        nodes.sort_by(f32::total_cmp);
        nodes.dedup();
    }
    nodes
}

/// ∫ S(λ)·{x̄, ȳ, z̄, V′}(λ) dλ over 360–830 nm (no efficacy factor), by the
/// trapezoid rule on the 1 nm grid merged with the spectrum's own tabulated
/// wavelengths, so narrow emission lines are integrated, not skipped.
pub fn integrate_observers(s: &Spectrum) -> [f64; 4] {
    integrate_weighted(s, cie::observers)
}

/// ∫ S(λ)·w(λ) dλ over 360–830 nm for each of the N weighting functions
/// `weights` gives at λ, as [`integrate_observers`] integrates.
pub fn integrate_weighted<const N: usize>(
    s: &Spectrum,
    weights: impl Fn(f32) -> [f32; N],
) -> [f64; N] {
    let nodes = integration_nodes(s);
    let integrand = |l: f32| {
        let v = s.eval(l) as f64;
        weights(l).map(|c| c as f64 * v)
    };
    let mut sum = [0.0f64; N];
    let mut prev = (nodes[0], integrand(nodes[0]));
    for &l in &nodes[1..] {
        let f = integrand(l);
        let h = (l - prev.0) as f64;
        for k in 0..N {
            sum[k] += 0.5 * h * (prev.1[k] + f[k]);
        }
        prev = (l, f);
    }
    sum
}

/// Absolute X, Y, Z (cd/m²) and V′ (scotopic cd/m²) of a spectral radiance:
/// X = K_m ∫ L x̄ dλ, …, V′ = K′_m ∫ L V′ dλ.
pub fn spectrum_to_xyzv(s: &Spectrum) -> Xyzv {
    let [x, y, z, v] = integrate_observers(s);
    Xyzv {
        x: K_M * x,
        y: K_M * y,
        z: K_M * z,
        v: K_M_SCOTOPIC * v,
    }
}

/// Monte Carlo estimate of absolute X, Y, Z, V′ from one wavelength cluster:
/// (1/K) Σₖ K_m·{x̄,ȳ,z̄}(λₖ)·L(λₖ)/p(λₖ), and K′_m·V′ likewise. Wavelengths
/// with zero density (terminated) contribute nothing.
#[inline]
pub fn estimate_xyzv<const K: usize>(
    radiance: &SampledSpectrum<K>,
    wavelengths: &SampledWavelengths<K>,
) -> [f32; 4] {
    let out = estimate_weighted(radiance, wavelengths, cie::observers);
    [
        out[0] * K_M as f32,
        out[1] * K_M as f32,
        out[2] * K_M as f32,
        out[3] * K_M_SCOTOPIC as f32,
    ]
}

/// Monte Carlo estimate of ∫ L(λ)·w(λ) dλ for each of the N weighting
/// functions `weights` gives at λ, from one wavelength cluster: (1/K)
/// Σₖ w(λₖ)·L(λₖ)/p(λₖ), without an efficacy factor.
#[inline]
pub fn estimate_weighted<const K: usize, const N: usize>(
    radiance: &SampledSpectrum<K>,
    wavelengths: &SampledWavelengths<K>,
    weights: impl Fn(f32) -> [f32; N],
) -> [f32; N] {
    let mut out = [0.0f32; N];
    for i in 0..K {
        let pdf = wavelengths.pdf(i);
        if pdf == 0.0 {
            continue;
        }
        let o = weights(wavelengths.lambda(i));
        let w = radiance[i] / (pdf * K as f32);
        for k in 0..N {
            out[k] += o[k] * w;
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::spectrum::Tabulated;

    #[test]
    fn the_rod_fit_estimates_scotopic_luminance() {
        // Against the integral of V′: D65 by construction, A and F11 as a
        // check of how far the linear fit carries.
        for (name, tolerance) in [("D65", 0.005), ("A", 0.15), ("F11", 0.15)] {
            let s = crate::cie::illuminant(name).unwrap();
            let v = spectrum_to_xyzv(&s);
            let estimate = estimate_scotopic([v.x, v.y, v.z]);
            let err = estimate / v.v - 1.0;
            assert!(err.abs() < tolerance, "{name}: {err:+.3}");
        }
    }

    #[test]
    fn equal_energy_is_white_with_the_standard_sums() {
        let e = spectrum_to_xyzv(&Spectrum::Constant(1.0));
        let [x, y] = e.xy().unwrap();
        assert!(
            (x - 1.0 / 3.0).abs() < 2e-4 && (y - 1.0 / 3.0).abs() < 2e-4,
            "{x} {y}"
        );
        // 683 lm/W × Σȳ (≈106.857 nm) cd/m².
        assert!((e.y / (683.0 * 106.857) - 1.0).abs() < 1e-3, "{}", e.y);
    }

    #[test]
    fn monochromatic_555_line_is_683_lm_per_watt() {
        // A 1 nm wide triangle of unit area at 555 nm, between the 1 nm
        // samples: Y = 683·ȳ(555) = 683 (ȳ is flat to 10⁻⁵ over the line).
        let line = Tabulated::new(vec![554.5, 555.0, 555.5], vec![0.0, 2.0, 0.0]).unwrap();
        let xyzv = spectrum_to_xyzv(&line.into());
        assert!((xyzv.y - 683.0).abs() < 0.05, "{}", xyzv.y);
        // V′(555) = 0.402 (CIE 1951): 1700 × 0.402.
        assert!((xyzv.v - 1700.0 * 0.402).abs() < 0.5, "{}", xyzv.v);
    }

    #[test]
    fn cluster_estimate_converges_to_the_integral() {
        // Stratified clusters over a blackbody, jitters from a seeded
        // SplitMix64: the mean of many estimates agrees with the integral
        // within 4 standard errors.
        let s = Spectrum::blackbody(3000.0).unwrap();
        let exact = spectrum_to_xyzv(&s);
        let n = 20_000;
        let mut sum = [0.0f64; 4];
        let mut sum2 = [0.0f64; 4];
        let mut state = 0x5c07_0b1a_u64;
        for _ in 0..n {
            state = state.wrapping_add(0x9e37_79b9_7f4a_7c15);
            let mut z = state;
            z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
            let u = ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32;
            let wl = SampledWavelengths::<4>::sample_uniform(u);
            let e = estimate_xyzv(&s.sample(&wl), &wl);
            for k in 0..4 {
                sum[k] += e[k] as f64;
                sum2[k] += (e[k] as f64).powi(2);
            }
        }
        let exact = [exact.x, exact.y, exact.z, exact.v];
        for k in 0..4 {
            let mean = sum[k] / n as f64;
            let se = ((sum2[k] / n as f64 - mean * mean) / n as f64).sqrt();
            assert!(
                (mean - exact[k]).abs() < 4.0 * se + 1e-5 * exact[k],
                "{k}: {mean} vs {}",
                exact[k]
            );
        }
    }
}

//! The spectral film: per pixel, the mean spectral radiance in N equal
//! wavelength bands over 360–830 nm, estimated from the same paths as
//! X, Y, Z, V′ (each cluster member adds L/(p·K) to its band).

use scotopia_color::{SampledSpectrum, SampledWavelengths, LAMBDA_MAX, LAMBDA_MIN};

/// N equal bands over 360–830 nm.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Bands(pub usize);

impl Bands {
    /// Width of a band, nm.
    pub fn width(self) -> f32 {
        (LAMBDA_MAX - LAMBDA_MIN) / self.0 as f32
    }

    /// Centre wavelength of band `i`, nm.
    pub fn centre(self, i: usize) -> f32 {
        LAMBDA_MIN + (i as f32 + 0.5) * self.width()
    }

    /// Adds one cluster's estimate of ∫_band L dλ / width to `sums`.
    #[inline]
    pub fn add<const K: usize>(
        self,
        sums: &mut [f64],
        radiance: &SampledSpectrum<K>,
        wl: &SampledWavelengths<K>,
    ) {
        let w = self.width();
        for k in 0..K {
            let p = wl.pdf(k);
            if p <= 0.0 {
                continue;
            }
            let i = ((wl.lambda(k) - LAMBDA_MIN) / w) as usize;
            if let Some(s) = sums.get_mut(i.min(self.0 - 1)) {
                *s += (radiance[k] / (p * K as f32 * w)) as f64;
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_constant_spectrum_fills_every_band_with_its_value() {
        let bands = Bands(47);
        assert!((bands.width() - 10.0).abs() < 1e-5 && (bands.centre(0) - 365.0).abs() < 1e-4);
        let mut sums = vec![0.0; 47];
        let n = 20_000;
        for i in 0..n {
            let wl = SampledWavelengths::<4>::sample_uniform((i as f32 + 0.5) / n as f32);
            bands.add(&mut sums, &SampledSpectrum::splat(2.0), &wl);
        }
        for s in sums {
            assert!((s / n as f64 - 2.0).abs() < 0.05, "{}", s / n as f64);
        }
    }
}

//! The light a bidirectional sample's light subpath starts from, chosen
//! for the sample's cluster.
//!
//! The cluster is drawn first (SWC: a light chosen by
//! power, K wavelengths stratified over its spectrum); the light subpath
//! then starts on light l with probability ∝ P(l)·Σₖ p_l(λₖ), P by power,
//! p_l the light's spectral density: the posterior of the light that drew
//! the cluster. With one light, or lights of distinct spectra, that is the
//! light SWC chose; unlike reusing SWC's choice, its probability is known
//! for every light given the cluster, so every strategy's density (a
//! light hit by a camera path, a light sampled for a connection) is too.

use scotopia_color::SampledWavelengths;

use super::LightChoice;

/// [`LightChoice::for_cluster`]'s choice for one cluster: probabilities
/// and their running sum (a row's scratch, no allocation once warm).
#[derive(Debug, Default)]
pub(crate) struct ClusterChoice {
    prob: Vec<f32>,
    cdf: Vec<f32>,
}

impl LightChoice {
    /// The choice for cluster `wl`: light l with probability
    /// ∝ P(l)·Σₖ p_l(λₖ), in `out`.
    pub(crate) fn for_cluster<const K: usize>(
        &self,
        wl: &SampledWavelengths<K>,
        out: &mut ClusterChoice,
    ) {
        out.prob.clear();
        out.cdf.clear();
        let mut total = 0.0f32;
        for (spectrum, &p) in self.spectra.iter().zip(&self.power_probability) {
            let w = match spectrum {
                Some(s) if p > 0.0 => p * wl.lambdas().iter().map(|&l| s.pdf(l)).sum::<f32>(),
                _ => 0.0,
            };
            out.prob.push(w);
            total += w;
            out.cdf.push(total);
        }
        if total > 0.0 {
            out.prob.iter_mut().for_each(|p| *p /= total);
            out.cdf.iter_mut().for_each(|c| *c /= total);
        }
    }
}

impl ClusterChoice {
    pub fn probability(&self, light: usize) -> f32 {
        self.prob.get(light).copied().unwrap_or(0.0)
    }

    /// A light and its probability; `None` when no light emits at the
    /// cluster's wavelengths.
    pub fn sample(&self, u: f32) -> Option<(usize, f32)> {
        let i = self.cdf.partition_point(|&c| c <= u);
        let i = (i..self.prob.len()).find(|&i| self.prob[i] > 0.0)?;
        Some((i, self.prob[i]))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::light::{Light, PointLight, SceneExtent};
    use crate::math::Vec3;
    use scotopia_color::spectrum::Tabulated;
    use scotopia_color::Spectrum;

    /// A lamp emitting only between `lo` and `hi` nm, flat there.
    fn band(lo: f32, hi: f32, at: f32) -> Light {
        let t = Tabulated::new(vec![lo, hi], vec![1.0, 1.0]).unwrap();
        Light::Point(PointLight {
            position: Vec3::new(at, 0.0, 0.0),
            intensity: Spectrum::tabulated(t),
        })
    }

    #[test]
    fn a_cluster_chooses_the_lights_that_emit_at_its_wavelengths_by_their_posterior() {
        // A blue and a red lamp (power 1 and 3), and one emitting in both
        // ranges (power 2, half its density in each).
        let lights = vec![band(400.0, 500.0, 0.0), band(600.0, 700.0, 1.0), {
            let t = Tabulated::new(
                vec![400.0, 500.0, 500.1, 599.9, 600.0, 700.0],
                vec![1.0, 1.0, 0.0, 0.0, 1.0, 1.0],
            )
            .unwrap();
            Light::Point(PointLight {
                position: Vec3::new(2.0, 0.0, 0.0),
                intensity: Spectrum::tabulated(t),
            })
        }];
        let extent = SceneExtent {
            shapes: &[],
            center: Vec3::ZERO,
            radius: 10.0,
            casters: &[],
        };
        let choice = LightChoice::new(&lights, &[1.0, 3.0, 2.0], &extent);
        let mut c = ClusterChoice::default();
        // Two blue wavelengths: the red lamp cannot have drawn them; the
        // blue one has density 1/100 nm at each, the broad one 1/200 nm.
        let wl = SampledWavelengths::new([450.0, 480.0], [0.01, 0.01]);
        choice.for_cluster(&wl, &mut c);
        let p: Vec<f32> = (0..3).map(|i| c.probability(i)).collect();
        // Posterior ∝ P(l)·Σ p_l(λ): 1/6·0.02, 0, 2/6·0.01 → 1/2, 0, 1/2.
        assert!((p[0] - 0.5).abs() < 2e-3 && p[1] == 0.0, "{p:?}");
        assert!((p[2] - 0.5).abs() < 2e-3, "{p:?}");
        // Sampling returns each light with the probability it reports.
        let n = 10_000;
        let mut counts = [0usize; 3];
        for k in 0..n {
            let (i, q) = c.sample((k as f32 + 0.5) / n as f32).unwrap();
            assert_eq!(q, c.probability(i));
            counts[i] += 1;
        }
        for i in 0..3 {
            assert!(
                (counts[i] as f32 - p[i] * n as f32).abs() <= 2.0,
                "{counts:?}"
            );
        }
        // No lamp emits at 550 nm: no light at all.
        let green = SampledWavelengths::new([550.0, 560.0], [0.01, 0.01]);
        choice.for_cluster(&green, &mut c);
        assert_eq!(c.sample(0.5), None);
    }
}

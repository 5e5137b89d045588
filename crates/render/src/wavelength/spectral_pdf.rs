//! A density over wavelength proportional to a spectrum: piecewise linear
//! between the spectrum's integration nodes (the 1 nm grid merged with its
//! own samples, so a 0.2 nm emission line keeps its shape), sampled by
//! inverting its CDF exactly.

use scotopia_color::photometry::integration_nodes;
use scotopia_color::Spectrum;

#[derive(Debug, Clone, PartialEq)]
pub struct SpectralPdf {
    nodes: Vec<f32>,
    values: Vec<f32>,
    /// cdf[i] = ∫ from nodes[0] to nodes[i], unnormalised.
    cdf: Vec<f64>,
}

impl SpectralPdf {
    /// `None` when the spectrum has no positive value in 360–830 nm.
    pub fn new(s: &Spectrum) -> Option<Self> {
        let nodes = integration_nodes(s);
        let values: Vec<f32> = nodes
            .iter()
            .map(|&l| {
                let v = s.eval(l);
                if v.is_finite() {
                    v.max(0.0)
                } else {
                    0.0
                }
            })
            .collect();
        let mut cdf = Vec::with_capacity(nodes.len());
        let mut sum = 0.0f64;
        cdf.push(0.0);
        for i in 1..nodes.len() {
            sum += 0.5 * (values[i - 1] + values[i]) as f64 * (nodes[i] - nodes[i - 1]) as f64;
            cdf.push(sum);
        }
        (sum > 0.0).then_some(Self { nodes, values, cdf })
    }

    fn total(&self) -> f64 {
        self.cdf[self.cdf.len() - 1]
    }

    /// Density at `lambda` (per nm).
    pub fn pdf(&self, lambda: f32) -> f32 {
        let n = &self.nodes;
        if !(n[0]..=n[n.len() - 1]).contains(&lambda) {
            return 0.0;
        }
        let i = n.partition_point(|&x| x <= lambda).clamp(1, n.len() - 1);
        let t = (lambda - n[i - 1]) / (n[i] - n[i - 1]);
        let v = self.values[i - 1] * (1.0 - t) + self.values[i] * t;
        (v as f64 / self.total()) as f32
    }

    /// A wavelength distributed by the density, for u ∈ [0, 1).
    pub fn sample(&self, u: f32) -> f32 {
        let target = u.clamp(0.0, 1.0) as f64 * self.total();
        let i = self
            .cdf
            .partition_point(|&c| c <= target)
            .clamp(1, self.cdf.len() - 1);
        let (a, b) = (self.nodes[i - 1], self.nodes[i]);
        let (v0, v1) = (self.values[i - 1] as f64, self.values[i] as f64);
        let mass = self.cdf[i] - self.cdf[i - 1];
        if mass <= 0.0 {
            return a;
        }
        // Within the interval the density is linear: solve its CDF for t,
        // in the form that stays stable when v0 ≈ v1.
        let w = (target - self.cdf[i - 1]) / mass;
        let root = (v0 * v0 + w * (v1 * v1 - v0 * v0)).max(0.0).sqrt();
        let t = if v0 + root > 0.0 {
            w * (v0 + v1) / (v0 + root)
        } else {
            w
        };
        a + (b - a) * t.clamp(0.0, 1.0) as f32
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use scotopia_color::Tabulated;

    #[test]
    fn samples_follow_the_density() {
        // A ramp with a narrow line: the histogram of samples matches pdf.
        let s = Spectrum::tabulated(
            Tabulated::new(
                vec![400.0, 588.9, 589.0, 589.1, 700.0],
                vec![0.1, 0.1, 50.0, 0.1, 1.0],
            )
            .unwrap(),
        );
        let p = SpectralPdf::new(&s).unwrap();
        let n = 200_000;
        let bins = [
            (400.0, 500.0),
            (500.0, 588.5),
            (588.8, 589.2),
            (600.0, 700.0),
        ];
        let mut counts = [0usize; 4];
        for i in 0..n {
            let l = p.sample((i as f32 + 0.5) / n as f32);
            for (k, (a, b)) in bins.iter().enumerate() {
                if (*a..*b).contains(&l) {
                    counts[k] += 1;
                }
            }
        }
        for (k, (a, b)) in bins.iter().enumerate() {
            let m = 20_000;
            let expected: f64 = (0..m)
                .map(|j| {
                    let l = a + (b - a) * (j as f32 + 0.5) / m as f32;
                    p.pdf(l) as f64 * (b - a) as f64 / m as f64
                })
                .sum();
            let got = counts[k] as f64 / n as f64;
            assert!(
                (got - expected).abs() < 1e-3,
                "bin {k}: {got} vs {expected}"
            );
        }
        assert!(SpectralPdf::new(&Spectrum::Constant(0.0)).is_none());
    }
}

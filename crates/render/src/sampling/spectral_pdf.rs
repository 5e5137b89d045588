//! A density over wavelength proportional to a spectrum: piecewise linear
//! between the spectrum's integration nodes (the 1 nm grid merged with its
//! own samples, so a 0.2 nm emission line keeps its shape), sampled by
//! inverting its CDF exactly. Both directions start from a guide table
//! (per nanometre for lookups, per CDF bucket for sampling), so a path's
//! wavelengths cost O(1) searches, not a bisection of ~500 nodes each.

use scotopia_color::photometry::integration_nodes;
use scotopia_color::{Spectrum, LAMBDA_MAX, LAMBDA_MIN};

use super::visible::visible_pdf;

#[derive(Debug, Clone, PartialEq)]
pub struct SpectralPdf {
    nodes: Vec<f32>,
    /// The density at each node (normalised, per nm).
    values: Vec<f32>,
    /// cdf[i] = ∫ from nodes[0] to nodes[i], normalised to end at 1.
    cdf: Vec<f64>,
    /// by_nm[j]: the interval holding nodes[0] + j nm.
    by_nm: Vec<u32>,
    /// by_mass[j]: the interval holding the CDF value j / by_mass.len().
    by_mass: Vec<u32>,
    /// ∫ of the function the density was made from (its normaliser).
    integral: f64,
}

/// Index of the interval [x[i], x[i + 1]] that holds `v` (x increasing,
/// at least two entries), searching only [lo, hi].
#[inline]
fn interval<T: PartialOrd + Copy>(x: &[T], v: T, lo: usize, hi: usize) -> usize {
    let hi = hi.min(x.len() - 2);
    let lo = lo.min(hi);
    lo + x[lo + 1..=hi].partition_point(|&c| c <= v)
}

impl SpectralPdf {
    /// `None` when the spectrum has no positive value in 360–830 nm.
    pub fn new(s: &Spectrum) -> Option<Self> {
        let nodes = integration_nodes(s);
        let values = nodes.iter().map(|&l| s.eval(l)).collect();
        Self::from_nodes(nodes, values)
    }

    /// A density proportional to `s` times the visible density
    /// ([`visible_pdf`]): where a lamp's light is seen. `None` as
    /// for [`Self::new`].
    pub fn seen(s: &Spectrum) -> Option<Self> {
        let nodes = integration_nodes(s);
        let values = nodes.iter().map(|&l| s.eval(l) * visible_pdf(l)).collect();
        Self::from_nodes(nodes, values)
    }

    /// The visible density ([`visible_pdf`]) on the 1 nm grid,
    /// linear between.
    pub fn visible() -> Self {
        let nodes: Vec<f32> = (LAMBDA_MIN as u32..=LAMBDA_MAX as u32)
            .map(|l| l as f32)
            .collect();
        let values = nodes.iter().map(|&l| visible_pdf(l)).collect();
        Self::from_nodes(nodes, values).expect("the visible density is positive")
    }

    /// The mixture Σ wᵢ·pᵢ of densities: piecewise linear on the union of
    /// their nodes, so it equals the mixture exactly. `None` when empty.
    pub fn mixture(parts: &[(f32, &SpectralPdf)]) -> Option<Self> {
        let mut nodes: Vec<f32> = parts.iter().flat_map(|(_, p)| p.nodes.clone()).collect();
        nodes.sort_by(f32::total_cmp);
        nodes.dedup();
        let values = nodes
            .iter()
            .map(|&l| parts.iter().map(|(w, p)| w * p.pdf(l)).sum())
            .collect();
        Self::from_nodes(nodes, values)
    }

    /// A density proportional to the piecewise-linear function through
    /// (nodes, values); negative or non-finite values count as zero.
    fn from_nodes(nodes: Vec<f32>, values: Vec<f32>) -> Option<Self> {
        if nodes.len() < 2 {
            return None;
        }
        let mut values: Vec<f32> = values
            .into_iter()
            .map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 })
            .collect();
        let mut cdf = Vec::with_capacity(nodes.len());
        let mut sum = 0.0f64;
        cdf.push(0.0);
        for i in 1..nodes.len() {
            sum += 0.5 * (values[i - 1] + values[i]) as f64 * (nodes[i] - nodes[i - 1]) as f64;
            cdf.push(sum);
        }
        if !(sum > 0.0 && sum.is_finite()) {
            return None;
        }
        cdf.iter_mut().for_each(|c| *c /= sum);
        values
            .iter_mut()
            .for_each(|v| *v = (*v as f64 / sum) as f32);
        let last = nodes.len() - 1;
        let span = (nodes[last] - nodes[0]).ceil() as usize;
        let by_nm = (0..=span)
            .map(|j| interval(&nodes, nodes[0] + j as f32, 0, last) as u32)
            .collect();
        let buckets = nodes.len();
        let by_mass = (0..=buckets)
            .map(|j| interval(&cdf, j as f64 / buckets as f64, 0, last) as u32)
            .collect();
        Some(Self {
            nodes,
            values,
            cdf,
            by_nm,
            by_mass,
            integral: sum,
        })
    }

    /// The integral of the function this density normalises (nm × its
    /// unit): the function is pdf(λ)·integral().
    pub fn integral(&self) -> f64 {
        self.integral
    }

    /// The node interval i holding `lambda` (within the nodes' span) and
    /// the density there, linear between nodes i and i + 1.
    #[inline]
    fn locate(&self, lambda: f32) -> (usize, f32) {
        let n = &self.nodes;
        let j = ((lambda - n[0]) as usize).min(self.by_nm.len() - 2);
        let i = interval(
            n,
            lambda,
            self.by_nm[j] as usize,
            self.by_nm[j + 1] as usize,
        );
        let t = ((lambda - n[i]) / (n[i + 1] - n[i])).clamp(0.0, 1.0);
        (i, self.values[i] * (1.0 - t) + self.values[i + 1] * t)
    }

    /// Density at `lambda` (per nm).
    #[inline]
    pub fn pdf(&self, lambda: f32) -> f32 {
        let n = &self.nodes;
        if !(n[0]..=n[n.len() - 1]).contains(&lambda) {
            return 0.0;
        }
        self.locate(lambda).1
    }

    /// A wavelength distributed by the density, for u ∈ [0, 1).
    #[inline]
    pub fn sample(&self, u: f32) -> f32 {
        self.sample_mass(u.clamp(0.0, 1.0) as f64)
    }

    /// The probability mass below `lambda` (the CDF).
    pub fn mass_below(&self, lambda: f32) -> f64 {
        let n = &self.nodes;
        if lambda <= n[0] {
            return 0.0;
        }
        if lambda >= n[n.len() - 1] {
            return 1.0;
        }
        let (i, v) = self.locate(lambda);
        // The density is linear on [n[i], λ]: a trapezoid.
        let v0 = self.values[i];
        self.cdf[i] + 0.5 * (v0 + v) as f64 * (lambda - n[i]) as f64
    }

    /// A wavelength distributed by the density restricted to wavelengths
    /// below `upper`, for u ∈ [0, 1); its density there is
    /// pdf(λ) / mass_below(upper).
    #[inline]
    pub fn sample_below(&self, u: f32, upper: f32) -> f32 {
        let sampled = self.sample_mass(u.clamp(0.0, 1.0) as f64 * self.mass_below(upper));
        sampled.min(upper)
    }

    /// The wavelengths where the density's slope may change.
    pub fn nodes(&self) -> &[f32] {
        &self.nodes
    }

    /// The wavelengths the density lives on, [first node, last node].
    pub fn support(&self) -> (f32, f32) {
        (self.nodes[0], self.nodes[self.nodes.len() - 1])
    }

    /// The wavelength where the CDF reaches `target` (clamped to [0, 1]),
    /// inverted exactly in f64: what a tabulated inverse CDF is built
    /// from, where the widths between quantiles must not be rounded to
    /// the f32 steps of λ (6·10⁻⁵ nm at 589 nm, a fifth of a cell inside
    /// a sodium line).
    pub fn quantile(&self, target: f64) -> f64 {
        let target = target.clamp(0.0, 1.0);
        let i = self.interval_of_mass(target);
        let (a, b) = (self.nodes[i] as f64, self.nodes[i + 1] as f64);
        let (v0, v1) = (self.values[i] as f64, self.values[i + 1] as f64);
        let mass = self.cdf[i + 1] - self.cdf[i];
        if mass <= 0.0 {
            return a;
        }
        // As in `sample_mass`.
        let w = ((target - self.cdf[i]) / mass).clamp(0.0, 1.0);
        let root = (v0 * v0 + w * (v1 * v1 - v0 * v0)).max(0.0).sqrt();
        let t = if v0 + root > 0.0 {
            w * (v0 + v1) / (v0 + root)
        } else {
            w
        };
        a + (b - a) * t.clamp(0.0, 1.0)
    }

    /// The node interval where the CDF reaches `target` ∈ [0, 1].
    #[inline]
    fn interval_of_mass(&self, target: f64) -> usize {
        let buckets = self.by_mass.len() - 1;
        let j = ((target * buckets as f64) as usize).min(buckets - 1);
        interval(
            &self.cdf,
            target,
            self.by_mass[j] as usize,
            self.by_mass[j + 1] as usize,
        )
    }

    /// The wavelength where the CDF reaches `target` ∈ [0, 1].
    #[inline]
    fn sample_mass(&self, target: f64) -> f32 {
        let i = self.interval_of_mass(target);
        let (a, b) = (self.nodes[i], self.nodes[i + 1]);
        let (v0, v1) = (self.values[i], self.values[i + 1]);
        let mass = self.cdf[i + 1] - self.cdf[i];
        if mass <= 0.0 {
            return a;
        }
        // Within the interval the density is linear: solve its CDF for t,
        // in the form that stays stable when v0 ≈ v1. (f32 suffices from
        // here: w is a fraction of one interval's mass.)
        let w = ((target - self.cdf[i]) / mass).clamp(0.0, 1.0) as f32;
        let root = (v0 * v0 + w * (v1 * v1 - v0 * v0)).max(0.0).sqrt();
        let t = if v0 + root > 0.0 {
            w * (v0 + v1) / (v0 + root)
        } else {
            w
        };
        a + (b - a) * t.clamp(0.0, 1.0)
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

    #[test]
    fn restricted_sampling_stays_below_and_follows_the_density() {
        let s = Spectrum::tabulated(
            Tabulated::new(vec![360.0, 400.0, 450.0, 600.0], vec![1.0, 3.0, 0.5, 2.0]).unwrap(),
        );
        let p = SpectralPdf::new(&s).unwrap();
        assert_eq!(p.mass_below(300.0), 0.0);
        assert!((p.mass_below(900.0) - 1.0).abs() < 1e-12);
        // The mass below 420 nm equals the integral of the density.
        let m = 100_000;
        let direct: f64 = (0..m)
            .map(|j| p.pdf(360.0 + 60.0 * (j as f32 + 0.5) / m as f32) as f64 * 60.0 / m as f64)
            .sum();
        assert!((p.mass_below(420.0) - direct).abs() < 1e-5, "{direct}");
        // Samples below 420 nm: all below, with the mean of the restricted
        // density.
        let n = 100_000;
        let samples: Vec<f32> = (0..n)
            .map(|i| p.sample_below((i as f32 + 0.5) / n as f32, 420.0))
            .collect();
        assert!(samples.iter().all(|&l| (360.0..=420.0).contains(&l)));
        let mean = samples.iter().map(|&l| l as f64).sum::<f64>() / n as f64;
        let want: f64 = (0..m)
            .map(|j| {
                let l = 360.0 + 60.0 * (j as f32 + 0.5) / m as f32;
                l as f64 * p.pdf(l) as f64 * 60.0 / m as f64
            })
            .sum::<f64>()
            / direct;
        assert!((mean - want).abs() < 0.01, "{mean} vs {want}");
    }

    /// The guided lookups agree with the spectrum itself, normalised by
    /// a plain trapezoid sum, and a mixture with its weighted sum.
    #[test]
    fn guided_lookups_match_the_spectrum_and_mixtures_their_parts() {
        let line = Spectrum::tabulated(
            Tabulated::new(
                vec![500.0, 501.0, 589.0, 589.2, 600.0, 600.5],
                vec![0.0, 0.2, 0.2, 80.0, 1.0, 0.0],
            )
            .unwrap(),
        );
        let smooth = Spectrum::blackbody(2700.0).unwrap();
        let (a, b) = (
            SpectralPdf::new(&line).unwrap(),
            SpectralPdf::new(&smooth).unwrap(),
        );
        let total = |s: &Spectrum| {
            let n = integration_nodes(s);
            n.windows(2)
                .map(|w| 0.5 * (s.eval(w[0]) + s.eval(w[1])) as f64 * (w[1] - w[0]) as f64)
                .sum::<f64>()
        };
        let (ta, tb) = (total(&line), total(&smooth));
        let mix = SpectralPdf::mixture(&[(0.25, &a), (0.75, &b)]).unwrap();
        for i in 0..=47_000 {
            let l = 360.0 + i as f32 * 0.01;
            let (pa, pb) = (a.pdf(l), b.pdf(l));
            // The spectrum reads a 0.1 nm resampling of its table, within
            // 10⁻⁴ of its peak (80) of the table's own function.
            let resampled = scotopia_color::spectrum::RESAMPLE_TOLERANCE as f64 * 80.0 / ta;
            assert!(
                (pa as f64 - line.eval(l) as f64 / ta).abs() < 1e-6 * (1.0 + pa as f64) + resampled,
                "{l}"
            );
            assert!(
                (pb as f64 - smooth.eval(l) as f64 / tb).abs() < 1e-4 * pb as f64,
                "{l}"
            );
            let m = 0.25 * pa + 0.75 * pb;
            assert!(
                (mix.pdf(l) - m).abs() <= 1e-5 * m + 1e-9,
                "{l}: {} vs {m}",
                mix.pdf(l)
            );
        }
        // Sampling inverts the CDF: u = ∫ pdf up to sample(u).
        for k in 1..200 {
            let u = k as f32 / 200.0;
            let l = a.sample(u);
            let m = 20_000;
            let cdf: f64 = (0..m)
                .map(|j| {
                    let x = 360.0 + (l - 360.0) * (j as f32 + 0.5) / m as f32;
                    a.pdf(x) as f64 * (l - 360.0) as f64 / m as f64
                })
                .sum();
            assert!((cdf - u as f64).abs() < 2e-3, "u {u}: cdf {cdf} at {l}");
        }
    }
}

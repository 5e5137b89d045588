//! Piecewise-constant distributions in one and two dimensions, sampled by
//! inverting their CDFs (pbrt's Distribution1D/2D, Pharr et al. 2016,
//! §13.6.7): choosing a triangle by area, a texel of an environment map by
//! its power.

/// A non-negative function on n equal bins of [0, 1).
#[derive(Debug, Clone, PartialEq)]
pub struct Distribution1D {
    func: Vec<f32>,
    /// cdf[i] = Σ_{j<i} func[j] / Σ func, with cdf[n] = 1.
    cdf: Vec<f32>,
    /// Σ func (the integral times n).
    sum: f64,
}

impl Distribution1D {
    /// Negative and non-finite values count as zero.
    pub fn new(func: Vec<f32>) -> Self {
        let func: Vec<f32> = func
            .into_iter()
            .map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 })
            .collect();
        let mut cdf = Vec::with_capacity(func.len() + 1);
        let mut sum = 0.0f64;
        cdf.push(0.0);
        for &f in &func {
            sum += f as f64;
            cdf.push(sum as f32);
        }
        if sum > 0.0 {
            for c in &mut cdf {
                *c = (*c as f64 / sum) as f32;
            }
        }
        if let Some(last) = cdf.last_mut() {
            *last = 1.0;
        }
        Self { func, cdf, sum }
    }

    pub fn len(&self) -> usize {
        self.func.len()
    }

    pub fn is_empty(&self) -> bool {
        self.func.is_empty()
    }

    /// Σ of the bin values.
    pub fn sum(&self) -> f64 {
        self.sum
    }

    /// Probability of bin `i`.
    pub fn probability(&self, i: usize) -> f32 {
        if self.sum > 0.0 {
            (self.func[i] as f64 / self.sum) as f32
        } else {
            0.0
        }
    }

    /// The bin whose CDF interval holds `u`, its probability, and `u`
    /// rescaled into [0, 1) within it. `None` when all bins are zero.
    pub fn sample_discrete(&self, u: f32) -> Option<(usize, f32, f32)> {
        if self.sum <= 0.0 || self.func.is_empty() {
            return None;
        }
        // The last bin with cdf[i] ≤ u, skipping zero-width bins.
        let n = self.func.len();
        let mut i = self.cdf.partition_point(|&c| c <= u).clamp(1, n) - 1;
        while self.func[i] == 0.0 && i + 1 < n {
            i += 1;
        }
        while self.func[i] == 0.0 && i > 0 {
            i -= 1;
        }
        let (lo, hi) = (self.cdf[i], self.cdf[i + 1]);
        let rest = if hi > lo {
            ((u - lo) / (hi - lo)).clamp(0.0, 1.0 - f32::EPSILON)
        } else {
            0.5
        };
        Some((i, self.probability(i), rest))
    }

    /// A point x ∈ [0, 1) with density pdf(x) = n · func[i] / Σ func.
    pub fn sample_continuous(&self, u: f32) -> Option<(f32, f32, usize)> {
        let (i, p, rest) = self.sample_discrete(u)?;
        let n = self.func.len() as f32;
        Some((((i as f32 + rest) / n).min(1.0 - f32::EPSILON), p * n, i))
    }

    /// Density of `sample_continuous` at x ∈ [0, 1).
    pub fn pdf(&self, x: f32) -> f32 {
        if self.func.is_empty() {
            return 0.0;
        }
        let n = self.func.len();
        let i = ((x * n as f32) as usize).min(n - 1);
        self.probability(i) * n as f32
    }
}

/// A non-negative function on a grid of w × h equal cells of [0, 1)²,
/// sampled row (v) first, then column (u) within the row.
#[derive(Debug, Clone, PartialEq)]
pub struct Distribution2D {
    rows: Vec<Distribution1D>,
    marginal: Distribution1D,
}

impl Distribution2D {
    /// `func` row-major, `width` values per row.
    pub fn new(func: &[f32], width: usize) -> Self {
        let rows: Vec<Distribution1D> = func
            .chunks(width.max(1))
            .map(|row| Distribution1D::new(row.to_vec()))
            .collect();
        let marginal = Distribution1D::new(rows.iter().map(|r| r.sum() as f32).collect());
        Self { rows, marginal }
    }

    /// (u, v) ∈ [0, 1)² and its density; `None` when the function is zero.
    pub fn sample(&self, u: [f32; 2]) -> Option<([f32; 2], f32)> {
        let (v, pdf_v, row) = self.marginal.sample_continuous(u[1])?;
        let (x, pdf_u, _) = self.rows[row].sample_continuous(u[0])?;
        Some(([x, v], pdf_v * pdf_u))
    }

    /// Density of `sample` at (u, v).
    pub fn pdf(&self, [u, v]: [f32; 2]) -> f32 {
        let h = self.rows.len();
        if h == 0 {
            return 0.0;
        }
        let row = ((v * h as f32) as usize).min(h - 1);
        self.marginal.pdf(v) * self.rows[row].pdf(u)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn discrete_sampling_follows_the_weights() {
        let d = Distribution1D::new(vec![1.0, 0.0, 3.0]);
        assert_eq!(d.sample_discrete(0.1).unwrap().0, 0);
        // u on the boundary of the empty bin never selects it.
        assert_eq!(d.sample_discrete(0.25).unwrap().0, 2);
        let (i, p, rest) = d.sample_discrete(0.625).unwrap();
        assert_eq!((i, p), (2, 0.75));
        assert!((rest - 0.5).abs() < 1e-6);
        assert!(Distribution1D::new(vec![0.0, 0.0])
            .sample_discrete(0.5)
            .is_none());
        assert!(Distribution1D::new(vec![]).sample_discrete(0.5).is_none());
    }

    #[test]
    fn continuous_pdf_matches_sampling() {
        let d = Distribution1D::new(vec![1.0, 0.0, 3.0, f32::NAN]);
        let (x, pdf, _) = d.sample_continuous(0.9).unwrap();
        assert!((0.5..0.75).contains(&x));
        assert_eq!(pdf, d.pdf(x));
        assert_eq!(pdf, 3.0);
        assert_eq!(d.pdf(0.3), 0.0);
    }

    #[test]
    fn two_dimensional_density_integrates_to_one() {
        let f = [0.0, 1.0, 2.0, 3.0, 4.0, 5.0];
        let d = Distribution2D::new(&f, 3);
        let mut total = 0.0;
        for j in 0..2 {
            for i in 0..3 {
                let p = d.pdf([(i as f32 + 0.5) / 3.0, (j as f32 + 0.5) / 2.0]);
                assert!((p - f[j * 3 + i] / 15.0 * 6.0).abs() < 1e-5);
                total += p / 6.0;
            }
        }
        assert!((total - 1.0).abs() < 1e-5);
        let (uv, p) = d.sample([0.999, 0.999]).unwrap();
        assert!(uv[0] >= 2.0 / 3.0 && uv[1] >= 0.5);
        assert_eq!(p, d.pdf(uv));
    }
}

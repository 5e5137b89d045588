//! A spectrum tabulated at increasing wavelengths, linearly interpolated
//! between them and zero outside them (as Mitsuba's irregular spectrum).

use crate::error::ColorError;

/// Piecewise-linear spectrum at any (strictly increasing) spacing.
#[derive(Debug, Clone, PartialEq)]
pub struct Tabulated {
    lambda: Vec<f32>,
    value: Vec<f32>,
    /// `(first wavelength, 1 / step)` when the spacing is uniform: lookups
    /// then index directly instead of searching.
    uniform: Option<(f32, f32)>,
}

impl Tabulated {
    /// Builds a tabulated spectrum. Wavelengths must be finite and strictly
    /// increasing, values finite, at least one sample.
    pub fn new(lambda: Vec<f32>, value: Vec<f32>) -> Result<Self, ColorError> {
        let bad = |m: String| Err(ColorError::InvalidSpectrum(m));
        if lambda.len() != value.len() {
            return bad(format!(
                "{} wavelengths but {} values",
                lambda.len(),
                value.len()
            ));
        }
        if lambda.is_empty() {
            return bad("no samples".into());
        }
        if let Some(i) = lambda
            .windows(2)
            .position(|w| w[1] <= w[0] || !w[1].is_finite())
        {
            return bad(format!("wavelengths not increasing at index {}", i + 1));
        }
        if let Some(i) = value.iter().position(|v| !v.is_finite()) {
            return bad(format!("value at {} nm is not finite", lambda[i]));
        }
        let uniform = Self::uniform_spacing(&lambda);
        Ok(Self {
            lambda,
            value,
            uniform,
        })
    }

    /// Samples `f` at `start, start + step, …, end` (inclusive).
    pub fn from_fn(start: f32, end: f32, step: f32, f: impl Fn(f32) -> f32) -> Self {
        let n = ((end - start) / step).round() as usize + 1;
        let lambda: Vec<f32> = (0..n).map(|i| start + step * i as f32).collect();
        let value = lambda.iter().map(|&l| f(l)).collect();
        Self {
            uniform: Self::uniform_spacing(&lambda),
            lambda,
            value,
        }
    }

    fn uniform_spacing(lambda: &[f32]) -> Option<(f32, f32)> {
        if lambda.len() < 2 {
            return None;
        }
        let step = (lambda[lambda.len() - 1] - lambda[0]) / (lambda.len() - 1) as f32;
        let uniform = lambda
            .iter()
            .enumerate()
            .all(|(i, &l)| (l - (lambda[0] + step * i as f32)).abs() <= 1e-4 * step);
        uniform.then_some((lambda[0], 1.0 / step))
    }

    /// The tabulated wavelengths, nm.
    pub fn wavelengths(&self) -> &[f32] {
        &self.lambda
    }

    /// The tabulated values.
    pub fn values(&self) -> &[f32] {
        &self.value
    }

    /// Value at `lambda` nm: linear between samples, zero outside them.
    #[inline]
    pub fn eval(&self, lambda: f32) -> f32 {
        let n = self.lambda.len();
        if !(lambda >= self.lambda[0] && lambda <= self.lambda[n - 1]) {
            return 0.0;
        }
        if n == 1 {
            return self.value[0];
        }
        // Find the segment [i, i + 1] that holds lambda, and the position in it.
        let (i, t) = match self.uniform {
            Some((start, inv_step)) => {
                let x = (lambda - start) * inv_step;
                let i = (x as usize).min(n - 2);
                (i, (x - i as f32).min(1.0))
            }
            None => {
                let i = self
                    .lambda
                    .partition_point(|&l| l <= lambda)
                    .clamp(1, n - 1)
                    - 1;
                let (l0, l1) = (self.lambda[i], self.lambda[i + 1]);
                (i, ((lambda - l0) / (l1 - l0)).clamp(0.0, 1.0))
            }
        };
        self.value[i] + t * (self.value[i + 1] - self.value[i])
    }

    /// Largest tabulated value.
    pub fn max_value(&self) -> f32 {
        self.value.iter().copied().fold(f32::MIN, f32::max)
    }

    /// Smallest tabulated value.
    pub fn min_value(&self) -> f32 {
        self.value.iter().copied().fold(f32::MAX, f32::min)
    }

    /// The same spectrum with every value multiplied by `s`.
    pub fn scaled(&self, s: f32) -> Self {
        Self {
            value: self.value.iter().map(|v| v * s).collect(),
            ..self.clone()
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn interpolates_and_is_zero_outside() {
        let s = Tabulated::new(vec![400.0, 410.0, 430.0], vec![1.0, 3.0, 1.0]).unwrap();
        assert!(s.uniform.is_none());
        assert_eq!(s.eval(399.9), 0.0);
        assert_eq!(s.eval(400.0), 1.0);
        assert_eq!(s.eval(405.0), 2.0);
        assert_eq!(s.eval(420.0), 2.0);
        assert_eq!(s.eval(430.0), 1.0);
        assert_eq!(s.eval(430.1), 0.0);
        assert_eq!(s.eval(f32::NAN), 0.0);
    }

    #[test]
    fn uniform_lookup_matches_search() {
        let u = Tabulated::from_fn(360.0, 830.0, 5.0, |l| (l * 0.05).sin() + 1.0);
        assert!(u.uniform.is_some());
        let searched = Tabulated {
            uniform: None,
            ..u.clone()
        };
        for i in 0..=4700 {
            let l = 360.0 + i as f32 * 0.1;
            // Both are exact up to f32 rounding of the position in the segment.
            assert!((u.eval(l) - searched.eval(l)).abs() < 1e-5, "at {l}");
        }
    }

    #[test]
    fn rejects_bad_tables() {
        assert!(Tabulated::new(vec![], vec![]).is_err());
        assert!(Tabulated::new(vec![400.0, 400.0], vec![1.0, 1.0]).is_err());
        assert!(Tabulated::new(vec![400.0], vec![1.0, 1.0]).is_err());
        assert!(Tabulated::new(vec![400.0, 500.0], vec![1.0, f32::NAN]).is_err());
    }
}

//! A spectrum tabulated at increasing wavelengths, linearly interpolated
//! between them and zero outside them (as Mitsuba's irregular spectrum).

use super::lookup::Lookup;
use crate::error::ColorError;

/// Piecewise-linear spectrum at any (strictly increasing) spacing.
#[derive(Debug, Clone, PartialEq)]
pub struct Tabulated {
    lambda: Vec<f32>,
    value: Vec<f32>,
    /// How `eval` finds a wavelength's segment: a uniform grid (the
    /// table's own, or the table resampled within 10⁻⁴ of its largest
    /// value), or a guide into the samples (see [`super::lookup`]).
    lookup: Lookup,
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
        let lookup = Lookup::new(&lambda, &value);
        Ok(Self {
            lambda,
            value,
            lookup,
        })
    }

    /// Samples `f` at `start, start + step, …, end` (inclusive).
    pub fn from_fn(start: f32, end: f32, step: f32, f: impl Fn(f32) -> f32) -> Self {
        let n = ((end - start) / step).round() as usize + 1;
        let lambda: Vec<f32> = (0..n).map(|i| start + step * i as f32).collect();
        let value: Vec<f32> = lambda.iter().map(|&l| f(l)).collect();
        Self {
            lookup: Lookup::new(&lambda, &value),
            lambda,
            value,
        }
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
        self.lookup.eval(&self.lambda, &self.value, lambda)
    }

    /// Values at the K wavelengths of a cluster.
    #[inline]
    pub fn eval_cluster<const K: usize>(&self, lambda: &[f32; K]) -> [f32; K] {
        self.lookup.eval_cluster(&self.lambda, &self.value, lambda)
    }

    /// Whether `eval` reads a uniform grid (the table's own or its
    /// resampling), rather than searching the samples.
    pub fn is_gridded(&self) -> bool {
        self.lookup.is_grid()
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
            lambda: self.lambda.clone(),
            value: self.value.iter().map(|v| v * s).collect(),
            lookup: self.lookup.scaled(s),
        }
    }
}

#[cfg(test)]
impl Tabulated {
    pub(super) fn lookup_for_tests(&self) -> &Lookup {
        &self.lookup
    }

    /// The same table kept and read through a guide: its own function,
    /// up to f32 rounding.
    pub(super) fn searched_for_tests(&self) -> Self {
        let n = self.lambda.len();
        Self {
            lookup: Lookup::guided(&self.lambda, &self.value, n.max(2) - 1),
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
        // Resampled to a 10 nm grid, exactly.
        assert!(s.is_gridded());
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
        assert!(u.is_gridded());
        for i in 0..=4700 {
            let l = 360.0 + i as f32 * 0.1;
            // Both are exact up to f32 rounding of the position in the segment.
            let searched = super::super::lookup::searched(u.wavelengths(), u.values(), l);
            assert!((u.eval(l) - searched).abs() < 1e-5, "at {l}");
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

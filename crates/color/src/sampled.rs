//! A cluster of K wavelengths travelling together along one path, and a
//! spectrum's values on it. K is a const generic (default 4) so clusters live
//! on the stack and loops over them unroll.

use std::ops::{
    Add, AddAssign, Div, DivAssign, Index, IndexMut, Mul, MulAssign, Neg, Sub, SubAssign,
};

use crate::{LAMBDA_MAX, LAMBDA_MIN};

/// K wavelengths (nm) and the probability density each was drawn with. A
/// density of zero marks a wavelength that no longer contributes (after a
/// dispersive event collapsed the cluster).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampledWavelengths<const K: usize = 4> {
    lambda: [f32; K],
    pdf: [f32; K],
}

impl<const K: usize> SampledWavelengths<K> {
    /// A cluster with explicit wavelengths and densities (per nm).
    pub fn new(lambda: [f32; K], pdf: [f32; K]) -> Self {
        Self { lambda, pdf }
    }

    /// Stratified uniform cluster over 360–830 nm: one jitter `u ∈ [0, 1)`
    /// shared by K equal strata, so the K wavelengths are evenly spread.
    pub fn sample_uniform(u: f32) -> Self {
        let range = LAMBDA_MAX - LAMBDA_MIN;
        let lambda = std::array::from_fn(|i| LAMBDA_MIN + range * ((i as f32 + u) / K as f32));
        Self {
            lambda,
            pdf: [1.0 / range; K],
        }
    }

    #[inline]
    pub fn lambdas(&self) -> &[f32; K] {
        &self.lambda
    }

    #[inline]
    pub fn pdfs(&self) -> &[f32; K] {
        &self.pdf
    }

    #[inline]
    pub fn lambda(&self, i: usize) -> f32 {
        self.lambda[i]
    }

    #[inline]
    pub fn pdf(&self, i: usize) -> f32 {
        self.pdf[i]
    }

    /// Moves member `i` to wavelength `lambda`, keeping its density: a
    /// fluorescent surface re-emits at the path's wavelength what it
    /// absorbed at `lambda`, so the path continues there while the
    /// estimate stays that of the wavelength it started with.
    #[inline]
    pub fn set_lambda(&mut self, i: usize, lambda: f32) {
        self.lambda[i] = lambda;
    }

    /// Rotates the cluster so member `first` comes first. Drawn uniformly at
    /// the start of a path, it makes the member a dispersive event keeps a
    /// uniform choice among the K, whose density is then the one stored,
    /// even when the members were drawn from different strata.
    pub fn rotate_to_front(&mut self, first: usize) {
        // Index arithmetic, not `rotate_left`: that is a memmove call per
        // array, at the start of every camera sample.
        let j = first % K.max(1);
        let (lambda, pdf) = (self.lambda, self.pdf);
        self.lambda = std::array::from_fn(|k| lambda[(k + j) % K]);
        self.pdf = std::array::from_fn(|k| pdf[(k + j) % K]);
    }

    /// Keeps only the first wavelength (a dispersive event). Its density is
    /// divided by K so the cluster-average estimator (1/K)·Σ f/p stays
    /// unbiased with one term left.
    pub fn terminate_secondary(&mut self) {
        if self.secondary_terminated() {
            return;
        }
        for p in self.pdf.iter_mut().skip(1) {
            *p = 0.0;
        }
        self.pdf[0] /= K as f32;
    }

    /// Whether the cluster has collapsed to its first wavelength.
    pub fn secondary_terminated(&self) -> bool {
        self.pdf.iter().skip(1).all(|&p| p == 0.0)
    }
}

/// A spectrum's values on the K wavelengths of a cluster.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SampledSpectrum<const K: usize = 4>(pub [f32; K]);

impl<const K: usize> SampledSpectrum<K> {
    #[inline]
    pub fn splat(v: f32) -> Self {
        Self([v; K])
    }

    #[inline]
    pub fn from_fn(f: impl FnMut(usize) -> f32) -> Self {
        Self(std::array::from_fn(f))
    }

    #[inline]
    pub fn is_zero(&self) -> bool {
        self.0.iter().all(|&v| v == 0.0)
    }

    #[inline]
    pub fn max_value(&self) -> f32 {
        self.0.iter().copied().fold(f32::MIN, f32::max)
    }

    #[inline]
    pub fn average(&self) -> f32 {
        self.0.iter().sum::<f32>() / K as f32
    }

    /// Element-wise division that yields 0 where the divisor is 0 (the
    /// estimator f/p for terminated wavelengths).
    #[inline]
    pub fn safe_div(&self, d: &Self) -> Self {
        Self::from_fn(|i| {
            if d.0[i] != 0.0 {
                self.0[i] / d.0[i]
            } else {
                0.0
            }
        })
    }

    /// Applies `f` to each value.
    #[inline]
    pub fn map(&self, f: impl Fn(f32) -> f32) -> Self {
        Self::from_fn(|i| f(self.0[i]))
    }
}

impl<const K: usize> Default for SampledSpectrum<K> {
    fn default() -> Self {
        Self::splat(0.0)
    }
}

impl<const K: usize> Index<usize> for SampledSpectrum<K> {
    type Output = f32;
    #[inline]
    fn index(&self, i: usize) -> &f32 {
        &self.0[i]
    }
}

impl<const K: usize> IndexMut<usize> for SampledSpectrum<K> {
    #[inline]
    fn index_mut(&mut self, i: usize) -> &mut f32 {
        &mut self.0[i]
    }
}

impl<const K: usize> Neg for SampledSpectrum<K> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        self.map(|v| -v)
    }
}

/// Element-wise arithmetic between two sampled spectra, and with a scalar.
macro_rules! elementwise {
    ($trait:ident, $method:ident, $assign_trait:ident, $assign_method:ident, $op:tt) => {
        impl<const K: usize> $trait for SampledSpectrum<K> {
            type Output = Self;
            #[inline]
            fn $method(self, rhs: Self) -> Self {
                Self::from_fn(|i| self.0[i] $op rhs.0[i])
            }
        }
        impl<const K: usize> $trait<f32> for SampledSpectrum<K> {
            type Output = Self;
            #[inline]
            fn $method(self, rhs: f32) -> Self {
                Self::from_fn(|i| self.0[i] $op rhs)
            }
        }
        impl<const K: usize> $assign_trait for SampledSpectrum<K> {
            #[inline]
            fn $assign_method(&mut self, rhs: Self) {
                *self = *self $op rhs;
            }
        }
        impl<const K: usize> $assign_trait<f32> for SampledSpectrum<K> {
            #[inline]
            fn $assign_method(&mut self, rhs: f32) {
                *self = *self $op rhs;
            }
        }
    };
}

elementwise!(Add, add, AddAssign, add_assign, +);
elementwise!(Sub, sub, SubAssign, sub_assign, -);
elementwise!(Mul, mul, MulAssign, mul_assign, *);
elementwise!(Div, div, DivAssign, div_assign, /);

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn uniform_cluster_is_stratified() {
        let wl = SampledWavelengths::<4>::sample_uniform(0.5);
        let width = (LAMBDA_MAX - LAMBDA_MIN) / 4.0;
        for i in 0..4 {
            let lo = LAMBDA_MIN + width * i as f32;
            assert!(wl.lambda(i) >= lo && wl.lambda(i) < lo + width);
            assert!((wl.pdf(i) * (LAMBDA_MAX - LAMBDA_MIN) - 1.0).abs() < 1e-6);
        }
    }

    #[test]
    fn terminating_secondary_keeps_the_estimate() {
        let mut wl = SampledWavelengths::<4>::sample_uniform(0.25);
        let p0 = wl.pdf(0);
        wl.terminate_secondary();
        assert!(wl.secondary_terminated());
        assert_eq!(wl.pdf(0), p0 / 4.0);
        wl.terminate_secondary();
        assert_eq!(wl.pdf(0), p0 / 4.0, "idempotent");
    }

    #[test]
    fn arithmetic() {
        let a = SampledSpectrum([1.0, 2.0, 3.0, 4.0]);
        let b = SampledSpectrum::splat(2.0);
        assert_eq!((a * b).0, [2.0, 4.0, 6.0, 8.0]);
        assert_eq!((a - 1.0).0, [0.0, 1.0, 2.0, 3.0]);
        assert_eq!(
            a.safe_div(&SampledSpectrum([1.0, 0.0, 3.0, 0.0])).0,
            [1.0, 0.0, 1.0, 0.0]
        );
        assert_eq!(a.average(), 2.5);
        let mut c = a;
        c += b;
        c /= 2.0;
        assert_eq!(c.0, [1.5, 2.0, 2.5, 3.0]);
    }
}

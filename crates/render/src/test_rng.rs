//! What the crate's unit tests share: one seeded generator (SplitMix64)
//! and the mean of a sample with its standard error.

use crate::math::Vec3;
use crate::sampling::splitmix::SplitMix;

/// SplitMix64 (Steele, Lea & Flood 2014), numbers in [0, 1).
pub(crate) struct Rng(pub(crate) u64);

impl Rng {
    pub(crate) fn next(&mut self) -> f32 {
        let mut g = SplitMix(self.0);
        let x = g.next_f32();
        self.0 = g.0;
        x
    }

    /// A point uniform in the box [lo, hi)³.
    pub(crate) fn vec(&mut self, lo: f32, hi: f32) -> Vec3 {
        Vec3::new(self.next(), self.next(), self.next()) * (hi - lo) + Vec3::splat(lo)
    }
}

/// The generator as a closure.
pub(crate) fn uniforms(seed: u64) -> impl FnMut() -> f32 {
    let mut rng = Rng(seed);
    move || rng.next()
}

/// Mean and standard error of the mean of `x`.
pub(crate) fn mean_and_se(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    let var = x.iter().map(|v| (v - m) * (v - m)).sum::<f64>() / (n - 1.0);
    (m, (var / n).sqrt())
}

/// Pearson's χ² of `observed` counts against `expected` ones (bins
/// expected fewer than 5 times pooled into one), and its z by the
/// Wilson–Hilferty cube-root transform: the upper tail probability is
/// below 1e-3 where z exceeds 3.0902 (the normal's 1 − 1e-3 quantile).
/// `None` with fewer than two bins. A bin expected 0 times must be empty.
pub(crate) fn chi2_z(expected: &[f64], observed: &[u64]) -> Option<(f64, f64, usize)> {
    let (mut chi2, mut bins) = (0.0f64, 0usize);
    let (mut pooled_e, mut pooled_o) = (0.0f64, 0.0f64);
    for (i, (&e, &o)) in expected.iter().zip(observed).enumerate() {
        if e == 0.0 {
            assert_eq!(o, 0, "bin {i} is expected empty but has {o}");
        } else if e < 5.0 {
            pooled_e += e;
            pooled_o += o as f64;
        } else {
            chi2 += (o as f64 - e).powi(2) / e;
            bins += 1;
        }
    }
    if pooled_e > 0.0 {
        chi2 += (pooled_o - pooled_e).powi(2) / pooled_e;
        bins += 1;
    }
    (bins > 1).then(|| {
        let k = (bins - 1) as f64;
        let v = 2.0 / (9.0 * k);
        (((chi2 / k).cbrt() - (1.0 - v)) / v.sqrt(), chi2, bins - 1)
    })
}

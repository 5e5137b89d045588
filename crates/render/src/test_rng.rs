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

//! The batch: the paths in flight, one [`Lane`] each, and what the stages
//! pass between them.

use scotopia_color::SampledSpectrum;

use super::super::path::PathState;
use crate::geometry::Hit;
use crate::math::Ray;
use crate::sampling::sobol::Sampler;
use crate::sampling::sobol_batch::sobol_sets;
use crate::simd::Level;

/// Paths in flight per batch: enough that each stage's loop amortises its
/// set-up, few enough that the batch (about 250 bytes a path at K = 4)
/// stays in the L2 cache.
pub const BATCH: usize = 1024;

/// One path in flight.
pub struct Lane<const K: usize> {
    pub path: PathState<K>,
    /// The path's own sampler: its numbers depend on (seed, pixel, sample
    /// index, dimension) only, not on the lane or the batch.
    pub sampler: Sampler,
    /// Where its estimate goes in the row's results.
    pub slot: u32,
    /// The intersect stage's result.
    pub hit: Option<Hit>,
    /// The next bounce's two 4-dimensional sets, drawn for the batch.
    pub u: [[f32; 4]; 2],
    /// The shade stage's shadow ray and what it carries if unoccluded.
    pub shadow: Option<(Ray, SampledSpectrum<K>)>,
    /// Whether the path goes on after this bounce.
    pub alive: bool,
}

/// Room for one number per lane of a batch, reused across iterations.
#[derive(Default)]
pub struct Scratch {
    pub lanes: Vec<u32>,
    pub keys: Vec<u32>,
    pub indices: Vec<u32>,
    pub xs: Vec<u32>,
    pub ys: Vec<u32>,
    pub sets: [Vec<f32>; 8],
}

impl Scratch {
    /// The number arrays sized for `n` lanes.
    pub fn resize(&mut self, n: usize) {
        for v in [
            &mut self.keys,
            &mut self.indices,
            &mut self.xs,
            &mut self.ys,
        ] {
            v.resize(n, 0);
        }
        for v in &mut self.sets {
            v.resize(n, 0.0);
        }
    }

    /// Two consecutive sets, `set` and `set + 1`, for the `n` lanes in
    /// `keys` and `indices` (bit-identical to each lane's own sampler).
    pub fn draw_sets(&mut self, level: Level, set: u32, n: usize) {
        let [a, b, c, d, e, f, g, h] = &mut self.sets;
        let (keys, indices) = (&self.keys[..n], &self.indices[..n]);
        sobol_sets(
            level,
            set,
            keys,
            indices,
            [&mut a[..n], &mut b[..n], &mut c[..n], &mut d[..n]],
        );
        sobol_sets(
            level,
            set + 1,
            keys,
            indices,
            [&mut e[..n], &mut f[..n], &mut g[..n], &mut h[..n]],
        );
    }

    /// Lane `k`'s two sets, as drawn by [`Self::draw_sets`].
    pub fn sets_of(&self, k: usize) -> [[f32; 4]; 2] {
        let s = &self.sets;
        [
            [s[0][k], s[1][k], s[2][k], s[3][k]],
            [s[4][k], s[5][k], s[6][k], s[7][k]],
        ]
    }
}

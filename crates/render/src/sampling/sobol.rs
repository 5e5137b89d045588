//! The sampler: Owen-scrambled Sobol points, padded in 4-dimensional sets,
//! after Burley 2020, "Practical Hash-based Owen Scrambling" (JCGT 9(4)).
//! Each set of 4 dimensions is the first 4 Sobol dimensions with its own
//! hash-based nested uniform (Owen) scramble, and its own shuffle of the
//! sample index, so sets are decorrelated. Every number depends only on
//! (seed, pixel, sample index, dimension): renders are identical on any
//! number of threads.
//!
//! The numbers themselves are `sobol_point`'s; a bounce's two sets are
//! drawn wide (`sobol_pair`).

pub use super::sobol_point::{hash, owen_scramble, pixel_key, set_point, sobol};

/// Random numbers for one sample of one pixel, drawn dimension by dimension.
#[derive(Debug, Clone)]
pub struct Sampler {
    seed: u32,
    /// Hash of (seed, pixel): the root of every scramble seed.
    pixel_key: u32,
    /// The sample index, bit-reversed.
    index_rev: u32,
    dimension: u32,
}

impl Sampler {
    pub fn new(seed: u32) -> Self {
        Self {
            seed,
            pixel_key: pixel_key(seed, [0, 0]),
            index_rev: 0,
            dimension: 0,
        }
    }

    /// Starts sample `index` of `pixel`, from dimension 0.
    pub fn start(&mut self, pixel: [u32; 2], index: u32) {
        self.pixel_key = pixel_key(self.seed, pixel);
        self.index_rev = index.reverse_bits();
        self.dimension = 0;
    }

    /// The key of the current pixel ([`pixel_key`]).
    pub fn pixel_key(&self) -> u32 {
        self.pixel_key
    }

    /// The current sample index.
    pub fn index(&self) -> u32 {
        self.index_rev.reverse_bits()
    }

    /// The sampler of sample `index` of the pixel with key `pixel_key`,
    /// about to draw set `set` (a batch drew the sets before it).
    pub fn resume(seed: u32, pixel_key: u32, index: u32, set: u32) -> Self {
        Self {
            seed,
            pixel_key,
            index_rev: index.reverse_bits(),
            dimension: set * 4,
        }
    }

    /// Moves on past `n` sets, drawn elsewhere (by a batch).
    pub fn skip_sets(&mut self, n: u32) {
        self.dimension = (self.dimension / 4 + n) * 4;
    }

    /// The 4-dimensional set the next draw uses: a batch
    /// ([`super::sobol_batch::sobol_sets`]) drawing it for this sample gives
    /// what this sampler would.
    pub fn next_set(&self) -> u32 {
        self.dimension / 4
    }

    /// The 4 coordinates of the current 4-dimensional set, then moves on.
    #[inline]
    fn set(&mut self) -> [f32; 4] {
        let set = self.dimension / 4;
        self.dimension = (set + 1) * 4;
        set_point(self.pixel_key, self.index_rev, set)
    }

    /// A generator for the numbers a sample needs beyond its sets (walks
    /// through heterogeneous media), seeded by the sample's pixel and index
    /// so that the image stays deterministic.
    pub fn stream(&self) -> super::splitmix::SplitMix {
        super::splitmix::SplitMix(((self.pixel_key as u64) << 32) | self.index() as u64)
    }

    /// One number in [0, 1) (uses a whole 4-dimensional set).
    pub fn get_1d(&mut self) -> f32 {
        self.set()[0]
    }

    /// Two numbers in [0, 1)² from one set, stratified jointly.
    pub fn get_2d(&mut self) -> [f32; 2] {
        let s = self.set();
        [s[0], s[1]]
    }

    /// Four numbers from one set (e.g. a 2D point and two choices).
    pub fn get_4d(&mut self) -> [f32; 4] {
        self.set()
    }

    /// The next two sets, `[get_4d(), get_4d()]` to the bit, drawn with
    /// the dimensions as SIMD lanes ([`super::sobol_pair`]): what a
    /// bounce takes.
    #[inline]
    pub fn get_two_4d(&mut self) -> [[f32; 4]; 2] {
        let set = self.dimension / 4;
        self.dimension = (set + 2) * 4;
        super::sobol_pair::set_pair(
            crate::simd::Level::current(),
            self.pixel_key,
            self.index_rev,
            set,
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sampling::sobol_batch::{pixel_keys, sobol_sets};
    use crate::simd::Level;

    #[test]
    fn deterministic_and_uniform() {
        let mut a = Sampler::new(5);
        let mut b = Sampler::new(5);
        a.start([3, 9], 17);
        b.start([3, 9], 17);
        assert_eq!(a.get_2d(), b.get_2d());
        assert_eq!(a.get_1d(), b.get_1d());
        // Mean and variance of many coordinates match U(0, 1).
        let (mut sum, mut sum2, mut n) = (0.0f64, 0.0f64, 0);
        for px in 0..16 {
            for i in 0..64 {
                a.start([px, 0], i);
                for _ in 0..6 {
                    for v in a.get_4d() {
                        assert!((0.0..1.0).contains(&v));
                        sum += v as f64;
                        sum2 += (v as f64).powi(2);
                        n += 1;
                    }
                }
            }
        }
        let mean = sum / n as f64;
        let var = sum2 / n as f64 - mean * mean;
        assert!(
            (mean - 0.5).abs() < 4.0 * (1.0 / 12.0 / n as f64).sqrt(),
            "{mean}"
        );
        assert!((var - 1.0 / 12.0).abs() < 5e-3, "{var}");
    }

    #[test]
    fn stratification_beats_random_on_a_smooth_integral() {
        // ∫∫ sin(πx) sin(πy) = 4/π²: 256 padded Sobol points per pixel
        // land far closer than the 1/√256 random error.
        let mut s = Sampler::new(1);
        let exact = 4.0 / std::f64::consts::PI.powi(2);
        let mut worst = 0.0f64;
        for px in 0..8 {
            let mut sum = 0.0;
            for i in 0..256 {
                s.start([px, 1], i);
                let [x, y] = s.get_2d();
                sum += ((std::f64::consts::PI * x as f64).sin())
                    * (std::f64::consts::PI * y as f64).sin();
            }
            worst = worst.max((sum / 256.0 - exact).abs());
        }
        assert!(worst < 0.005, "{worst}");
    }

    fn rng(mut state: u64) -> impl FnMut() -> u32 {
        move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 32) as u32
        }
    }

    /// The batches (`sobol_batch`) against the sampler they stand in for.
    #[test]
    fn batches_match_the_sampler_bit_for_bit_on_every_level() {
        let mut next = rng(99);
        // Lengths that leave tails at every width, random pixels, indices
        // (small and full 32-bit), sets and seeds.
        for (round, n) in [1usize, 3, 4, 7, 8, 15, 16, 17, 33, 100, 257]
            .into_iter()
            .enumerate()
        {
            let seed = if round % 3 == 0 { 0 } else { next() };
            let xs: Vec<u32> = (0..n).map(|_| next() % 4096).collect();
            let ys: Vec<u32> = (0..n).map(|_| next()).collect();
            let indices: Vec<u32> = (0..n)
                .map(|i| if i % 2 == 0 { next() % 1024 } else { next() })
                .collect();
            let set = [0, 1, 5, next() % 64, next()][round % 5];
            // The reference: a Sampler drawn up to `set`.
            let want: Vec<[f32; 4]> = (0..n)
                .map(|i| {
                    let mut s = Sampler::new(seed);
                    s.start([xs[i], ys[i]], indices[i]);
                    if set < 64 {
                        for _ in 0..set {
                            s.get_4d();
                        }
                        assert_eq!(s.next_set(), set);
                        s.get_4d()
                    } else {
                        set_point(s.pixel_key(), indices[i].reverse_bits(), set)
                    }
                })
                .collect();
            for level in Level::available() {
                let mut keys = vec![0u32; n];
                pixel_keys(level, seed, &xs, &ys, &mut keys);
                for i in 0..n {
                    assert_eq!(keys[i], pixel_key(seed, [xs[i], ys[i]]), "{level} key {i}");
                }
                let mut out = [vec![0f32; n], vec![0f32; n], vec![0f32; n], vec![0f32; n]];
                let [a, b, c, d] = &mut out;
                sobol_sets(level, set, &keys, &indices, [a, b, c, d]);
                for (i, w) in want.iter().enumerate() {
                    for dim in 0..4 {
                        assert_eq!(
                            out[dim][i].to_bits(),
                            w[dim].to_bits(),
                            "{level}: lane {i} of {n}, set {set}, dim {dim}"
                        );
                    }
                }
            }
        }
    }
}

//! The two 4-dimensional sets one bounce of one path draws, with the
//! dimensions as SIMD lanes: what the scalar tracer asks its sampler for at
//! every vertex. Bit-identical to two calls of [`set_point`] at every
//! level.
//!
//! A set's scramble seeds, its index scramble and its Sobol coordinates
//! (table lookups, which pulp's safe kernels cannot gather) are a few
//! scalar steps; the eight coordinates' own scrambles — a hash, the
//! Laine–Karras permutation, a bit reversal and the conversion to [0, 1)
//! each, most of the work — run as one 8-lane register on AVX2 (two on
//! SSE4.2, half of one on AVX-512).
//!
//! [`set_point`]: super::sobol_point::set_point

use super::sobol_point::{laine_karras, mix, set_point, sobol_reversed, DIM_MUL, SET_MUL, UNIT};
use crate::simd::{Kernel, Level, Wide};

/// Sets `set` and `set + 1` of the sample whose bit-reversed index is
/// `index_rev`, in the pixel with key `pixel_key`, at SIMD level `level`.
#[inline]
pub fn set_pair(level: Level, pixel_key: u32, index_rev: u32, set: u32) -> [[f32; 4]; 2] {
    level.run(Pair {
        pixel_key,
        index_rev,
        set,
    })
}

struct Pair {
    pixel_key: u32,
    index_rev: u32,
    set: u32,
}

/// Lanes of the buffers: the eight coordinates, padded to a whole
/// AVX-512 register.
const PADDED: usize = 16;

impl Kernel for Pair {
    type Output = [[f32; 4]; 2];

    fn scalar(self) -> [[f32; 4]; 2] {
        [0, 1].map(|k| set_point(self.pixel_key, self.index_rev, self.set.wrapping_add(k)))
    }

    #[inline(always)]
    fn wide<W: Wide>(self, s: W) -> [[f32; 4]; 2] {
        // Lane 4k + d: coordinate d of set `set + k`; its Sobol value
        // (reversed) and the seed of its own scramble.
        let mut coords = [0u32; PADDED];
        let mut seeds = [0u32; PADDED];
        for k in 0..2 {
            let key = mix(self.pixel_key ^ self.set.wrapping_add(k).wrapping_mul(SET_MUL));
            let index_rev = laine_karras(self.index_rev, key);
            for d in 0..4 {
                coords[4 * k as usize + d] = sobol_reversed(index_rev, d);
                seeds[4 * k as usize + d] = key.wrapping_add((d as u32 + 1).wrapping_mul(DIM_MUL));
            }
        }
        let used = 8usize.max(W::LANES);
        let mut out = [0f32; PADDED];
        let coords = W::as_simd_u32s(&coords[..used]).0;
        let seeds = W::as_simd_u32s(&seeds[..used]).0;
        let outs = W::as_mut_simd_f32s(&mut out[..used]).0;
        for ((o, &x), &seed) in outs.iter_mut().zip(coords).zip(seeds) {
            let bits = s.reverse_bits_u32s(lk(s, x, mix_wide(s, seed)));
            *o = s.mul_f32s(s.i32s_to_f32s(s.shr_u32s::<8>(bits)), s.splat_f32s(UNIT));
        }
        [
            [out[0], out[1], out[2], out[3]],
            [out[4], out[5], out[6], out[7]],
        ]
    }
}

/// `mix` (sobol_point.rs) per lane.
#[inline(always)]
fn mix_wide<W: Wide>(s: W, x: W::u32s) -> W::u32s {
    super::sobol_batch::mix(s, x)
}

/// `laine_karras` (sobol_point.rs) per lane.
#[inline(always)]
fn lk<W: Wide>(s: W, x: W::u32s, seed: W::u32s) -> W::u32s {
    super::sobol_batch::laine_karras(s, x, seed)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pairs_match_two_set_points_bit_for_bit_on_every_level() {
        let mut state = 17u64;
        let mut next = move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 32) as u32
        };
        for round in 0..2000 {
            let (key, index_rev) = (next(), next());
            let set = [0, 1, 7, next() % 64, next(), u32::MAX][round % 6];
            let want = [
                set_point(key, index_rev, set),
                set_point(key, index_rev, set.wrapping_add(1)),
            ];
            for level in Level::available() {
                let got = set_pair(level, key, index_rev, set);
                assert_eq!(
                    got.map(|p| p.map(f32::to_bits)),
                    want.map(|p| p.map(f32::to_bits)),
                    "{level}: key {key}, index {index_rev}, set {set}"
                );
            }
        }
    }
}

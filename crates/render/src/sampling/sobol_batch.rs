//! The sampler's numbers for many samples at once: lane i of a batch is
//! sample `indices[i]` of the pixel with key `pixel_keys[i]`, all at the
//! same 4-dimensional set, bit-identical to [`Sampler`] (and to
//! [`set_point`], the scalar reference) at every SIMD level.
//!
//! The hashes and scrambles are 32-bit multiplies, shifts and XORs, one per
//! lane. The Sobol matrix–vector product, which the scalar code does with
//! byte tables, becomes lookups of b index bits at a time in tables of one
//! register (b = 2, 3, 4 for 4, 8, 16 lanes: a byte shuffle, `vpermd` on
//! AVX2 and AVX-512), since pulp's safe kernels have no gathers.
//!
//! [`Sampler`]: super::sobol::Sampler
//! [`set_point`]: super::sobol_point::set_point

use super::sobol_point::{
    murmur, pixel_key, set_point, DIM_MUL, DIRECTIONS, LK_MULS, MIX_MULS, SET_MUL, UNIT,
};
use crate::simd::{Kernel, Level, Wide};

/// For Sobol dimensions 1–3 and each group `g` of `B` bits of a reversed
/// index (bits gB … gB + B − 1), the XOR of the reversed direction numbers
/// of each pattern of those bits: the reversed coordinate is the XOR of
/// one entry per group (dimension 0's reversed coordinate is the index's
/// bit reversal: its generator matrix is the identity).
const fn group_tables<const B: usize, const G: usize, const P: usize>() -> [[[u32; P]; G]; 3] {
    let mut t = [[[0u32; P]; G]; 3];
    let mut d = 0;
    while d < 3 {
        let mut g = 0;
        while g < G {
            let mut pattern = 0;
            while pattern < P {
                let mut x = 0u32;
                let mut bit = 0;
                while bit < B {
                    let j = g * B + bit;
                    if j < 32 && (pattern >> bit) & 1 == 1 {
                        x ^= DIRECTIONS[d + 1][31 - j].reverse_bits();
                    }
                    bit += 1;
                }
                t[d][g][pattern] = x;
                pattern += 1;
            }
            g += 1;
        }
        d += 1;
    }
    t
}

static GROUPS_4: [[[u32; 4]; 16]; 3] = group_tables::<2, 16, 4>();
static GROUPS_8: [[[u32; 8]; 11]; 3] = group_tables::<3, 11, 8>();
static GROUPS_16: [[[u32; 16]; 8]; 3] = group_tables::<4, 8, 16>();

/// Fills `out[d][i]` with coordinate d of 4-dimensional set `set` of sample
/// `indices[i]` of the pixel with key `pixel_keys[i]` (from [`pixel_key`]
/// or [`pixel_keys`]), at SIMD level `level`.
///
/// # Panics
/// When the slices' lengths differ.
pub fn sobol_sets(
    level: Level,
    set: u32,
    pixel_keys: &[u32],
    indices: &[u32],
    out: [&mut [f32]; 4],
) {
    let n = pixel_keys.len();
    assert!(
        indices.len() == n && out.iter().all(|o| o.len() == n),
        "sobol_sets: lanes of different lengths"
    );
    level.run(Sets {
        set,
        keys: pixel_keys,
        indices,
        out,
    });
}

/// Fills `out[i]` with the key of pixel (xs[i], ys[i]) under `seed`
/// ([`pixel_key`]), at SIMD level `level`.
///
/// # Panics
/// When the slices' lengths differ.
pub fn pixel_keys(level: Level, seed: u32, xs: &[u32], ys: &[u32], out: &mut [u32]) {
    assert!(
        xs.len() == out.len() && ys.len() == out.len(),
        "pixel_keys: lanes of different lengths"
    );
    level.run(Keys { seed, xs, ys, out });
}

struct Sets<'a> {
    set: u32,
    keys: &'a [u32],
    indices: &'a [u32],
    out: [&'a mut [f32]; 4],
}

impl Kernel for Sets<'_> {
    type Output = ();

    fn scalar(self) {
        let [o0, o1, o2, o3] = self.out;
        for i in 0..self.keys.len() {
            let p = set_point(self.keys[i], self.indices[i].reverse_bits(), self.set);
            (o0[i], o1[i], o2[i], o3[i]) = (p[0], p[1], p[2], p[3]);
        }
    }

    #[inline(always)]
    fn wide<W: Wide>(self, s: W) {
        let full = self.keys.len() / W::LANES * W::LANES;
        let [o0, o1, o2, o3] = self.out.map(|o| o.split_at_mut(full));
        let keys = W::as_simd_u32s(&self.keys[..full]).0;
        let indices = W::as_simd_u32s(&self.indices[..full]).0;
        let outs = [
            W::as_mut_simd_f32s(o0.0).0,
            W::as_mut_simd_f32s(o1.0).0,
            W::as_mut_simd_f32s(o2.0).0,
            W::as_mut_simd_f32s(o3.0).0,
        ];
        let (t0, t1, t2, t3) = (o0.1, o1.1, o2.1, o3.1);
        let [a, b, c, d] = outs;
        for (v, (&k, &i)) in keys.iter().zip(indices).enumerate() {
            let p = set_points(s, k, i, self.set);
            (a[v], b[v], c[v], d[v]) = (p[0], p[1], p[2], p[3]);
        }
        // The lanes past the last full register: the scalar reference.
        for (j, i) in (full..self.keys.len()).enumerate() {
            let p = set_point(self.keys[i], self.indices[i].reverse_bits(), self.set);
            (t0[j], t1[j], t2[j], t3[j]) = (p[0], p[1], p[2], p[3]);
        }
    }
}

/// [`set_point`] on a register of lanes.
#[inline(always)]
fn set_points<W: Wide>(s: W, keys: W::u32s, index: W::u32s, set: u32) -> [W::f32s; 4] {
    let key = mix(s, s.xor_u32s(keys, s.splat_u32s(set.wrapping_mul(SET_MUL))));
    let index_rev = laine_karras(s, s.reverse_bits_u32s(index), key);
    let rev = sobol_reversed(s, index_rev);
    let mut out = [s.splat_f32s(0.0); 4];
    for (d, (o, x)) in out.iter_mut().zip(rev).enumerate() {
        let seed = mix(
            s,
            s.add_u32s(key, s.splat_u32s((d as u32 + 1).wrapping_mul(DIM_MUL))),
        );
        let bits = s.reverse_bits_u32s(laine_karras(s, x, seed));
        *o = s.mul_f32s(s.i32s_to_f32s(s.shr_u32s::<8>(bits)), s.splat_f32s(UNIT));
    }
    out
}

/// Wellons's lowbias32 per lane (`mix` in sobol_point.rs).
#[inline(always)]
pub(super) fn mix<W: Wide>(s: W, mut x: W::u32s) -> W::u32s {
    x = s.xor_u32s(x, s.shr_u32s::<16>(x));
    x = s.mul_u32s(x, s.splat_u32s(MIX_MULS[0]));
    x = s.xor_u32s(x, s.shr_u32s::<15>(x));
    x = s.mul_u32s(x, s.splat_u32s(MIX_MULS[1]));
    s.xor_u32s(x, s.shr_u32s::<16>(x))
}

/// The Laine–Karras permutation per lane (`laine_karras` in sobol_point.rs).
#[inline(always)]
pub(super) fn laine_karras<W: Wide>(s: W, x: W::u32s, seed: W::u32s) -> W::u32s {
    let mut x = s.add_u32s(x, seed);
    for m in LK_MULS {
        x = s.xor_u32s(x, s.mul_u32s(x, s.splat_u32s(m)));
    }
    x
}

/// The four reversed Sobol coordinates of reversed indices `x`
/// (`sobol_reversed` in sobol_point.rs).
#[inline(always)]
fn sobol_reversed<W: Wide>(s: W, x: W::u32s) -> [W::u32s; 4] {
    let [d1, d2, d3] = match W::LANES {
        4 => by_groups::<W, 2, 16, 4>(s, x, &GROUPS_4),
        8 => by_groups::<W, 3, 11, 8>(s, x, &GROUPS_8),
        _ => by_groups::<W, 4, 8, 16>(s, x, &GROUPS_16),
    };
    [s.reverse_bits_u32s(x), d1, d2, d3]
}

/// Dimensions 1–3 by table lookups, `B` bits of `x` at a time.
#[inline(always)]
fn by_groups<W: Wide, const B: i32, const G: usize, const P: usize>(
    s: W,
    mut x: W::u32s,
    tables: &[[[u32; P]; G]; 3],
) -> [W::u32s; 3] {
    let mut r = [s.splat_u32s(0); 3];
    for g in 0..G {
        for (r, t) in r.iter_mut().zip(tables) {
            let table = W::as_simd_u32s(&t[g]).0[0];
            *r = s.xor_u32s(*r, s.permute_u32s(table, x));
        }
        x = s.shr_u32s::<B>(x);
    }
    r
}

struct Keys<'a> {
    seed: u32,
    xs: &'a [u32],
    ys: &'a [u32],
    out: &'a mut [u32],
}

impl Kernel for Keys<'_> {
    type Output = ();

    fn scalar(self) {
        for ((o, &x), &y) in self.out.iter_mut().zip(self.xs).zip(self.ys) {
            *o = pixel_key(self.seed, [x, y]);
        }
    }

    #[inline(always)]
    fn wide<W: Wide>(self, s: W) {
        let full = self.out.len() / W::LANES * W::LANES;
        let (head, tail) = self.out.split_at_mut(full);
        let xs = W::as_simd_u32s(&self.xs[..full]).0;
        let ys = W::as_simd_u32s(&self.ys[..full]).0;
        let out = W::as_mut_simd_u32s(head).0;
        for ((o, &x), &y) in out.iter_mut().zip(xs).zip(ys) {
            *o = hash3(s, self.seed, x, y);
        }
        for (o, i) in tail.iter_mut().zip(full..) {
            *o = pixel_key(self.seed, [self.xs[i], self.ys[i]]);
        }
    }
}

/// `x.rotate_left(R)` per lane (`L` = 32 − `R`).
#[inline(always)]
fn rotl<W: Wide, const R: i32, const L: i32>(s: W, x: W::u32s) -> W::u32s {
    s.or_u32s(s.shl_u32s::<R>(x), s.shr_u32s::<L>(x))
}

/// One word's round of `hash` (sobol_point.rs) per lane.
#[inline(always)]
fn hash_round<W: Wide>(s: W, h: W::u32s, w: W::u32s) -> W::u32s {
    let k = s.mul_u32s(w, s.splat_u32s(murmur::C1));
    let k = s.mul_u32s(rotl::<W, 15, 17>(s, k), s.splat_u32s(murmur::C2));
    let h = s.xor_u32s(h, k);
    s.add_u32s(
        s.mul_u32s(rotl::<W, 13, 19>(s, h), s.splat_u32s(5)),
        s.splat_u32s(murmur::N),
    )
}

/// `hash(&[seed, x, y])` (sobol_point.rs) per lane.
#[inline(always)]
fn hash3<W: Wide>(s: W, seed: u32, x: W::u32s, y: W::u32s) -> W::u32s {
    // The first word is the same in every lane: hashed once, in scalar.
    let k = seed
        .wrapping_mul(murmur::C1)
        .rotate_left(15)
        .wrapping_mul(murmur::C2);
    let h0 = (murmur::INIT ^ k)
        .rotate_left(13)
        .wrapping_mul(5)
        .wrapping_add(murmur::N);
    let mut h = hash_round(s, hash_round(s, s.splat_u32s(h0), x), y);
    h = s.xor_u32s(h, s.shr_u32s::<16>(h));
    h = s.mul_u32s(h, s.splat_u32s(murmur::F1));
    h = s.xor_u32s(h, s.shr_u32s::<13>(h));
    h = s.mul_u32s(h, s.splat_u32s(murmur::F2));
    s.xor_u32s(h, s.shr_u32s::<16>(h))
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rng(mut state: u64) -> impl FnMut() -> u32 {
        move || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 32) as u32
        }
    }

    #[test]
    fn group_tables_match_the_byte_tables() {
        let mut next = rng(5);
        for _ in 0..1000 {
            let x = next();
            for (d, t4) in GROUPS_16.iter().enumerate() {
                let by = |b: u32, groups: &[[u32; 16]]| -> u32 {
                    (0..groups.len())
                        .map(|g| groups[g][((x >> (g as u32 * b)) & 15) as usize])
                        .fold(0, |a, v| a ^ v)
                };
                let want =
                    crate::sampling::sobol_point::sobol(x.reverse_bits(), d + 1).reverse_bits();
                assert_eq!(by(4, t4), want);
                let g8: u32 = (0..11)
                    .map(|g| GROUPS_8[d][g][((x >> (3 * g)) & 7) as usize])
                    .fold(0, |a, v| a ^ v);
                let g4: u32 = (0..16)
                    .map(|g| GROUPS_4[d][g][((x >> (2 * g)) & 3) as usize])
                    .fold(0, |a, v| a ^ v);
                assert_eq!((g8, g4), (want, want));
            }
        }
    }
}

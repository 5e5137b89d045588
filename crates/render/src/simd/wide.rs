//! What kernels need beyond pulp's generic `Simd` trait (which has no bit
//! shifts, integer-to-float conversion or table lookups), for each of
//! pulp's x86 levels, from pulp's safe intrinsic wrappers; and lane
//! helpers whose lane order is tested here (pulp 0.22.3's
//! `first_true_m32s` returns the highest set lane of AVX-512 bit masks).

use super::Level;

/// A pulp SIMD level with the operations scotopia's kernels use.
pub trait Wide: pulp::Simd + super::Lanes8 {
    const LEVEL: Level;
    /// 32-bit lanes per register.
    const LANES: usize;
    /// `a << N` per lane.
    fn shl_u32s<const N: i32>(self, a: Self::u32s) -> Self::u32s;
    /// `a >> N` per lane (logical).
    fn shr_u32s<const N: i32>(self, a: Self::u32s) -> Self::u32s;
    /// Lanes below 2³¹ as `f32` (`x as f32`, rounding to nearest).
    fn i32s_to_f32s(self, a: Self::u32s) -> Self::f32s;
    /// The mask as bits: bit i set when lane i is.
    fn mask_bits(self, m: Self::m32s) -> u32;
    /// `table[idx & (LANES − 1)]` per lane: a lookup in a table of one
    /// register.
    fn permute_u32s(self, table: Self::u32s, idx: Self::u32s) -> Self::u32s;
    /// `a.reverse_bits()` per lane.
    fn reverse_bits_u32s(self, a: Self::u32s) -> Self::u32s;
}

/// The lowest lane set in `bits` (from [`Wide::mask_bits`]), if any.
#[inline(always)]
pub fn first_lane(bits: u32) -> Option<usize> {
    (bits != 0).then(|| bits.trailing_zeros() as usize)
}

/// Per byte: bits 0–3 reversed, in the high nibble / in the low nibble.
#[cfg(target_arch = "x86_64")]
const REV_NIBBLE_HI: [u8; 16] = nibble_table(4);
#[cfg(target_arch = "x86_64")]
const REV_NIBBLE_LO: [u8; 16] = nibble_table(0);
/// Byte indices reversing the bytes of each 32-bit lane.
#[cfg(target_arch = "x86_64")]
const BYTE_SWAP: [u8; 16] = [3, 2, 1, 0, 7, 6, 5, 4, 11, 10, 9, 8, 15, 14, 13, 12];

#[cfg(target_arch = "x86_64")]
const fn nibble_table(shift: u32) -> [u8; 16] {
    let mut t = [0u8; 16];
    let mut n = 0;
    while n < 16 {
        t[n] = ((n as u8).reverse_bits() >> 4) << shift;
        n += 1;
    }
    t
}

/// A 16-byte table repeated over `N` bytes (byte shuffles index within
/// each 128-bit block).
#[cfg(target_arch = "x86_64")]
const fn repeat<const N: usize>(t: [u8; 16]) -> [u8; N] {
    let mut out = [0u8; N];
    let mut i = 0;
    while i < N {
        out[i] = t[i % 16];
        i += 1;
    }
    out
}

/// The three tables of [`reverse_by_shuffles`] for registers of `N` bytes.
#[cfg(target_arch = "x86_64")]
struct ReverseTables<const N: usize>;

#[cfg(target_arch = "x86_64")]
impl<const N: usize> ReverseTables<N> {
    const HI: [u8; N] = repeat(REV_NIBBLE_HI);
    const LO: [u8; N] = repeat(REV_NIBBLE_LO);
    const SWAP: [u8; N] = repeat(BYTE_SWAP);
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    use super::*;
    use pulp::x86::{V2, V3, V4};
    use pulp::{cast, u32x16, u32x4, u32x8, Simd};

    /// Reverses the bits of each 32-bit lane with three byte shuffles:
    /// each nibble through a reversal table (into the other half of its
    /// byte), then the bytes of each lane in reverse order.
    macro_rules! reverse_by_shuffles {
        ($s:expr, $a:expr, $u32s:ident, $bytes:literal, $shuffle:ident) => {{
            let s = $s;
            let low = s.splat_u32s(0x0f0f_0f0f);
            let lo = s.and_u32s($a, low);
            let hi = s.and_u32s(s.shr_u32s::<4>($a), low);
            let t_hi: $u32s = cast(ReverseTables::<$bytes>::HI);
            let t_lo: $u32s = cast(ReverseTables::<$bytes>::LO);
            let swap: $u32s = cast(ReverseTables::<$bytes>::SWAP);
            let bytes = s.or_u32s($shuffle(s, t_hi, lo), $shuffle(s, t_lo, hi));
            $shuffle(s, bytes, swap)
        }};
    }

    #[inline(always)]
    fn shuffle_v2(s: V2, t: u32x4, i: u32x4) -> u32x4 {
        cast(s.ssse3._mm_shuffle_epi8(cast(t), cast(i)))
    }
    #[inline(always)]
    fn shuffle_v3(s: V3, t: u32x8, i: u32x8) -> u32x8 {
        cast(s.avx2._mm256_shuffle_epi8(cast(t), cast(i)))
    }
    #[inline(always)]
    fn shuffle_v4(s: V4, t: u32x16, i: u32x16) -> u32x16 {
        cast(s.avx512bw._mm512_shuffle_epi8(cast(t), cast(i)))
    }

    impl Wide for V2 {
        const LEVEL: Level = Level::Sse42;
        const LANES: usize = 4;
        #[inline(always)]
        fn shl_u32s<const N: i32>(self, a: u32x4) -> u32x4 {
            self.shl_const_u32x4::<N>(a)
        }
        #[inline(always)]
        fn shr_u32s<const N: i32>(self, a: u32x4) -> u32x4 {
            self.shr_const_u32x4::<N>(a)
        }
        #[inline(always)]
        fn i32s_to_f32s(self, a: u32x4) -> pulp::f32x4 {
            self.convert_i32x4_to_f32x4(cast(a))
        }
        #[inline(always)]
        fn mask_bits(self, m: pulp::m32x4) -> u32 {
            self.sse._mm_movemask_ps(cast(m)) as u32
        }
        #[inline(always)]
        fn permute_u32s(self, table: u32x4, idx: u32x4) -> u32x4 {
            // No 32-bit permute below AVX2: a byte shuffle whose byte
            // indices are 4·idx + (0, 1, 2, 3) in every lane.
            let i = self.and_u32s(idx, self.splat_u32s(3));
            let bytes = self.add_u32s(
                self.mul_u32s(i, self.splat_u32s(0x0404_0404)),
                self.splat_u32s(0x0302_0100),
            );
            cast(self.ssse3._mm_shuffle_epi8(cast(table), cast(bytes)))
        }
        #[inline(always)]
        fn reverse_bits_u32s(self, a: u32x4) -> u32x4 {
            reverse_by_shuffles!(self, a, u32x4, 16, shuffle_v2)
        }
    }

    impl Wide for V3 {
        const LEVEL: Level = Level::Avx2;
        const LANES: usize = 8;
        #[inline(always)]
        fn shl_u32s<const N: i32>(self, a: u32x8) -> u32x8 {
            self.shl_const_u32x8::<N>(a)
        }
        #[inline(always)]
        fn shr_u32s<const N: i32>(self, a: u32x8) -> u32x8 {
            self.shr_const_u32x8::<N>(a)
        }
        #[inline(always)]
        fn i32s_to_f32s(self, a: u32x8) -> pulp::f32x8 {
            self.convert_i32x8_to_f32x8(cast(a))
        }
        #[inline(always)]
        fn mask_bits(self, m: pulp::m32x8) -> u32 {
            self.avx._mm256_movemask_ps(cast(m)) as u32
        }
        #[inline(always)]
        fn permute_u32s(self, table: u32x8, idx: u32x8) -> u32x8 {
            cast(
                self.avx2
                    ._mm256_permutevar8x32_epi32(cast(table), cast(idx)),
            )
        }
        #[inline(always)]
        fn reverse_bits_u32s(self, a: u32x8) -> u32x8 {
            reverse_by_shuffles!(self, a, u32x8, 32, shuffle_v3)
        }
    }

    impl Wide for V4 {
        const LEVEL: Level = Level::Avx512;
        const LANES: usize = 16;
        #[inline(always)]
        fn shl_u32s<const N: i32>(self, a: u32x16) -> u32x16 {
            // pulp's immediate form takes a u32 constant; LLVM folds this one.
            self.shl_u32x16(a, pulp::u64x2(N as u64, 0))
        }
        #[inline(always)]
        fn shr_u32s<const N: i32>(self, a: u32x16) -> u32x16 {
            self.shr_u32x16(a, pulp::u64x2(N as u64, 0))
        }
        #[inline(always)]
        fn i32s_to_f32s(self, a: u32x16) -> pulp::f32x16 {
            self.convert_i32x16_to_f32x16(cast(a))
        }
        #[inline(always)]
        fn mask_bits(self, m: pulp::b16) -> u32 {
            // Bit i of an AVX-512 mask register is lane i.
            m.0 as u32
        }
        #[inline(always)]
        fn permute_u32s(self, table: u32x16, idx: u32x16) -> u32x16 {
            cast(
                self.avx512f
                    ._mm512_permutexvar_epi32(cast(idx), cast(table)),
            )
        }
        #[inline(always)]
        fn reverse_bits_u32s(self, a: u32x16) -> u32x16 {
            reverse_by_shuffles!(self, a, u32x16, 64, shuffle_v4)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simd::Kernel;
    use pulp::cast;

    /// Every lane helper on every level this machine has, against scalar
    /// code, on lane patterns that would expose a wrong lane order.
    struct Check;
    impl Kernel for Check {
        type Output = ();
        fn scalar(self) {}
        fn wide<W: Wide>(self, s: W) {
            let n = W::LANES;
            assert_eq!(std::mem::size_of::<W::u32s>(), 4 * n);
            let from = |f: &dyn Fn(usize) -> u32| -> W::u32s {
                let v: Vec<u32> = (0..n).map(f).collect();
                s.partial_load_u32s(&v)
            };
            let to = |v: W::u32s| -> Vec<u32> {
                let mut out = vec![0u32; n];
                s.partial_store_u32s(&mut out, v);
                out
            };
            let mut state = 0x1234_5678u32;
            let mut rand = move || {
                state ^= state << 13;
                state ^= state >> 17;
                state ^= state << 5;
                state
            };
            for _ in 0..200 {
                let vals: Vec<u32> = (0..n).map(|_| rand()).collect();
                let a = from(&|i| vals[i]);
                assert_eq!(
                    to(s.shl_u32s::<7>(a)),
                    vals.iter().map(|v| v << 7).collect::<Vec<_>>()
                );
                assert_eq!(
                    to(s.shr_u32s::<9>(a)),
                    vals.iter().map(|v| v >> 9).collect::<Vec<_>>()
                );
                assert_eq!(
                    to(s.reverse_bits_u32s(a)),
                    vals.iter().map(|v| v.reverse_bits()).collect::<Vec<_>>()
                );
                let f = s.i32s_to_f32s(s.shr_u32s::<1>(a));
                let mut got = vec![0f32; n];
                s.partial_store_f32s(&mut got, f);
                for (g, v) in got.iter().zip(&vals) {
                    assert_eq!(g.to_bits(), ((v >> 1) as f32).to_bits());
                }
                // A table lookup uses the low bits of the index.
                let table = from(&|i| 1000 + i as u32);
                let idx = a;
                assert_eq!(
                    to(s.permute_u32s(table, idx)),
                    vals.iter()
                        .map(|v| 1000 + (v & (n as u32 - 1)))
                        .collect::<Vec<_>>()
                );
                // Mask bits follow lane order, and the first lane is the
                // lowest set one.
                let pick = rand() & ((1u64 << n) - 1) as u32;
                let m = s.equal_u32s(
                    s.and_u32s(from(&|i| 1 << i), s.splat_u32s(pick)),
                    from(&|i| 1 << i),
                );
                assert_eq!(s.mask_bits(m), pick);
                assert_eq!(
                    first_lane(pick),
                    (0..n).find(|i| pick >> i & 1 == 1),
                    "{pick:b}"
                );
            }
            // One lane at a time, each position.
            for lane in 0..n {
                let m = s.equal_u32s(from(&|i| i as u32), s.splat_u32s(lane as u32));
                assert_eq!(s.mask_bits(m), 1 << lane);
                assert_eq!(first_lane(s.mask_bits(m)), Some(lane));
                let f = s.less_than_f32s(
                    cast::<_, W::f32s>(s.splat_u32s(0)),
                    cast::<_, W::f32s>(from(&|i| if i == lane { 1.0f32.to_bits() } else { 0 })),
                );
                assert_eq!(s.mask_bits(f), 1 << lane);
            }
            assert_eq!(first_lane(0), None);
        }
    }

    #[test]
    fn lane_helpers_agree_with_scalar_code_on_every_level() {
        for level in Level::available() {
            level.run(Check);
        }
    }
}

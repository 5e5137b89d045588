//! Eight f32 lanes at every level: one 256-bit register at AVX2 and
//! AVX-512 (8-wide BVH nodes gain nothing from 16 lanes), two 128-bit
//! halves at SSE4.2, an array loop at scalar. Each operation is the same
//! IEEE operation on every level, lane by lane, and `min`/`max` keep the
//! x86 operand rule (`if a < b { a } else { b }`: the second operand when
//! either is NaN), so a computation written with them gives the same bits
//! at every level.

/// Eight f32 lanes and the operations a box test needs.
pub trait Lanes8: Copy {
    type F: Copy;
    fn load(self, a: &[f32; 8]) -> Self::F;
    fn splat(self, v: f32) -> Self::F;
    fn sub(self, a: Self::F, b: Self::F) -> Self::F;
    fn mul(self, a: Self::F, b: Self::F) -> Self::F;
    /// `if a < b { a } else { b }` per lane.
    fn min(self, a: Self::F, b: Self::F) -> Self::F;
    /// `if a > b { a } else { b }` per lane.
    fn max(self, a: Self::F, b: Self::F) -> Self::F;
    /// Bit i set when `a[i] <= b[i]` (false for NaN).
    fn le_bits(self, a: Self::F, b: Self::F) -> u32;
    fn store(self, a: Self::F) -> [f32; 8];
}

/// The scalar level's lanes: loops over arrays.
#[derive(Clone, Copy)]
pub struct Scalar8;

impl Lanes8 for Scalar8 {
    type F = [f32; 8];
    #[inline(always)]
    fn load(self, a: &[f32; 8]) -> [f32; 8] {
        *a
    }
    #[inline(always)]
    fn splat(self, v: f32) -> [f32; 8] {
        [v; 8]
    }
    #[inline(always)]
    fn sub(self, mut a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
        for i in 0..8 {
            a[i] -= b[i];
        }
        a
    }
    #[inline(always)]
    fn mul(self, mut a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
        for i in 0..8 {
            a[i] *= b[i];
        }
        a
    }
    #[inline(always)]
    fn min(self, mut a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
        for i in 0..8 {
            a[i] = if a[i] < b[i] { a[i] } else { b[i] };
        }
        a
    }
    #[inline(always)]
    fn max(self, mut a: [f32; 8], b: [f32; 8]) -> [f32; 8] {
        for i in 0..8 {
            a[i] = if a[i] > b[i] { a[i] } else { b[i] };
        }
        a
    }
    #[inline(always)]
    fn le_bits(self, a: [f32; 8], b: [f32; 8]) -> u32 {
        let mut m = 0;
        for i in 0..8 {
            m |= ((a[i] <= b[i]) as u32) << i;
        }
        m
    }
    #[inline(always)]
    fn store(self, a: [f32; 8]) -> [f32; 8] {
        a
    }
}

#[cfg(target_arch = "x86_64")]
mod x86 {
    use super::Lanes8;
    use core::arch::x86_64::{__m128, __m256, _CMP_LE_OQ};
    use pulp::cast;
    use pulp::x86::{V2, V3, V4};

    /// Two halves of four lanes: lanes 0–3, 4–7.
    impl Lanes8 for V2 {
        type F = (__m128, __m128);
        #[inline(always)]
        fn load(self, a: &[f32; 8]) -> Self::F {
            let [lo, hi]: [__m128; 2] = cast(*a);
            (lo, hi)
        }
        #[inline(always)]
        fn splat(self, v: f32) -> Self::F {
            let h = self.sse._mm_set1_ps(v);
            (h, h)
        }
        #[inline(always)]
        fn sub(self, a: Self::F, b: Self::F) -> Self::F {
            (self.sse._mm_sub_ps(a.0, b.0), self.sse._mm_sub_ps(a.1, b.1))
        }
        #[inline(always)]
        fn mul(self, a: Self::F, b: Self::F) -> Self::F {
            (self.sse._mm_mul_ps(a.0, b.0), self.sse._mm_mul_ps(a.1, b.1))
        }
        #[inline(always)]
        fn min(self, a: Self::F, b: Self::F) -> Self::F {
            (self.sse._mm_min_ps(a.0, b.0), self.sse._mm_min_ps(a.1, b.1))
        }
        #[inline(always)]
        fn max(self, a: Self::F, b: Self::F) -> Self::F {
            (self.sse._mm_max_ps(a.0, b.0), self.sse._mm_max_ps(a.1, b.1))
        }
        #[inline(always)]
        fn le_bits(self, a: Self::F, b: Self::F) -> u32 {
            let lo = self.sse._mm_movemask_ps(self.sse._mm_cmple_ps(a.0, b.0)) as u32;
            let hi = self.sse._mm_movemask_ps(self.sse._mm_cmple_ps(a.1, b.1)) as u32;
            lo | hi << 4
        }
        #[inline(always)]
        fn store(self, a: Self::F) -> [f32; 8] {
            cast([a.0, a.1])
        }
    }

    /// One 256-bit register.
    impl Lanes8 for V3 {
        type F = __m256;
        #[inline(always)]
        fn load(self, a: &[f32; 8]) -> __m256 {
            cast(*a)
        }
        #[inline(always)]
        fn splat(self, v: f32) -> __m256 {
            self.avx._mm256_set1_ps(v)
        }
        #[inline(always)]
        fn sub(self, a: __m256, b: __m256) -> __m256 {
            self.avx._mm256_sub_ps(a, b)
        }
        #[inline(always)]
        fn mul(self, a: __m256, b: __m256) -> __m256 {
            self.avx._mm256_mul_ps(a, b)
        }
        #[inline(always)]
        fn min(self, a: __m256, b: __m256) -> __m256 {
            self.avx._mm256_min_ps(a, b)
        }
        #[inline(always)]
        fn max(self, a: __m256, b: __m256) -> __m256 {
            self.avx._mm256_max_ps(a, b)
        }
        #[inline(always)]
        fn le_bits(self, a: __m256, b: __m256) -> u32 {
            self.avx
                ._mm256_movemask_ps(self.avx._mm256_cmp_ps::<_CMP_LE_OQ>(a, b)) as u32
        }
        #[inline(always)]
        fn store(self, a: __m256) -> [f32; 8] {
            cast(a)
        }
    }

    /// AVX-512's 256-bit register (its AVX2 subset).
    impl Lanes8 for V4 {
        type F = __m256;
        #[inline(always)]
        fn load(self, a: &[f32; 8]) -> __m256 {
            (*self).load(a)
        }
        #[inline(always)]
        fn splat(self, v: f32) -> __m256 {
            (*self).splat(v)
        }
        #[inline(always)]
        fn sub(self, a: __m256, b: __m256) -> __m256 {
            (*self).sub(a, b)
        }
        #[inline(always)]
        fn mul(self, a: __m256, b: __m256) -> __m256 {
            (*self).mul(a, b)
        }
        #[inline(always)]
        fn min(self, a: __m256, b: __m256) -> __m256 {
            (*self).min(a, b)
        }
        #[inline(always)]
        fn max(self, a: __m256, b: __m256) -> __m256 {
            (*self).max(a, b)
        }
        #[inline(always)]
        fn le_bits(self, a: __m256, b: __m256) -> u32 {
            (*self).le_bits(a, b)
        }
        #[inline(always)]
        fn store(self, a: __m256) -> [f32; 8] {
            (*self).store(a)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::simd::{Kernel, Level, Wide};

    /// Values that exercise the NaN and infinity rules of min, max and ≤.
    const SPECIAL: [f32; 8] = [
        0.0,
        -0.0,
        1.5,
        -2.25,
        f32::INFINITY,
        f32::NEG_INFINITY,
        f32::NAN,
        1e-40,
    ];

    fn bits(a: [f32; 8]) -> [u32; 8] {
        a.map(f32::to_bits)
    }

    fn run_ops<L: Lanes8>(
        l: L,
        a: [f32; 8],
        b: [f32; 8],
    ) -> ([u32; 8], [u32; 8], [u32; 8], [u32; 8], u32) {
        let (x, y) = (l.load(&a), l.load(&b));
        (
            bits(l.store(l.sub(x, y))),
            bits(l.store(l.mul(x, y))),
            bits(l.store(l.min(x, y))),
            bits(l.store(l.max(x, y))),
            l.le_bits(x, y) | (l.le_bits(l.splat(a[3]), y) << 8),
        )
    }

    struct Check(Vec<([f32; 8], [f32; 8])>);
    impl Kernel for Check {
        type Output = ();
        fn scalar(self) {}
        fn wide<W: Wide>(self, s: W) {
            for (a, b) in &self.0 {
                assert_eq!(run_ops(s, *a, *b), run_ops(Scalar8, *a, *b), "{a:?} {b:?}");
            }
        }
    }

    #[test]
    fn every_level_computes_the_scalar_lanes_bits() {
        let mut pairs = Vec::new();
        for r in 0..8 {
            let a = SPECIAL;
            let mut b = SPECIAL;
            b.rotate_left(r);
            pairs.push((a, b));
            pairs.push((b, a));
        }
        for level in Level::available() {
            level.run(Check(pairs.clone()));
        }
        // The scalar rules themselves: the second operand on NaN.
        let (_, _, min, max, le) = run_ops(Scalar8, SPECIAL, [f32::NAN; 8]);
        assert!(min.iter().chain(&max).all(|&m| f32::from_bits(m).is_nan()));
        assert_eq!(le, 0);
    }
}

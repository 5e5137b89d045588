//! log₂, 2^x and eˣ written so that a loop over a row compiles to wide
//! SIMD (no calls into libm, no branches: selects, integer bit moves and
//! polynomials), for the multiscale model's per-pixel gains and contrast
//! roll-off. They work in f64 and are accurate to 1e-11, so the f32
//! results they feed equal libm's `powf` and `expf` (themselves within an
//! ulp of exact) in all but the rare cases where the exact value lies near
//! an f32 rounding boundary — then they differ by one ulp (tested here
//! and, through the whole model, in multiscale's tests).
//!
//! [`cbrt`], the cube root in Oklab (gamut mapping), is written the same
//! way and is faithful to a few f64 ulps rather than correctly rounded:
//! Rust's `f64::cbrt` (compiler_builtins' correctly rounded one) was a
//! quarter of a daylight `scotopia display`.
//!
//! [`dispatch`] runs a closure compiled for the best instruction set the
//! CPU has (pulp's run-time dispatch; safe code, `unsafe` stays in pulp).
//! Rust never fuses a multiply and an add on its own, so every level
//! computes the same bits.

/// Runs `f` inside a function compiled for the CPU's widest SIMD level
/// (AVX-512, AVX2+FMA, SSE4.2 or plain x86-64): the loops in `f` that
/// call only the `#[inline(always)]` functions here vectorise to it.
#[inline(always)]
pub fn dispatch<R>(f: impl FnOnce() -> R) -> R {
    pulp::Arch::new().dispatch(f)
}

/// 1.5·2⁵²: adding it rounds an f64 of magnitude below 2⁵¹ to an
/// integer, which lands in the low mantissa bits.
const ROUNDER: f64 = 6_755_399_441_055_744.0;

/// 2^y for y in [−1000, 1000] (clamped there; NaN stays NaN).
#[inline(always)]
pub fn exp2(y: f64) -> f64 {
    // Clamped with comparisons, not `clamp`/`max`, so NaN passes through.
    let y = if y < -1000.0 { -1000.0 } else { y };
    let y = if y > 1000.0 { 1000.0 } else { y };
    // y = k + f, k an integer, |f| ≤ ½.
    let r = y + ROUNDER;
    let k = r - ROUNDER;
    let f = y - k;
    // 2^f = e^(f·ln 2), |f·ln 2| ≤ 0.347: Taylor to degree 9 leaves
    // 0.347¹⁰/10! < 1e-11, far below an f32 ulp (6e-8).
    let x = f * std::f64::consts::LN_2;
    let mut p = 1.0 / 362_880.0; // 1/9!
    for d in INV_FACTORIALS {
        p = p * x + d;
    }
    // 2^k: r's low mantissa bits hold k (two's complement); k + 1023 in
    // the exponent field is 2^k for −1022 ≤ k ≤ 1023.
    let scale = f64::from_bits(r.to_bits().wrapping_add(1023) << 52);
    p * scale
}

/// 1/8!, 1/7!, …, 1/1!, 1/0!: the Horner steps after 1/9!.
const INV_FACTORIALS: [f64; 9] = [
    1.0 / 40_320.0,
    1.0 / 5_040.0,
    1.0 / 720.0,
    1.0 / 120.0,
    1.0 / 24.0,
    1.0 / 6.0,
    1.0 / 2.0,
    1.0,
    1.0,
];

/// eˣ (x·log₂e clamped to [−1000, 1000]).
#[inline(always)]
pub fn exp(x: f64) -> f64 {
    exp2(x * std::f64::consts::LOG2_E)
}

/// log₂ t for a positive, normal, finite f32 `t`, in f64.
#[inline(always)]
pub fn log2(t: f32) -> f64 {
    let bits = t.to_bits();
    // t = 2^e · m, m in [1, 2), then m moved to [√½, √2).
    let e = ((bits >> 23) as i32 - 127) as f32;
    let m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000);
    let high = m > std::f32::consts::SQRT_2;
    let m = if high { 0.5 * m } else { m };
    let e = if high { e + 1.0 } else { e };
    // ln m = 2 atanh s, s = (m − 1)/(m + 1), |s| ≤ 0.1716: the series
    // 2(s + s³/3 + … + s¹³/13) leaves 2·0.1716¹⁵/15 < 5e-13.
    let m = f64::from(m);
    let s = (m - 1.0) / (m + 1.0);
    let z = s * s;
    let mut p = 1.0 / 13.0;
    for d in ODD_RECIPROCALS {
        p = p * z + d;
    }
    f64::from(e) + 2.0 * s * p * std::f64::consts::LOG2_E
}

/// 1/11, 1/9, …, 1/3, 1: the Horner steps after 1/13.
const ODD_RECIPROCALS: [f64; 6] = [1.0 / 11.0, 1.0 / 9.0, 1.0 / 7.0, 1.0 / 5.0, 1.0 / 3.0, 1.0];

/// log₂ t in f32 for a positive, normal, finite `t`, within 3e-7 plus an
/// ulp of the result (2e-7 relative in 2^result near 1): for the
/// adaptation grid's pooling, where twice the lanes matter more than
/// f64's digits.
#[inline(always)]
pub fn log2_f32(t: f32) -> f32 {
    let bits = t.to_bits();
    let e = ((bits >> 23) as i32 - 127) as f32;
    let m = f32::from_bits((bits & 0x007f_ffff) | 0x3f80_0000);
    let high = m > std::f32::consts::SQRT_2;
    let m = if high { 0.5 * m } else { m };
    let e = if high { e + 1.0 } else { e };
    // ln m = 2 atanh s, |s| ≤ 0.1716: to s⁹/9, leaving 2·0.1716¹¹/11 < 7e-10.
    let s = (m - 1.0) / (m + 1.0);
    let z = s * s;
    let p = (((z * (1.0 / 9.0) + 1.0 / 7.0) * z + 1.0 / 5.0) * z + 1.0 / 3.0) * z + 1.0;
    e + (2.0 * std::f32::consts::LOG2_E) * s * p
}

/// 2^y in f32 for y in [−126, 127] (clamped there; NaN stays NaN), within
/// 3e-7 relative.
#[inline(always)]
pub fn exp2_f32(y: f32) -> f32 {
    let y = if y < -126.0 { -126.0 } else { y };
    let y = if y > 127.0 { 127.0 } else { y };
    // y = k + f, |f| ≤ ½ (1.5·2²³ rounds an f32 below 2²² to an integer).
    const ROUND: f32 = 12_582_912.0;
    let r = y + ROUND;
    let k = r - ROUND;
    let x = (y - k) * std::f32::consts::LN_2;
    // e^x, |x| ≤ 0.347, Taylor to x⁷: 0.347⁸/8! < 6e-9.
    let p = ((((((x * (1.0 / 5040.0) + 1.0 / 720.0) * x + 1.0 / 120.0) * x + 1.0 / 24.0) * x
        + 1.0 / 6.0)
        * x
        + 0.5)
        * x
        + 1.0)
        * x
        + 1.0;
    // r's low mantissa bits hold k; k + 127 in the exponent field is 2^k.
    let scale = f32::from_bits(r.to_bits().wrapping_sub(ROUND.to_bits()).wrapping_add(127) << 23);
    p * scale
}

/// `t.powf(n)` for a positive, normal, finite f32 `t`: t^n through
/// [`log2`] and [`exp2`], rounded once to f32.
#[inline(always)]
pub fn powf(t: f32, n: f32) -> f32 {
    exp2(f64::from(n) * log2(t)) as f32
}

/// `x.exp()` in f32, through [`exp`], rounded once.
#[inline(always)]
pub fn expf(x: f32) -> f32 {
    exp(f64::from(x)) as f32
}

/// ∛x for any f64, within 4 ulps (relative error under 1e-15) of the
/// correctly rounded root; ±0, ±∞ and NaN come back as they are. The
/// reciprocal root r = x^(−1/3) starts from the exponent bits (the upper
/// 32 bits of x divided by three, subtracted from a constant, as musl's
/// `cbrt` starts: ~3 % off), takes two steps of r ← r (1 − d)^(−1/3),
/// d = 1 − x r³, the binomial series to d⁴ (error ~d⁵/8: 1e-7, then far
/// below an ulp), and ∛x = x r². No division, and only 32-bit integer
/// arithmetic, so a loop of them vectorises; subnormal and tiny x are
/// scaled by 2⁹⁰⁰ first.
#[inline(always)]
pub fn cbrt(x: f64) -> f64 {
    const TINY: f64 = 1e-250;
    const UP: f64 = 8.452_712_498_170_644e270; // 2⁹⁰⁰
    const DOWN: f64 = 4.909_093_465_297_727e-91; // 2⁻³⁰⁰ = ∛(2⁻⁹⁰⁰)
                                                 // (4/3)·(1023 << 20) less a tuning term: x^(−1/3)'s upper bits from
                                                 // x's, as in the well-known inverse-square-root trick.
    const MAGIC: u32 = 0x553E_F0FF;
    let a = x.abs();
    let tiny = a < TINY;
    let s = if tiny { a * UP } else { a };
    let high = (s.to_bits() >> 32) as u32;
    let r = f64::from_bits(u64::from(MAGIC.wrapping_sub(high / 3)) << 32);
    // First 1 + d/3 + 2d²/9 (error ~14d³/81: 1e-4), then the series to d⁴.
    let d = 1.0 - s * (r * r * r);
    let r = r + r * (d * (1.0 / 3.0 + d * (2.0 / 9.0)));
    let r = cbrt_step(r, s);
    let y = s * r * r;
    let y = if tiny { y * DOWN } else { y };
    // Zero, infinity and NaN pass through.
    let finite_nonzero = a > 0.0 && a < f64::INFINITY;
    if finite_nonzero {
        y.copysign(x)
    } else {
        x
    }
}

/// One step toward s^(−1/3) from r: r (1 − d)^(−1/3) with d = 1 − s r³,
/// the series 1 + d/3 + 2d²/9 + 14d³/81 + 35d⁴/243.
#[inline(always)]
fn cbrt_step(r: f64, s: f64) -> f64 {
    let d = 1.0 - s * (r * r * r);
    let p = 35.0 / 243.0;
    let p = p * d + 14.0 / 81.0;
    let p = p * d + 2.0 / 9.0;
    let p = p * d + 1.0 / 3.0;
    r + r * (d * p)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ulps between two positive f32s.
    fn ulps(a: f32, b: f32) -> u32 {
        a.to_bits().abs_diff(b.to_bits())
    }

    #[test]
    fn exp2_and_log2_are_exact_to_1e11() {
        for i in -4000..4000 {
            let y = i as f64 * 0.2371;
            let want = y.exp2();
            let rel = (exp2(y) / want - 1.0).abs();
            assert!(rel < 1e-11, "2^{y}: {} vs {want}", exp2(y));
        }
        for i in 0..20000 {
            let t = 10f32.powf(-3.0 + i as f32 * 0.0007);
            let want = f64::from(t).log2();
            assert!((log2(t) - want).abs() < 1e-12, "{t}");
        }
        assert!(exp2(f64::NAN).is_nan());
        assert_eq!(exp2(-5000.0), (-1000f64).exp2());
    }

    #[test]
    fn the_f32_log2_and_exp2_are_within_3e_7() {
        for i in 0..200_000 {
            let t = 10f32.powf(-30.0 + i as f32 * 3e-4);
            let want = f64::from(t).log2();
            let got = f64::from(log2_f32(t));
            let ulp = want.abs() * f64::from(f32::EPSILON);
            assert!((got - want).abs() < 3e-7 + ulp, "log2 {t}: {got} vs {want}");
        }
        for i in -125_900..127_000 {
            let y = i as f32 * 1e-3;
            let want = f64::from(y).exp2();
            let got = f64::from(exp2_f32(y));
            assert!((got / want - 1.0).abs() < 3e-7, "2^{y}: {got} vs {want}");
        }
        assert!(exp2_f32(f32::NAN).is_nan());
        assert_eq!(exp2_f32(-500.0), 2f32.powi(-126));
    }

    #[test]
    fn powf_and_expf_are_libms_within_an_ulp_and_usually_equal() {
        // The gains' range: adaptation 1e-3 to 1e9 cd/m², exponent 0.85.
        let (mut differ, mut n) = (0, 0);
        for i in 0..200_000 {
            let t = 10f32.powf(-3.0 + i as f32 * 6e-5);
            let (a, b) = (powf(t, 0.85), t.powf(0.85));
            assert!(ulps(a, b) <= 1, "{t}^0.85: {a} vs {b}");
            differ += (a != b) as usize;
            n += 1;
        }
        // The contrast roll-off's range: e^c for c in [−60, 0].
        for i in 0..200_000 {
            let x = -(i as f32) * 3e-4;
            let (a, b) = (expf(x), x.exp());
            assert!(ulps(a, b) <= 1, "e^{x}: {a} vs {b}");
            differ += (a != b) as usize;
            n += 1;
        }
        assert!(differ * 1000 < n, "{differ} of {n} differ from libm");
        // Far below f32's range the result is 0, as libm's.
        assert_eq!(expf(-200.0), 0.0);
    }

    #[test]
    fn cbrt_is_within_4_ulps_of_the_correctly_rounded_root() {
        let mut worst = 0;
        // 1e-320 (subnormal) to 1e300, ~70 000 values over all binades.
        let mut x = 1e-320f64;
        while x < 1e300 {
            for v in [x, x * 1.000_000_1, x * 1.234_567_8, x * 1.7, x * 1.999_9] {
                for v in [v, -v] {
                    let (a, b) = (cbrt(v), v.cbrt());
                    worst = worst.max(a.to_bits().abs_diff(b.to_bits()));
                }
            }
            x *= 1.01;
        }
        assert!(worst <= 4, "{worst} ulps");
        // Exact cubes too, and the special values come back as they are.
        for k in [1.0f64, 2.0, 3.0, 10.0, 0.5, 0.25] {
            assert!(cbrt(k * k * k).to_bits().abs_diff(k.to_bits()) <= 4, "{k}");
        }
        for v in [0.0, -0.0, f64::INFINITY, f64::NEG_INFINITY] {
            assert_eq!(cbrt(v).to_bits(), v.to_bits());
        }
        assert!(cbrt(f64::NAN).is_nan());
        assert!(cbrt(f64::MAX).to_bits().abs_diff(f64::MAX.cbrt().to_bits()) <= 4);
    }

    #[test]
    fn the_dispatched_loop_gives_the_scalar_bits() {
        let xs: Vec<f32> = (0..1000).map(|i| 1e-3 + i as f32 * 7.3).collect();
        let mut wide = vec![0.0f32; xs.len()];
        dispatch(|| {
            for (o, &x) in wide.iter_mut().zip(&xs) {
                *o = powf(x, 0.85) + expf(-x * 1e-2);
            }
        });
        for (o, &x) in wide.iter().zip(&xs) {
            assert_eq!(o.to_bits(), (powf(x, 0.85) + expf(-x * 1e-2)).to_bits());
        }
    }
}

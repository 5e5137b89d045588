//! Encoding display-referred linear RGB (1 = the display's peak white) into
//! code values: the sRGB transfer function at 8 bits with dithering or at
//! 16 bits, and Rec. 2100 PQ for HDR displays.

use rayon::prelude::*;
use scotopia_color::space::srgb_encode;

/// 8-bit sRGB with triangular (TPDF) dither of ±1 code value, so that dark
/// night gradients do not band. The noise is a hash of the pixel and
/// channel index: the same image always encodes to the same bytes.
pub fn srgb8(rgb: &[[f32; 3]]) -> Vec<u8> {
    // Written in place, a block of pixels per task (a flat_map collect
    // gathers per-task vectors and copies them again).
    const BLOCK: usize = 4096;
    let mut out = crate::resample::zeroed(3 * rgb.len());
    out.par_chunks_mut(3 * BLOCK)
        .zip(rgb.par_chunks(BLOCK))
        .enumerate()
        .for_each_init(
            || vec![false; 3 * BLOCK],
            |settled, (b, (out, px))| {
                let table = PowerTable::get();
                let samples = px.as_flattened();
                let k0 = 3 * b * BLOCK;
                let settled = &mut settled[..samples.len()];
                // The table's codes, a wide loop over the block; then the
                // samples it could not settle, one by one.
                crate::wide_math::dispatch(
                    #[inline(always)]
                    || table.codes(samples, k0, out, settled),
                );
                for (j, (o, &v)) in out.iter_mut().zip(samples).enumerate() {
                    if !settled[j] {
                        *o = code8(table, v.clamp(0.0, 1.0), k0 + j);
                    }
                }
            },
        );
    out
}

/// Sample `k`'s dithered 8-bit code of `linear` (in [0, 1]): always
/// `dithered8(srgb_encode_f32(linear) * 255.0, k)`, but above the knee
/// without the power function where the table's estimate decides the code.
fn code8(table: &PowerTable, linear: f32, k: usize) -> u8 {
    if linear > SRGB_KNEE {
        if let Some(code) = table.code(linear, k) {
            return code;
        }
    }
    dithered8(srgb_encode_f32(linear) * 255.0, k)
}

/// The 8-bit code of `v` (in code values, 0..=255) with sample `k`'s
/// triangular dither.
fn dithered8(v: f32, k: usize) -> u8 {
    let v = f64::from(v);
    // Pure black and peak white stay exact.
    if v <= 0.0 || v >= 255.0 {
        return v as u8;
    }
    round_code(v + dither(k))
}

/// Sample `k`'s triangular noise in (−1, 1).
#[inline(always)]
fn dither(k: usize) -> f64 {
    let k = k as u64;
    uniform(k, 0) + uniform(k, 1) - 1.0
}

/// Linear values above this take the power branch of the sRGB encoding.
const SRGB_KNEE: f32 = 0.003_130_8;

/// The power branch in code values, 255 (1.055 x^(1/2.4) − 0.055), at
/// 256 points per octave of x from 2^−9 (below the knee) to 1, for linear
/// interpolation: its error is under 1.3e-4 of a code (h²/8 |f''|), with
/// `srgb_encode_f32`'s f32 rounding under a fifth of `MARGIN` (tested), so a dithered
/// value farther than `MARGIN` from a rounding boundary rounds as the
/// exact one does — all but ~0.2 % of samples — and the rest are computed
/// exactly. The output is the same byte for byte; a power per sample was a
/// third of the encoding's time.
struct PowerTable {
    codes: Vec<f64>,
}

/// Segments per octave, as mantissa bits: 2^8.
const SEGMENT_SHIFT: u32 = 23 - 8;
/// The table's first point, 2^−9, as `f32` bits shifted to a segment index.
const FIRST_SEGMENT: u32 = (127 - 9) << 8;
/// The table's points: 256 per octave over 9 octaves, and both ends.
const TABLE_POINTS: usize = 9 * 256 + 2;
/// How close (in code values) to a rounding boundary the estimate may come.
const MARGIN: f64 = 1e-3;

impl PowerTable {
    fn get() -> &'static Self {
        static TABLE: std::sync::OnceLock<PowerTable> = std::sync::OnceLock::new();
        TABLE.get_or_init(|| Self {
            codes: (0..TABLE_POINTS as u32)
                .map(|i| {
                    let x = f64::from(f32::from_bits((FIRST_SEGMENT + i) << SEGMENT_SHIFT));
                    255.0 * (1.055 * x.powf(1.0 / 2.4) - 0.055)
                })
                .collect(),
        })
    }

    /// The interpolated code value of `linear` in (2^−9, 1], if in range.
    fn estimate(&self, linear: f32) -> Option<f64> {
        let bits = linear.to_bits();
        let i = ((bits >> SEGMENT_SHIFT).checked_sub(FIRST_SEGMENT))? as usize;
        let [a, b] = self.codes.get(i..i + 2)? else {
            return None;
        };
        let t = f64::from(bits & ((1 << SEGMENT_SHIFT) - 1)) / f64::from(1u32 << SEGMENT_SHIFT);
        Some(a + (b - a) * t)
    }

    /// [`PowerTable::code`] of every sample (`k0 + j` for sample j of
    /// `samples`, each clamped to [0, 1]) into `out`, `settled[j]` saying
    /// whether sample j's code is settled: the table's, or exact — at and
    /// below the knee (the line, in f32 as `srgb_encode_f32` computes it)
    /// and at peak white, where `dithered8`'s value is known without a
    /// power. Without branches, so the loop vectorises: the same
    /// arithmetic, each step taken for every sample and its outcome
    /// chosen by a select.
    #[inline(always)]
    fn codes(&self, samples: &[f32], k0: usize, out: &mut [u8], settled: &mut [bool]) {
        let n = samples.len();
        let (out, settled) = (&mut out[..n], &mut settled[..n]);
        let codes: &[f64; TABLE_POINTS] = match self.codes[..].try_into() {
            Ok(codes) => codes,
            Err(_) => return settled.fill(false),
        };
        let peak = f64::from(srgb_encode_f32(1.0) * 255.0);
        let last = TABLE_POINTS as i32 - 2;
        for j in 0..n {
            let linear = samples[j].clamp(0.0, 1.0);
            let bits = linear.to_bits();
            // (NaN's bits give a segment past the table: not settled.)
            let segment = (bits >> SEGMENT_SHIFT) as i32 - FIRST_SEGMENT as i32;
            let in_table = (segment >= 0) & (segment <= last);
            let i = segment.clamp(0, last) as usize;
            let (a, b) = (codes[i], codes[i + 1]);
            let t = f64::from(bits & ((1 << SEGMENT_SHIFT) - 1)) / f64::from(1u32 << SEGMENT_SHIFT);
            let below = linear <= SRGB_KNEE;
            let white = linear >= 1.0;
            let v = if below {
                f64::from(srgb_line_f32(linear) * 255.0)
            } else if white {
                peak
            } else {
                a + (b - a) * t
            };
            let x = v + dither(k0 + j);
            // −1 < x < 256: i32 holds it, and `as` truncates toward zero
            // as in `round_code`.
            let whole = x as i32;
            let fraction = x - f64::from(whole);
            let up = (fraction >= 0.5) as i32;
            let rounded = (whole + up).clamp(0, 255) as u8;
            // As `dithered8`: black and peak white exact.
            out[j] = if v <= 0.0 {
                0
            } else if v >= 255.0 {
                255
            } else {
                rounded
            };
            // (`&`, not `&&`: no branches.)
            settled[j] = below
                | white
                | (in_table & (v < 255.0 - MARGIN) & ((fraction - 0.5).abs() > MARGIN));
        }
    }

    /// Sample `k`'s code of `linear` (above the knee) when the estimate
    /// is far enough from a rounding boundary and from peak white.
    fn code(&self, linear: f32, k: usize) -> Option<u8> {
        let v = self.estimate(linear)?;
        if v >= 255.0 - MARGIN {
            return None;
        }
        // v > 10 above the knee, so x is positive and `as` truncates down.
        let x = v + dither(k);
        let fraction = x - (x as i64) as f64;
        ((fraction - 0.5).abs() > MARGIN).then(|| round_code(x))
    }
}

/// `x.round().clamp(0.0, 255.0) as u8` for x in (−1, 256) — a dithered
/// code — without a call to `round` (not inlined without SSE4.1): the
/// integer part by conversion and the fraction exactly, as x − ⌊x⌋ is
/// exact for these magnitudes.
fn round_code(x: f64) -> u8 {
    let whole = x as i64; // toward zero
    let up = (x - whole as f64 >= 0.5) as i64;
    (whole + up).clamp(0, 255) as u8
}

/// The sRGB transfer function (IEC 61966-2-1, as `srgb_encode`) in f32: the
/// pipeline's values are f32, and at 8 bits f32 arithmetic (a few 1e-5 of a
/// code) moves a dithered code by one in ~5 of a million samples (night
/// street, 1920×1080), for under half the time of the f64 power.
fn srgb_encode_f32(linear: f32) -> f32 {
    if linear <= SRGB_KNEE {
        srgb_line_f32(linear)
    } else {
        1.055 * linear.powf(1.0 / 2.4) - 0.055
    }
}

/// The sRGB transfer function's linear part, at and below the knee.
#[inline(always)]
fn srgb_line_f32(linear: f32) -> f32 {
    12.92 * linear
}

/// 16-bit sRGB (no dither needed at this depth).
pub fn srgb16(rgb: &[[f32; 3]]) -> Vec<u16> {
    rgb.par_iter()
        .flat_map_iter(|p| {
            p.map(|v| (srgb_encode(v.clamp(0.0, 1.0) as f64) * 65535.0).round() as u16)
        })
        .collect()
}

/// 16-bit PQ (SMPTE ST 2084 / ITU-R BT.2100) of display-relative linear
/// values shown at `peak` cd/m².
pub fn pq16(rgb: &[[f32; 3]], peak: f64) -> Vec<u16> {
    rgb.par_iter()
        .flat_map_iter(|p| {
            p.map(|v| (pq_encode(v.max(0.0) as f64 * peak) * 65535.0).round() as u16)
        })
        .collect()
}

/// The PQ inverse EOTF: absolute luminance (cd/m², up to 10 000) to a
/// signal in [0, 1]. Constants of SMPTE ST 2084:2014, eq. 5.2.
pub fn pq_encode(luminance: f64) -> f64 {
    const M1: f64 = 2610.0 / 16384.0;
    const M2: f64 = 2523.0 / 4096.0 * 128.0;
    const C1: f64 = 3424.0 / 4096.0;
    const C2: f64 = 2413.0 / 4096.0 * 32.0;
    const C3: f64 = 2392.0 / 4096.0 * 32.0;
    let y = (luminance / 10_000.0).clamp(0.0, 1.0).powf(M1);
    ((C1 + C2 * y) / (1.0 + C3 * y)).powf(M2)
}

/// A uniform number in [0, 1) from a counter (SplitMix64's finaliser).
#[inline(always)]
fn uniform(k: u64, stream: u64) -> f64 {
    let mut z = k
        .wrapping_mul(2)
        .wrapping_add(stream)
        .wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^= z >> 31;
    (z >> 11) as f64 / (1u64 << 53) as f64
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pq_matches_its_reference_points() {
        // ST 2084: 0 → 0, 10 000 cd/m² → 1, 100 cd/m² → 0.5081 (the
        // commonly tabulated code value 520/1023).
        assert!(pq_encode(0.0) < 1e-6);
        assert!((pq_encode(10_000.0) - 1.0).abs() < 1e-12);
        assert!((pq_encode(100.0) - 0.5081).abs() < 5e-4);
    }

    #[test]
    fn dithering_keeps_the_mean_and_varies_the_codes() {
        // A flat value between two codes encodes to both, averaging to it.
        let v = srgb_encode(0.2) * 255.0;
        let px = vec![[0.2f32; 3]; 4096];
        let codes = srgb8(&px);
        let mean = codes.iter().map(|&c| c as f64).sum::<f64>() / codes.len() as f64;
        assert!((mean - v).abs() < 0.05, "{mean} vs {v}");
        assert!(codes.iter().any(|&c| c != codes[0]));
        // Black and white stay exact.
        assert!(srgb8(&[[0.0; 3]]).iter().all(|&c| c == 0));
        assert!(srgb8(&[[1.0; 3]]).iter().all(|&c| c == 255));
    }

    #[test]
    fn the_f32_transfer_function_is_the_f64_one_to_a_few_ulp() {
        // Both branches and the knee; 2e-7 is ~3 ulp of f32 near 1 (5e-5
        // of an 8-bit code).
        for i in 0..=200_000 {
            let x = i as f32 / 200_000.0;
            let err = (f64::from(srgb_encode_f32(x)) - srgb_encode(f64::from(x))).abs();
            assert!(err < 2e-7, "{x}: {err}");
        }
    }

    #[test]
    fn the_table_estimates_the_f32_power_branch_within_a_fifth_of_its_margin() {
        let table = PowerTable::get();
        let start = SRGB_KNEE.to_bits() + 1;
        let mut worst: f64 = 0.0;
        // Every 7th f32 above the knee (10 million), and 1.0.
        for bits in (start..1.0f32.to_bits())
            .step_by(7)
            .chain([1.0f32.to_bits()])
        {
            let x = f32::from_bits(bits);
            let exact = f64::from(srgb_encode_f32(x) * 255.0);
            worst = worst.max((table.estimate(x).unwrap() - exact).abs());
        }
        assert!(worst < MARGIN / 5.0, "{worst}");
    }

    #[test]
    fn table_codes_are_the_exact_codes() {
        // Values spread over the whole range, each at many dither indices:
        // every code must be the power function's.
        let table = PowerTable::get();
        let (low, high) = (SRGB_KNEE.to_bits() - 16, 1.0f32.to_bits());
        let mut close = 0;
        for i in 0..400_000u32 {
            let x = f32::from_bits(low + i.wrapping_mul(0x9E37_79B9) % (high - low + 1));
            let k = (i as usize).wrapping_mul(7919);
            let exact = dithered8(srgb_encode_f32(x) * 255.0, k);
            assert_eq!(code8(table, x, k), exact, "{x} at {k}");
            close += usize::from(x > SRGB_KNEE && table.code(x, k).is_none());
        }
        // Few fall back to the power function (2 MARGIN of the samples).
        assert!(close < 400_000 / 100, "{close}");
    }

    #[test]
    fn srgb8_codes_are_dithered8_of_the_f32_transfer_function() {
        // The whole encoder, its wide loop included, against the
        // definition, sample by sample: black, white, out of range, NaN,
        // at and below the knee, and spread over the power branch.
        let mut values = vec![0.0f32, -0.0, 1.0, -0.5, 1.5, f32::NAN, SRGB_KNEE, 1e-30];
        values.extend((0..20_000).map(|i| i as f32 * 1.7e-7)); // below the knee
        values.extend((0..40_000).map(|i| (i as f32 * 0.618_034).fract()));
        values.extend((0..2_000).map(|i| 1.0 - i as f32 * 1e-7)); // near white
        values.resize(values.len().next_multiple_of(3), 0.3);
        let px: Vec<[f32; 3]> = values.chunks(3).map(|c| [c[0], c[1], c[2]]).collect();
        let codes = srgb8(&px);
        for (k, (&v, &c)) in values.iter().zip(&codes).enumerate() {
            let want = dithered8(srgb_encode_f32(v.clamp(0.0, 1.0)) * 255.0, k);
            assert_eq!(c, want, "{v} at {k}");
        }
    }

    #[test]
    fn code_rounding_is_round_and_clamp() {
        let mut x: f64 = -0.999_999;
        while x < 256.0 {
            for v in [x, x.next_up(), x.next_down()] {
                assert_eq!(round_code(v), v.round().clamp(0.0, 255.0) as u8, "{v}");
            }
            x += 0.001_953_125 / 3.0;
        }
        for v in [
            -0.5,
            -0.0,
            0.0,
            0.5,
            0.499_999_999_999_999_94,
            2.5,
            254.5,
            255.49,
            255.5,
        ] {
            assert_eq!(round_code(v), v.round().clamp(0.0, 255.0) as u8, "{v}");
        }
    }

    #[test]
    fn sixteen_bit_is_the_transfer_function() {
        let c = srgb16(&[[0.0, 0.5, 1.0]]);
        assert_eq!(c[0], 0);
        assert_eq!(c[2], 65535);
        assert!((c[1] as f64 / 65535.0 - srgb_encode(0.5)).abs() < 1e-5);
    }
}

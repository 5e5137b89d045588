//! Encoding display-referred linear RGB (1 = the display's peak white) into
//! code values: the sRGB transfer function at 8 bits with dithering or at
//! 16 bits, and Rec. 2100 PQ for HDR displays.

use rayon::prelude::*;
use scotopia_color::space::srgb_encode;

/// 8-bit sRGB with triangular (TPDF) dither of ±1 code value, so that dark
/// night gradients do not band. The noise is a hash of the pixel and
/// channel index: the same image always encodes to the same bytes.
pub fn srgb8(rgb: &[[f32; 3]]) -> Vec<u8> {
    rgb.par_iter()
        .enumerate()
        .flat_map_iter(|(i, p)| {
            (0..3).map(move |c| {
                let v = srgb_encode(p[c].clamp(0.0, 1.0) as f64) * 255.0;
                // Pure black and peak white stay exact.
                if v <= 0.0 || v >= 255.0 {
                    return v as u8;
                }
                let k = (3 * i + c) as u64;
                let noise = uniform(k, 0) + uniform(k, 1) - 1.0;
                (v + noise).round().clamp(0.0, 255.0) as u8
            })
        })
        .collect()
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
    fn sixteen_bit_is_the_transfer_function() {
        let c = srgb16(&[[0.0, 0.5, 1.0]]);
        assert_eq!(c[0], 0);
        assert_eq!(c[2], 65535);
        assert!((c[1] as f64 / 65535.0 - srgb_encode(0.5)).abs() < 1e-5);
    }
}

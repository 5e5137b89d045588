//! A quick look at an X, Y, Z image: auto-exposed linear sRGB, clipped and
//! encoded. Not the vision pipeline (`scotopia display`); just enough to
//! see what a render holds.

use scotopia_color::space::srgb_encode;
use scotopia_color::RgbSpace;

/// 8-bit sRGB pixels of row-major absolute X, Y, Z(, V′) values: exposed so
/// that the log-average luminance lands at 0.18 (Reinhard et al. 2002's
/// key value), converted to linear sRGB, clipped to [0, 1], encoded.
pub fn preview_srgb8(xyz: &[[f32; 4]]) -> Vec<u8> {
    let finite: Vec<f64> = xyz
        .iter()
        .map(|p| p[1] as f64)
        .filter(|y| y.is_finite() && *y > 0.0)
        .collect();
    let log_mean = if finite.is_empty() {
        0.0
    } else {
        finite.iter().map(|y| y.ln()).sum::<f64>() / finite.len() as f64
    };
    let scale = 0.18 / log_mean.exp();
    let space = RgbSpace::Srgb.def();
    xyz.iter()
        .flat_map(|p| {
            let rgb = space.xyz_to_rgb([
                p[0] as f64 * scale,
                p[1] as f64 * scale,
                p[2] as f64 * scale,
            ]);
            rgb.map(|v| {
                let v = if v.is_finite() {
                    v.clamp(0.0, 1.0)
                } else {
                    0.0
                };
                (srgb_encode(v) * 255.0 + 0.5) as u8
            })
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_key_grey_is_middle_grey_and_black_stays_black() {
        // D65 white at any absolute level maps to sRGB grey 0.18 (≈ 118).
        let white = RgbSpace::Srgb.def().white_xyz();
        let px = [[white[0] as f32 * 500.0, 500.0, white[2] as f32 * 500.0, 0.0]];
        let out = preview_srgb8(&px);
        for c in out {
            assert!((c as i32 - 118).abs() <= 1, "{c}");
        }
        assert_eq!(preview_srgb8(&[[0.0; 4], [f32::NAN; 4]]), vec![0; 6]);
    }
}

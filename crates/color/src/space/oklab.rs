//! Oklab and OkLCh (B. Ottosson, "A perceptual color space for image
//! processing", 2020): XYZ (D65, Y = 1 for white) → LMS → cube root → Lab.

use super::Mat3;

/// Ottosson 2020, M₁: XYZ (D65) → LMS.
const M1: Mat3 = Mat3([
    [0.8189330101, 0.3618667424, -0.1288597137],
    [0.0329845436, 0.9293118715, 0.0361456387],
    [0.0482003018, 0.2643662691, 0.6338517070],
]);
/// Ottosson 2020, M₂: cube-rooted LMS → Lab.
const M2: Mat3 = Mat3([
    [0.2104542553, 0.7936177850, -0.0040720468],
    [1.9779984951, -2.4285922050, 0.4505937099],
    [0.0259040371, 0.7827717662, -0.8086757660],
]);

/// XYZ (relative, D65 white at Y = 1) → Oklab.
pub fn xyz_to_oklab(xyz: [f64; 3]) -> [f64; 3] {
    M2.apply(M1.apply(xyz).map(f64::cbrt))
}

/// Oklab → XYZ (relative, D65).
pub fn oklab_to_xyz(lab: [f64; 3]) -> [f64; 3] {
    static INVERSES: std::sync::OnceLock<(Mat3, Mat3)> = std::sync::OnceLock::new();
    // The constant matrices are invertible; inverted once.
    let (m1_inv, m2_inv) = INVERSES.get_or_init(|| {
        (
            M1.inverse().expect("M1 is invertible"),
            M2.inverse().expect("M2 is invertible"),
        )
    });
    let lms = m2_inv.apply(lab).map(|v| v * v * v);
    m1_inv.apply(lms)
}

/// Oklab → OkLCh (h in degrees, [0, 360)).
pub fn oklab_to_oklch([l, a, b]: [f64; 3]) -> [f64; 3] {
    [l, a.hypot(b), b.atan2(a).to_degrees().rem_euclid(360.0)]
}

/// OkLCh → Oklab.
pub fn oklch_to_oklab([l, c, h]: [f64; 3]) -> [f64; 3] {
    let (s, co) = h.to_radians().sin_cos();
    [l, c * co, c * s]
}

/// ΔEOK: Euclidean distance in Oklab (CSS Color 4's gamut-mapping metric).
pub fn delta_e_ok(a: [f64; 3], b: [f64; 3]) -> f64 {
    ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ottosson_reference_values() {
        // Ottosson 2020, table of XYZ → Oklab test values (to 3 decimals).
        let cases = [
            ([0.950, 1.000, 1.089], [1.000, 0.000, 0.000]),
            ([1.000, 0.000, 0.000], [0.450, 1.236, -0.019]),
            ([0.000, 1.000, 0.000], [0.922, -0.671, 0.263]),
            ([0.000, 0.000, 1.000], [0.153, -1.415, -0.449]),
        ];
        for (xyz, lab) in cases {
            let got = xyz_to_oklab(xyz);
            for k in 0..3 {
                assert!((got[k] - lab[k]).abs() < 1.5e-3, "{xyz:?}: {got:?}");
            }
            let back = oklab_to_xyz(got);
            for k in 0..3 {
                assert!((back[k] - xyz[k]).abs() < 1e-9);
            }
        }
        let lch = oklab_to_oklch([0.5, 0.1, -0.1]);
        assert!((lch[2] - 315.0).abs() < 1e-9);
        let back = oklch_to_oklab(lch);
        assert!((back[1] - 0.1).abs() < 1e-12 && (back[2] + 0.1).abs() < 1e-12);
    }
}

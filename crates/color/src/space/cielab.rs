//! CIE 1976 L*a*b* and its cylindrical form, and xyY (CIE 015:2018 §8).

/// (6/29)³, the CIELAB linear-segment threshold (CIE 015:2018 eq. 8.3).
const EPSILON: f64 = 216.0 / 24389.0;
/// (29/3)³, the slope of the linear segment in L* (CIE 015:2018 eq. 8.3).
const KAPPA: f64 = 24389.0 / 27.0;

fn f(t: f64) -> f64 {
    if t > EPSILON {
        t.cbrt()
    } else {
        (KAPPA * t + 16.0) / 116.0
    }
}

fn f_inv(f: f64) -> f64 {
    let t = f * f * f;
    if t > EPSILON {
        t
    } else {
        (116.0 * f - 16.0) / KAPPA
    }
}

/// XYZ → L*a*b* relative to the white `white` (XYZ, same scale as `xyz`).
pub fn xyz_to_lab(xyz: [f64; 3], white: [f64; 3]) -> [f64; 3] {
    let [fx, fy, fz] = [0, 1, 2].map(|k| f(xyz[k] / white[k]));
    [116.0 * fy - 16.0, 500.0 * (fx - fy), 200.0 * (fy - fz)]
}

/// L*a*b* → XYZ relative to `white`.
pub fn lab_to_xyz([l, a, b]: [f64; 3], white: [f64; 3]) -> [f64; 3] {
    let fy = (l + 16.0) / 116.0;
    let fx = fy + a / 500.0;
    let fz = fy - b / 200.0;
    [
        f_inv(fx) * white[0],
        f_inv(fy) * white[1],
        f_inv(fz) * white[2],
    ]
}

/// L*a*b* → L*C*h (h in degrees, [0, 360)).
pub fn lab_to_lch([l, a, b]: [f64; 3]) -> [f64; 3] {
    [l, a.hypot(b), b.atan2(a).to_degrees().rem_euclid(360.0)]
}

/// L*C*h → L*a*b*.
pub fn lch_to_lab([l, c, h]: [f64; 3]) -> [f64; 3] {
    let (s, co) = h.to_radians().sin_cos();
    [l, c * co, c * s]
}

/// XYZ → xyY; black keeps the given fallback chromaticity.
pub fn xyz_to_xyy([x, y, z]: [f64; 3], black_xy: [f64; 2]) -> [f64; 3] {
    let s = x + y + z;
    if s <= 0.0 {
        return [black_xy[0], black_xy[1], 0.0];
    }
    [x / s, y / s, y]
}

/// xyY → XYZ.
pub fn xyy_to_xyz([x, y, big_y]: [f64; 3]) -> [f64; 3] {
    if y <= 0.0 {
        return [0.0; 3];
    }
    [x * big_y / y, big_y, (1.0 - x - y) * big_y / y]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trips_and_white() {
        let w = [0.95047, 1.0, 1.08883];
        assert_eq!(xyz_to_lab(w, w), [100.0, 0.0, 0.0]);
        for xyz in [[0.2, 0.3, 0.1], [0.001, 0.002, 0.0005], [0.9, 0.5, 1.2]] {
            let back = lab_to_xyz(xyz_to_lab(xyz, w), w);
            let xyy = xyy_to_xyz(xyz_to_xyy(xyz, [0.3, 0.3]));
            for k in 0..3 {
                assert!((back[k] - xyz[k]).abs() < 1e-12);
                assert!((xyy[k] - xyz[k]).abs() < 1e-12);
            }
        }
        let lab = [50.0, 20.0, -30.0];
        let back = lch_to_lab(lab_to_lch(lab));
        for k in 0..3 {
            assert!((back[k] - lab[k]).abs() < 1e-12);
        }
    }
}

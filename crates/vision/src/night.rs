//! The night-vision shift of Jensen et al. 2001 ("A Physically-Based Night
//! Sky Model", SIGGRAPH, §6; ../shared/vision-equations.md §3): as rods take
//! over, colours fade towards a blue-grey and brightness follows the rods'
//! response. With s the scotopic sensitivity (1 photopic, 0 scotopic):
//!
//!   x′ = (1−s)·0.25 + s·x,  y′ = (1−s)·0.25 + s·y,
//!   Y′ = 0.4468·(1−s)·V′ + s·Y,  X′ = x′Y′/y′,  Z′ = X′/x′ − X′ − Y′.
//!
//! (0.25, 0.25) is the chromaticity Jensen et al. give night vision (a
//! slightly blue grey: the "blue shift" painters use for moonlight); 0.4468
//! scales V′ to Y for an equal-energy spectrum's ratio as they state it.

/// Chromaticity scotopic vision is shifted towards (Jensen et al. 2001).
pub const NIGHT_CHROMATICITY: [f64; 2] = [0.25, 0.25];
/// Y per unit V′ in the shifted luminance (Jensen et al. 2001).
pub const V_TO_Y: f64 = 0.4468;

/// Shifts one pixel [X, Y, Z, V′] by scotopic sensitivity `s`, returning
/// X′, Y′, Z′. V′ must be on the same scale as Y (scene or display).
pub fn night_shift([x, y, z, v]: [f64; 4], s: f64) -> [f64; 3] {
    let s = s.clamp(0.0, 1.0);
    if s >= 1.0 {
        return [x, y, z];
    }
    let sum = x + y + z;
    // Black (or a negative sum from noise) has no chromaticity: the
    // night point's.
    let [cx, cy] = if sum > 0.0 {
        [x / sum, y / sum]
    } else {
        NIGHT_CHROMATICITY
    };
    let xs = (1.0 - s) * NIGHT_CHROMATICITY[0] + s * cx;
    let ys = (1.0 - s) * NIGHT_CHROMATICITY[1] + s * cy;
    let big_y = V_TO_Y * (1.0 - s) * v.max(0.0) + s * y;
    if ys <= 0.0 {
        return [0.0, big_y, 0.0];
    }
    let big_x = xs * big_y / ys;
    let big_z = (1.0 - xs - ys) * big_y / ys;
    [big_x, big_y, big_z]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn photopic_is_unchanged_and_scotopic_is_the_night_point() {
        let px = [0.3, 0.2, 0.5, 0.7];
        assert_eq!(night_shift(px, 1.0), [0.3, 0.2, 0.5]);
        let [x, y, z] = night_shift(px, 0.0);
        assert!((y - 0.4468 * 0.7).abs() < 1e-12);
        let sum = x + y + z;
        assert!((x / sum - 0.25).abs() < 1e-12 && (y / sum - 0.25).abs() < 1e-12);
        // Between, chromaticity and luminance move linearly in s.
        let [x, y, z] = night_shift(px, 0.5);
        let sum = x + y + z;
        assert!((y - (0.5 * 0.4468 * 0.7 + 0.5 * 0.2)).abs() < 1e-12);
        assert!((x / sum - (0.125 + 0.5 * 0.3)).abs() < 1e-12);
        assert_eq!(night_shift([0.0; 4], 0.3), [0.0, 0.0, 0.0]);
    }
}

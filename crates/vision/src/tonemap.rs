//! The simple tone operators that stand beside the multiscale model for
//! comparison (`--tonemap exposure | reinhard`). Both map absolute
//! luminance to display luminance relative to the display's peak (1 =
//! peak white), scaling X, Y, Z (and V′) of a pixel by one factor, so
//! chromaticity is kept.

/// Linear exposure: the adaptation luminance `adapt` lands at 18 % of the
/// display peak (a mid-grey key), everything else scaled alike.
pub fn exposure_scale(adapt: f64) -> f64 {
    if adapt > 0.0 {
        0.18 / adapt
    } else {
        1.0
    }
}

/// Reinhard et al. 2002 ("Photographic Tone Reproduction for Digital
/// Images", SIGGRAPH, eqs. 2 and 4): L = a·Y / L̄ (key a = 0.18, L̄ the
/// log-average luminance), L_d = L (1 + L / L_white²) / (1 + L), with
/// L_white the scaled luminance that maps to peak white (the scene's
/// maximum). Returns the factor L_d / Y for a pixel of luminance `y`.
pub fn reinhard_scale(y: f64, log_average: f64, maximum: f64) -> f64 {
    const KEY: f64 = 0.18;
    if !(y > 0.0 && log_average > 0.0) {
        return 0.0;
    }
    let l = KEY * y / log_average;
    let white = (KEY * maximum / log_average).max(1e-9);
    let ld = l * (1.0 + l / (white * white)) / (1.0 + l);
    ld / y
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn reinhard_maps_the_maximum_to_white_and_compresses() {
        let (avg, max) = (2.0, 500.0);
        assert!((reinhard_scale(max, avg, max) * max - 1.0).abs() < 1e-12);
        // Monotonic, below white, and compressive: 10× the luminance gives
        // far less than 10× the display value at high levels.
        let d = |y: f64| reinhard_scale(y, avg, max) * y;
        assert!(d(1.0) < d(10.0) && d(10.0) < d(100.0) && d(100.0) < 1.0);
        assert!(d(100.0) / d(10.0) < 3.0);
        assert!((exposure_scale(avg) * avg - 0.18).abs() < 1e-12);
    }
}

//! Loss of visual acuity in the dark: the finest grating the eye resolves
//! falls from ~50 cycles/degree in daylight to a few under starlight.
//! Neither implementation of Jensen et al. 2001 read for this project has a
//! blur (../shared/vision-equations.md §3), so scotopia's is documented in
//! docs/vision.md: a Gaussian that removes what the scene's viewer could
//! not resolve but the display's viewer could.

use rayon::prelude::*;

/// The highest resolvable spatial frequency (cycles/degree) at adaptation
/// luminance `la` (cd/m²): ω = 17.25·atan(1.4·log₁₀ La + 0.35) + 25.72, Ward
/// Larson, Rushmeier & Piatko 1997 (IEEE TVCG 3(4), §5, a fit to Shaler
/// 1937's acuity data; constants from the paper as quoted in the tone
/// mapping literature, unverified here).
pub fn acuity_cpd(la: f64) -> f64 {
    let l = la.max(1e-6).log10();
    17.25 * (1.4 * l + 0.35).atan() + 25.72
}

/// The standard deviation (degrees) of a Gaussian whose modulation
/// transfer is ½ at `cpd`: exp(−2π²σ²f²) = ½ → σ = √(ln 2 / 2) / (π f).
pub fn sigma_for_cpd(cpd: f64) -> f64 {
    (std::f64::consts::LN_2 / 2.0).sqrt() / (std::f64::consts::PI * cpd)
}

/// The blur (σ in degrees) that brings the display viewer's acuity (at the
/// display's adaptation `la_display`) down to the scene viewer's (at
/// `la_scene`): zero when the scene is at least as bright.
pub fn scotopic_blur_degrees(la_scene: f64, la_display: f64) -> f64 {
    let scene = sigma_for_cpd(acuity_cpd(la_scene));
    let display = sigma_for_cpd(acuity_cpd(la_display));
    (scene * scene - display * display).max(0.0).sqrt()
}

/// Blurs `pixels` (4 channels, row-major) with a Gaussian of `sigma`
/// pixels, separably, edges clamped. Below 0.3 pixels nothing visible
/// would change, so the image is left alone.
pub fn gaussian_blur(pixels: &mut [[f32; 4]], width: usize, height: usize, sigma: f64) {
    if sigma.is_nan() || sigma < 0.3 || width == 0 || height == 0 {
        return;
    }
    let radius = (3.0 * sigma).ceil() as i64;
    let mut taps: Vec<f32> = (-radius..=radius)
        .map(|d| (-(d * d) as f64 / (2.0 * sigma * sigma)).exp() as f32)
        .collect();
    let total: f32 = taps.iter().sum();
    taps.iter_mut().for_each(|t| *t /= total);
    let pass = |src: &[[f32; 4]], out: &mut [[f32; 4]], horizontal: bool| {
        out.par_chunks_mut(width).enumerate().for_each(|(y, row)| {
            for (x, o) in row.iter_mut().enumerate() {
                let mut acc = [0.0f32; 4];
                for (k, t) in taps.iter().enumerate() {
                    let d = k as i64 - radius;
                    let (sx, sy) = if horizontal {
                        ((x as i64 + d).clamp(0, width as i64 - 1) as usize, y)
                    } else {
                        (x, (y as i64 + d).clamp(0, height as i64 - 1) as usize)
                    };
                    let p = src[sy * width + sx];
                    for c in 0..4 {
                        acc[c] += t * p[c];
                    }
                }
                *o = acc;
            }
        });
    };
    let mut tmp = vec![[0.0f32; 4]; pixels.len()];
    pass(pixels, &mut tmp, true);
    pass(&tmp, pixels, false);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn acuity_falls_with_light_as_shalers_data() {
        // ≈ 47 cycles/degree at 100 cd/m², a few under starlight.
        assert!((acuity_cpd(100.0) - 47.5).abs() < 1.0);
        assert!(acuity_cpd(1e-3) < 5.0);
        let mut last = 0.0;
        for e in -5..5 {
            let a = acuity_cpd(10f64.powi(e));
            assert!(a > last);
            last = a;
        }
    }

    #[test]
    fn the_blur_grows_as_light_falls_and_vanishes_in_daylight() {
        assert_eq!(scotopic_blur_degrees(500.0, 50.0), 0.0);
        let dusk = scotopic_blur_degrees(0.1, 50.0);
        let night = scotopic_blur_degrees(0.001, 50.0);
        assert!(dusk > 0.0 && night > 2.0 * dusk, "{dusk} {night}");
        // The blur's MTF at the scene's acuity limit, with the display
        // viewer's own, is ½: σ² adds.
        let f = acuity_cpd(0.001);
        let total = night.hypot(sigma_for_cpd(acuity_cpd(50.0)));
        let mtf = (-2.0 * std::f64::consts::PI.powi(2) * total * total * f * f).exp();
        assert!((mtf - 0.5).abs() < 1e-9);
    }

    #[test]
    fn blurring_keeps_the_sum_and_spreads_a_point() {
        let (w, h) = (21, 21);
        let mut px = vec![[0.0f32; 4]; w * h];
        px[10 * w + 10] = [1.0, 2.0, 3.0, 4.0];
        gaussian_blur(&mut px, w, h, 1.5);
        let sum: f32 = px.iter().map(|p| p[1]).sum();
        assert!((sum - 2.0).abs() < 1e-4);
        assert!(px[10 * w + 10][1] < 0.2 && px[10 * w + 12][1] > 0.0);
    }
}

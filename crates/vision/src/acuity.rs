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

/// The widest blur `gaussian_blur` applies, pixels: wider ones are
/// clamped to it (callers reject them first: the display pipeline's blur
/// stays below 0.25° / `MIN_DEGREES_PER_PIXEL` = 2,500 pixels, and the
/// Python binding refuses more).
pub const MAX_BLUR_SIGMA: f64 = 1e5;

/// The finest visual angle of a pixel the vision pipeline accepts,
/// degrees: 0.36″, a hundredth of the finest detail the eye resolves
/// (≈ 60 cycles/degree, i.e. 30″ per line pair). Below it every pixel is
/// far under one cone and the acuity blur spans thousands of pixels.
pub const MIN_DEGREES_PER_PIXEL: f64 = 1e-4;

/// The visual angle of one pixel of an image `width` pixels wide seen
/// over a horizontal field of view `fov` degrees; an error (to be prefixed
/// with where `fov` came from) unless 0 < fov < 360 and a pixel spans at
/// least `MIN_DEGREES_PER_PIXEL`.
pub fn degrees_per_pixel(fov: f64, width: usize) -> Result<f64, String> {
    // Tiny and huge values in exponent form (1e-10, not 0.0000000001).
    let shown = if fov != 0.0 && !(1e-3..1e6).contains(&fov.abs()) {
        format!("{fov:e}")
    } else {
        format!("{fov}")
    };
    if !(fov.is_finite() && fov > 0.0 && fov < 360.0) {
        return Err(format!("{shown}: must be between 0 and 360 degrees"));
    }
    let dpp = fov / width.max(1) as f64;
    if dpp < MIN_DEGREES_PER_PIXEL {
        return Err(format!(
            "{shown}: over {width} pixels, a pixel would span {dpp:e}°; the vision model needs at least {MIN_DEGREES_PER_PIXEL}° per pixel (a field of view of at least {}°)",
            MIN_DEGREES_PER_PIXEL * width.max(1) as f64
        ));
    }
    Ok(dpp)
}

/// Blurs `pixels` (4 channels, row-major) with a Gaussian of `sigma`
/// pixels (at most `MAX_BLUR_SIGMA`), separably, edges clamped. Below 0.3
/// pixels nothing visible would change, so the image is left alone. The
/// taps that fall beyond an edge are summed onto the edge pixel, so a
/// pass costs at most one multiply per pixel of the row, however wide
/// the blur.
pub fn gaussian_blur(pixels: &mut [[f32; 4]], width: usize, height: usize, sigma: f64) {
    if sigma.is_nan() || sigma < 0.3 || width == 0 || height == 0 {
        return;
    }
    let sigma = sigma.min(MAX_BLUR_SIGMA);
    let radius = (3.0 * sigma).ceil() as i64;
    let taps: Vec<f64> = (-radius..=radius)
        .map(|d| (-(d * d) as f64 / (2.0 * sigma * sigma)).exp())
        .collect();
    // prefix[k] = the sum of taps[..k], normalised.
    let mut prefix = Vec::with_capacity(taps.len() + 1);
    prefix.push(0.0f64);
    for t in &taps {
        prefix.push(prefix.last().copied().unwrap_or(0.0) + t);
    }
    let total = prefix.last().copied().unwrap_or(1.0);
    let weight = |k: i64| (taps[k as usize] / total) as f32;
    // The weights pixel `x` of an `n`-long axis gives sources 0, 1..n-1
    // and n-1: interior taps at their offset, edges the taps beyond them.
    let edge_weights = |x: i64, n: i64| -> (f32, f32) {
        if n == 1 {
            return (1.0, 0.0);
        }
        let low = (radius - x).clamp(-1, 2 * radius) + 1; // taps with x + d ≤ 0
        let high = (radius + n - 1 - x).clamp(0, 2 * radius + 1); // x + d ≥ n-1
        (
            (prefix[low as usize] / total) as f32,
            ((total - prefix[high as usize]) / total) as f32,
        )
    };
    let pass = |src: &[[f32; 4]], out: &mut [[f32; 4]], horizontal: bool| {
        let n = if horizontal { width } else { height } as i64;
        out.par_chunks_mut(width).enumerate().for_each(|(y, row)| {
            for (x, o) in row.iter_mut().enumerate() {
                let at = |i: i64| {
                    if horizontal {
                        src[y * width + i as usize]
                    } else {
                        src[i as usize * width + x]
                    }
                };
                let pos = if horizontal { x } else { y } as i64;
                let (w0, w1) = edge_weights(pos, n);
                let mut acc = [0.0f32; 4];
                let mut add = |p: [f32; 4], t: f32| {
                    for c in 0..4 {
                        acc[c] += t * p[c];
                    }
                };
                add(at(0), w0);
                for i in (pos - radius).max(1)..=(pos + radius).min(n - 2) {
                    add(at(i), weight(i - pos + radius));
                }
                if n > 1 {
                    add(at(n - 1), w1);
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

    /// The blur as it was written first: every tap, edges clamped.
    fn blur_by_every_tap(px: &[[f32; 4]], w: usize, h: usize, sigma: f64) -> Vec<[f32; 4]> {
        let r = (3.0 * sigma).ceil() as i64;
        let t: Vec<f64> = (-r..=r)
            .map(|d| (-(d * d) as f64 / (2.0 * sigma * sigma)).exp())
            .collect();
        let z: f64 = t.iter().sum();
        let mut tmp = vec![[0.0f32; 4]; w * h];
        let mut out = vec![[0.0f32; 4]; w * h];
        for y in 0..h {
            for x in 0..w {
                for (k, tk) in t.iter().enumerate() {
                    let sx = (x as i64 + k as i64 - r).clamp(0, w as i64 - 1) as usize;
                    for c in 0..4 {
                        tmp[y * w + x][c] += (tk / z) as f32 * px[y * w + sx][c];
                    }
                }
            }
        }
        for y in 0..h {
            for x in 0..w {
                for (k, tk) in t.iter().enumerate() {
                    let sy = (y as i64 + k as i64 - r).clamp(0, h as i64 - 1) as usize;
                    for c in 0..4 {
                        out[y * w + x][c] += (tk / z) as f32 * tmp[sy * w + x][c];
                    }
                }
            }
        }
        out
    }

    #[test]
    fn folding_the_taps_beyond_the_edges_changes_nothing() {
        let (w, h) = (9, 5);
        let px: Vec<[f32; 4]> = (0..w * h)
            .map(|i| [i as f32, (i * 7 % 11) as f32, 1.0, (i % 3) as f32])
            .collect();
        for sigma in [0.7, 1.5, 4.0, 40.0] {
            let mut fast = px.clone();
            gaussian_blur(&mut fast, w, h, sigma);
            let slow = blur_by_every_tap(&px, w, h, sigma);
            for (a, b) in fast.iter().zip(&slow) {
                for c in 0..4 {
                    assert!(
                        (a[c] - b[c]).abs() < 1e-4 * (1.0 + b[c].abs()),
                        "σ {sigma}: {a:?} {b:?}"
                    );
                }
            }
        }
        // A one-pixel-wide image keeps its values.
        let mut one = vec![[2.0f32; 4]; 3];
        gaussian_blur(&mut one, 1, 3, 5.0);
        assert!(one.iter().all(|p| (p[0] - 2.0).abs() < 1e-6));
    }

    #[test]
    fn absurd_blurs_and_fields_of_view_are_bounded() {
        // An infinite σ is clamped, not a panic, and costs one image width.
        let mut px = vec![[1.0f32; 4]; 64 * 64];
        gaussian_blur(&mut px, 64, 64, f64::INFINITY);
        assert!(px.iter().all(|p| (p[0] - 1.0).abs() < 1e-3), "{:?}", px[0]);
        assert_eq!(degrees_per_pixel(40.0, 1000), Ok(0.04));
        for fov in [1e-10, 1e-30, 1e-6] {
            let e = degrees_per_pixel(fov, 64).unwrap_err();
            assert!(e.contains("at least 0.0001° per pixel"), "{e}");
        }
        for fov in [0.0, -1.0, 360.0, f64::NAN, f64::INFINITY] {
            assert!(degrees_per_pixel(fov, 64)
                .unwrap_err()
                .contains("between 0 and 360"));
        }
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

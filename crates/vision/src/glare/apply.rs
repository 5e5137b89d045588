//! Applying the glare PSF: only the light a display cannot show glares
//! (Spencer et al. 1995, §5): a pixel brighter than the display's maximum
//! keeps that maximum and its excess is spread by the PSF, convolved by
//! FFT with zero padding, one PSF per channel (the halo differs).

use rustfft::num_complex::Complex32;
use rustfft::FftDirection;

use super::fft2::fft2;
use super::psf::{scatter, weights, Halo};
use crate::pyramid::{expand, Plane};
use rayon::prelude::*;

/// How the glare is applied.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlareParams {
    /// Visual angle of one pixel, degrees.
    pub degrees_per_pixel: f64,
    /// Scotopic sensitivity s (1 photopic, 0 scotopic): the PSF's mixture.
    pub s: f64,
    /// The largest luminance (Y, cd/m²) the display reproduces at this
    /// image's exposure; light above it glares.
    pub threshold: f64,
}

/// Pixels within this distance of the PSF's centre (in pixels) are
/// integrated over their area (the core is 0.02° wide, often sub-pixel).
const SUPERSAMPLED_RADIUS: i64 = 4;
const SUBSAMPLES: usize = 8;

/// `f` of the visual angle (degrees) on a `pw` × `ph` grid centred at
/// (0, 0) and wrapped, each pixel near the centre averaged over its area.
fn grid(pw: usize, ph: usize, degrees_per_pixel: f64, f: impl Fn(f64) -> f64) -> Vec<f64> {
    let signed = |i: usize, n: usize| {
        if i <= n / 2 {
            i as i64
        } else {
            i as i64 - n as i64
        }
    };
    let at = |x: f64, y: f64| f(x.hypot(y) * degrees_per_pixel);
    let n = SUBSAMPLES as f64;
    let mut k = vec![0.0f64; pw * ph];
    for j in 0..ph {
        let dy = signed(j, ph);
        for i in 0..pw {
            let dx = signed(i, pw);
            k[j * pw + i] = if dx.abs() <= SUPERSAMPLED_RADIUS && dy.abs() <= SUPERSAMPLED_RADIUS {
                let mut sum = 0.0;
                for sy in 0..SUBSAMPLES {
                    for sx in 0..SUBSAMPLES {
                        let ox = (sx as f64 + 0.5) / n - 0.5;
                        let oy = (sy as f64 + 0.5) / n - 0.5;
                        sum += at(dx as f64 + ox, dy as f64 + oy);
                    }
                }
                sum / (n * n)
            } else {
                at(dx as f64, dy as f64)
            };
        }
    }
    k
}

/// The PSF on a `pw` × `ph` grid, normalised to sum 1: one kernel when the
/// halo has no weight (every channel alike), else one per channel (the
/// shared scatter computed once, each channel's halo added to it).
fn kernels(p: &GlareParams, pw: usize, ph: usize) -> Vec<Vec<f32>> {
    let w = weights(p.s);
    let normalised = |k: Vec<f64>| {
        let total: f64 = k.iter().sum();
        k.iter().map(|v| (v / total) as f32).collect::<Vec<f32>>()
    };
    let shared = grid(pw, ph, p.degrees_per_pixel, |t| scatter(t, &w));
    if w[3] == 0.0 {
        return vec![normalised(shared)];
    }
    let halo = Halo::new();
    (0..4)
        .map(|c| {
            let ring = grid(pw, ph, p.degrees_per_pixel, |t| w[3] * halo.eval(c, t));
            normalised(shared.iter().zip(ring).map(|(a, b)| a + b).collect())
        })
        .collect()
}

/// Adds glare to `pixels` ([X, Y, Z, V′], row-major, `width` × `height`)
/// in place. Returns whether any pixel exceeded the threshold.
pub fn apply_glare(pixels: &mut [[f32; 4]], width: usize, height: usize, p: &GlareParams) -> bool {
    // Split each pixel into what the display shows and the excess, by the
    // same factor on all channels so the excess keeps the pixel's colour.
    let excess: Vec<[f32; 4]> = pixels
        .iter_mut()
        .map(|px| {
            let y = px[1] as f64;
            if y > p.threshold && y.is_finite() {
                let f = ((y - p.threshold) / y) as f32;
                let e = px.map(|v| v * f);
                for c in 0..4 {
                    px[c] -= e[c];
                }
                e
            } else {
                [0.0; 4]
            }
        })
        .collect();
    if excess.iter().all(|e| e[1] == 0.0) {
        return false;
    }
    // The PSF beyond its central pixel is smooth, so on large images it is
    // convolved on a grid coarser by `f` (block sums of the excess, so
    // nothing is lost) and brought back bilinearly; the share of the PSF
    // inside the central coarse cell stays where it fell, at full
    // resolution, so lamps keep their sharp core.
    let f = coarse_factor(width, height);
    let (cw, ch) = (width.div_ceil(f), height.div_ceil(f));
    let mut coarse = vec![[0.0f32; 4]; cw * ch];
    for (i, e) in excess.iter().enumerate() {
        let (x, y) = (i % width, i / width);
        let cell = &mut coarse[(y / f) * cw + x / f];
        for c in 0..4 {
            cell[c] += e[c];
        }
    }
    let cp = GlareParams {
        degrees_per_pixel: p.degrees_per_pixel * f as f64,
        ..*p
    };
    // Padding to twice the image keeps the circular convolution from
    // wrapping light from one edge onto the other.
    let (pw, ph) = (2 * cw, 2 * ch);
    let mut kernels = kernels(&cp, pw, ph);
    let kept: Vec<f32> = kernels
        .iter_mut()
        .map(|k| {
            if f > 1 {
                std::mem::take(&mut k[0])
            } else {
                0.0
            }
        })
        .collect();
    let spectra: Vec<Vec<Complex32>> = kernels
        .into_iter()
        .map(|kernel| {
            let mut k: Vec<Complex32> = kernel.iter().map(|&v| Complex32::new(v, 0.0)).collect();
            fft2(&mut k, pw, ph, FftDirection::Forward);
            k
        })
        .collect();
    let scale = 1.0 / (pw * ph * f * f) as f32;
    for c in 0..4 {
        let which = c.min(spectra.len() - 1);
        let mut img = vec![Complex32::new(0.0, 0.0); pw * ph];
        for y in 0..ch {
            for x in 0..cw {
                img[y * pw + x].re = coarse[y * cw + x][c];
            }
        }
        fft2(&mut img, pw, ph, FftDirection::Forward);
        for (a, b) in img.iter_mut().zip(&spectra[which]) {
            *a *= b;
        }
        fft2(&mut img, pw, ph, FftDirection::Inverse);
        let glare = Plane::new(
            cw,
            ch,
            (0..cw * ch)
                .map(|i| img[(i / cw) * pw + i % cw].re * scale)
                .collect(),
        );
        let glare = if f > 1 {
            expand(&glare, width, height)
        } else {
            glare
        };
        pixels.par_iter_mut().enumerate().for_each(|(i, px)| {
            px[c] += glare.data[i] + kept[which] * excess[i][c];
        });
    }
    true
}

/// The coarsening of the glare grid: 1 up to about 130 000 pixels, then
/// the smallest factor that brings the image under it (full HD: 4, so a
/// coarse cell is 0.12° at a 60° field of view).
fn coarse_factor(width: usize, height: usize) -> usize {
    const MAX_PIXELS: f64 = 2.0 * 256.0 * 256.0;
    ((width * height) as f64 / MAX_PIXELS)
        .sqrt()
        .ceil()
        .max(1.0) as usize
}

#[cfg(test)]
mod tests {
    use super::*;

    fn params() -> GlareParams {
        GlareParams {
            degrees_per_pixel: 0.05,
            s: 1.0,
            threshold: 100.0,
        }
    }

    #[test]
    fn an_image_the_display_can_show_is_unchanged() {
        let mut px = vec![[50.0, 60.0, 70.0, 80.0]; 32 * 24];
        let before = px.clone();
        assert!(!apply_glare(&mut px, 32, 24, &params()));
        assert_eq!(px, before);
    }

    #[test]
    fn a_bright_point_spreads_and_luminance_is_conserved() {
        // A lamp in the centre of a dark image wide enough (256 × 256
        // pixels of 0.5°: ±64°) to hold nearly all of the PSF, whose bloom
        // falls only as 1/θ².
        let (w, h) = (256, 256);
        let c = 128;
        let mut px = vec![[0.0f32; 4]; w * h];
        px[c * w + c] = [9.0e5, 1.0e6, 8.0e5, 2.0e6];
        let total_before: f64 = px.iter().map(|p| p[1] as f64).sum();
        let p = GlareParams {
            degrees_per_pixel: 0.5,
            ..params()
        };
        assert!(apply_glare(&mut px, w, h, &p));
        let total_after: f64 = px.iter().map(|p| p[1] as f64).sum();
        assert!(
            (total_after / total_before - 1.0).abs() < 0.01,
            "{total_after} vs {total_before}"
        );
        // Light reaches pixels far from the lamp, falling with distance.
        let at = |d: usize| px[c * w + c + d][1];
        assert!(at(2) > at(8) && at(8) > at(30) && at(30) > 0.0);
    }

    #[test]
    fn the_coarse_grid_conserves_light_and_keeps_the_core_sharp() {
        // 1024² pixels of 0.125° (±64°): glare is convolved on a 3× coarser
        // grid; the total is still conserved and the lamp stays a point.
        let (w, h) = (1024, 1024);
        assert_eq!(coarse_factor(w, h), 3);
        let c = 512;
        let mut px = vec![[0.0f32; 4]; w * h];
        px[c * w + c] = [9.0e5, 1.0e6, 8.0e5, 2.0e6];
        let p = GlareParams {
            degrees_per_pixel: 0.125,
            ..params()
        };
        assert!(apply_glare(&mut px, w, h, &p));
        let total: f64 = px.iter().map(|p| p[1] as f64).sum();
        assert!((total / 1.0e6 - 1.0).abs() < 0.01, "{total}");
        let at = |d: usize| px[c * w + c + d][1];
        assert!(at(0) > 10.0 * at(1), "{} {}", at(0), at(1));
        assert!(at(3) > at(12) && at(12) > at(60) && at(60) > 0.0);
    }

    #[test]
    fn the_scotopic_halo_is_red_outside_blue_inside() {
        // A white (X = Z) lamp at 0.1° per pixel: around the 3° ring the
        // glare is redder (X/Z higher) at 3.4° than at 2.2°. Photopic
        // vision has no halo term, so there the ratio stays 1.
        let (w, h) = (128, 128);
        let c = 64;
        let lamp = [1.0e6, 1.0e6, 1.0e6, 1.0e6];
        let ratio = |s: f64, r: usize| {
            let mut px = vec![[0.0f32; 4]; w * h];
            px[c * w + c] = lamp;
            let p = GlareParams {
                degrees_per_pixel: 0.1,
                s,
                threshold: 1.0,
            };
            apply_glare(&mut px, w, h, &p);
            let q = px[c * w + c + r];
            q[0] / q[2]
        };
        assert!(
            ratio(0.0, 34) > 1.02 * ratio(0.0, 22),
            "{} {}",
            ratio(0.0, 34),
            ratio(0.0, 22)
        );
        assert!((ratio(1.0, 34) - 1.0).abs() < 1e-3 && (ratio(1.0, 22) - 1.0).abs() < 1e-3);
    }
}

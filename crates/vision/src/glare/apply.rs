//! Applying the glare PSF: only the light a display cannot show glares
//! (Spencer et al. 1995, §5): a pixel brighter than the display's maximum
//! keeps that maximum and its excess is spread by the PSF, convolved by
//! FFT with zero padding, one PSF per channel (the halo differs).

use rayon::prelude::*;
use rustfft::num_complex::Complex32;

use super::fft2::{smooth_size, Fft2};
use super::kernel::KernelSpectra;
use crate::pyramid::Bilinear;

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

/// Adds glare to `pixels` ([X, Y, Z, V′], row-major, `width` × `height`)
/// in place. Returns whether any pixel exceeded the threshold.
pub fn apply_glare(pixels: &mut [[f32; 4]], width: usize, height: usize, p: &GlareParams) -> bool {
    // Split each pixel into what the display shows and the excess, by the
    // same factor on all channels so the excess keeps the pixel's colour.
    // The excess is recomputed from the pixel where needed rather than
    // stored: a full-size excess image is mostly zeros, and a fresh
    // process pays for each of its pages.
    let excess = |px: &[f32; 4]| -> [f32; 4] {
        let y = px[1] as f64;
        if y > p.threshold && y.is_finite() {
            let f = ((y - p.threshold) / y) as f32;
            px.map(|v| v * f)
        } else {
            [0.0; 4]
        }
    };
    if pixels.par_iter().all(|px| excess(px)[1] == 0.0) {
        // Nothing glares; what an excess of no luminance would take from
        // the other channels is still taken, as when it is spread.
        pixels.par_iter_mut().for_each(|px| {
            let e = excess(px);
            for c in 0..4 {
                px[c] -= e[c];
            }
        });
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
    coarse
        .par_chunks_mut(cw)
        .enumerate()
        .for_each(|(cy, cells)| {
            for y in cy * f..((cy + 1) * f).min(height) {
                for (x, px) in pixels[y * width..(y + 1) * width].iter().enumerate() {
                    let e = excess(px);
                    let cell = &mut cells[x / f];
                    for c in 0..4 {
                        cell[c] += e[c];
                    }
                }
            }
        });
    // Padding to at least twice the image keeps the circular convolution
    // from wrapping light from one edge onto the other.
    let fft = Fft2::new(smooth_size(2 * cw), smooth_size(2 * ch));
    let kernels = KernelSpectra::new(&fft, p.degrees_per_pixel * f as f64, p.s, f > 1);
    let kept = if f > 1 { kernels.centre } else { [0.0; 4] };
    let glare = convolve(&coarse, cw, ch, &fft, &kernels);
    // Per pixel: what the display shows, the coarse glare (per coarse
    // cell, so shared by its f² pixels) brought back up, plus the kept
    // central share.
    let up = Bilinear::new((cw, ch), (width, height));
    let scale = 1.0 / (f * f) as f32;
    pixels.par_chunks_mut(width).enumerate().for_each_init(
        || (vec![0.0f32; width], vec![[0.0f32; 4]; width]),
        |(row_glare, ex), (y, row)| {
            for (px, e) in row.iter_mut().zip(ex.iter_mut()) {
                *e = excess(px);
                for c in 0..4 {
                    px[c] -= e[c];
                }
            }
            for c in 0..4 {
                up.row(&glare[c], y, row_glare);
                for ((px, e), g) in row.iter_mut().zip(ex.iter()).zip(row_glare.iter()) {
                    px[c] += g * scale + kept[c] * e[c];
                }
            }
        },
    );
    true
}

/// Each channel of the `cw` × `ch` image `img` convolved with its PSF on
/// `fft`'s padded grid. Two real channels travel in one complex FFT
/// (X + iY, Z + iV′): with P = F(a + ib), the transforms of a and b are
/// (P(k) + P̄(−k))/2 and (P(k) − P̄(−k))/2i, so filtering them by the real
/// spectra Ka, Kb gives P(k)·(Ka + Kb)/2 + P̄(−k)·(Ka − Kb)/2, whose
/// inverse holds a's result in its real part and b's in its imaginary.
fn convolve(
    img: &[[f32; 4]],
    cw: usize,
    ch: usize,
    fft: &Fft2,
    kernels: &KernelSpectra,
) -> [Vec<f32>; 4] {
    let (pw, ph) = (fft.width, fft.height);
    let norm = 1.0 / (pw * ph) as f32;
    let mut out: [Vec<f32>; 4] = Default::default();
    for (a, b) in [(0, 1), (2, 3)] {
        // Buffers are made in parallel, each value written once (zeroing
        // them first would run on one thread).
        let mut packed = Vec::with_capacity(pw * ph);
        packed.par_extend((0..pw * ph).into_par_iter().map(|i| {
            let (x, y) = (i % pw, i / pw);
            match img.get(y * cw + x).filter(|_| x < cw) {
                Some(px) => Complex32::new(px[a], px[b]),
                None => Complex32::new(0.0, 0.0),
            }
        }));
        let spectrum = fft.forward(&mut packed, ch);
        let (ka, kb) = (kernels.channel(a), kernels.channel(b));
        // Column-major: index kx·ph + ky; −k wraps on both axes.
        let mut filtered = Vec::with_capacity(pw * ph);
        filtered.par_extend((0..pw * ph).into_par_iter().map(|k| {
            let (kx, ky) = (k / ph, k % ph);
            let mirror = ((pw - kx) % pw) * ph;
            let conj_neg = spectrum[mirror + (ph - ky) % ph].conj();
            spectrum[k] * (0.5 * (ka[k] + kb[k])) + conj_neg * (0.5 * (ka[k] - kb[k]))
        }));
        let result = fft.inverse(&mut filtered, ch);
        let plane = |part: fn(&Complex32) -> f32| -> Vec<f32> {
            result
                .par_chunks(pw)
                .flat_map_iter(|row| row[..cw].iter().map(move |z| part(z) * norm))
                .collect()
        };
        out[a] = plane(|z| z.re);
        out[b] = plane(|z| z.im);
    }
    out
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
    fn the_packed_fft_convolution_equals_the_direct_sum() {
        // Four different channels through four different (scotopic halo)
        // kernels: the FFT result equals the convolution summed directly.
        let (cw, ch) = (9, 7);
        let img: Vec<[f32; 4]> = (0..cw * ch)
            .map(|i| {
                let v = ((i * 37 % 11) as f32).powi(2);
                [v, 0.5 * v + 1.0, (i % 5) as f32, (i % 3) as f32 * 2.0]
            })
            .collect();
        let fft = Fft2::new(smooth_size(2 * cw), smooth_size(2 * ch));
        let (pw, ph) = (fft.width, fft.height);
        let kernels = KernelSpectra::new(&fft, 0.7, 0.0, false);
        let got = convolve(&img, cw, ch, &fft, &kernels);
        let (k, _) = super::super::kernel::sample(pw, ph, 0.7, 0.0);
        for c in 0..4 {
            let total: f64 = k.iter().map(|v| v[c]).sum();
            for y in 0..ch {
                for x in 0..cw {
                    let mut sum = 0.0f64;
                    for (i, px) in img.iter().enumerate() {
                        let (sx, sy) = (i % cw, i / cw);
                        let kx = (x + pw - sx) % pw;
                        let ky = (y + ph - sy) % ph;
                        sum += px[c] as f64 * k[ky * pw + kx][c] / total;
                    }
                    let g = got[c][y * cw + x] as f64;
                    assert!(
                        (g - sum).abs() < 1e-4 * (1.0 + sum.abs()),
                        "{c} {x} {y}: {g} {sum}"
                    );
                }
            }
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

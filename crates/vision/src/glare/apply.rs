//! Applying the glare PSF to the scene, in absolute units: the light of
//! each pixel that the display will not reproduce is spread by the eye's
//! PSF (`psf`) and added where it lands, convolved by FFT with zero
//! padding, one PSF per channel (the halo differs).
//!
//! The viewer's own eye scatters the light the display shows; simulating
//! that light's glare too would count it twice (Spencer et al. 1995, §5).
//! So each pixel is split into what the display reproduces of it, in
//! scene units at the adaptation point ([`Reproduced`]), and the rest,
//! which glares. For a linear exposure that is Spencer et al.'s rule:
//! everything above the display's peak glares. For a compressive operator
//! the display shows a lamp at a small fraction of its luminance, so
//! nearly all of a lamp's light glares, as it does in a real eye, and a
//! surface at the adaptation luminance, shown as it is, glares not at
//! all.

use rayon::prelude::*;
use rustfft::num_complex::Complex32;

use super::fft2::{smooth_size, Fft2};
use super::kernel::KernelSpectra;
use super::psf::Psf;
use crate::multiscale::GainFunction;
use crate::observer::Observer;
use crate::resample::Bilinear;
use crate::tonemap::reinhard_scale;
use crate::wide_math;

/// What the display reproduces of a scene luminance, in scene cd/m² at
/// the image's adaptation point: the display's luminance for it over the
/// display's luminance per scene cd/m² at the adaptation luminance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Reproduced {
    /// Nothing: every pixel's light glares (the retinal image).
    Nothing,
    /// Everything up to a luminance (a linear exposure whose peak is it).
    Below(f64),
    /// A photoreceptor response y·G(y) relative to the adaptation
    /// luminance `la`'s, y·G(y)/G(la), up to `threshold` (where the display
    /// reaches its peak): the multiscale model's.
    Gain {
        cones: GainFunction,
        la: f64,
        threshold: f64,
    },
    /// Reinhard et al. 2002's operator (log-average `la`, white `maximum`).
    Reinhard { la: f64, maximum: f64 },
}

impl Reproduced {
    /// Each pixel's share that glares, (y − reproduced)/y (0 for no light
    /// or a non-finite one), into `out`: the excess keeps the pixel's
    /// colour, all four channels scaled alike. The multiscale model's
    /// case runs wide (`wide_math::dispatch`): it is evaluated for every
    /// pixel twice.
    pub fn excess_factors(&self, row: &[[f32; 4]], out: &mut [f32]) {
        let out = &mut out[..row.len()];
        if let Reproduced::Gain {
            cones,
            la,
            threshold,
        } = *self
        {
            let (la, threshold) = (la as f32, threshold as f32);
            let g_la = cones.gain(la);
            wide_math::dispatch(
                #[inline(always)]
                || {
                    for (o, px) in out.iter_mut().zip(row) {
                        let y = px[1];
                        let f = (y - kept_by_gain(y, &cones, g_la, threshold)) / y;
                        // Selects: at or below La, not finite, or no
                        // light, nothing glares.
                        *o = if y > la && y < f32::INFINITY && f > 0.0 {
                            f
                        } else {
                            0.0
                        };
                    }
                },
            );
            return;
        }
        for (o, px) in out.iter_mut().zip(row) {
            let y = px[1] as f64;
            *o = if y > 0.0 && y.is_finite() {
                let kept = self.of(y);
                ((y - kept) / y) as f32
            } else {
                0.0
            };
        }
    }

    /// What is reproduced of luminance `y` (at most `y`).
    pub fn of(&self, y: f64) -> f64 {
        let r = match *self {
            Reproduced::Nothing => 0.0,
            Reproduced::Below(t) => t,
            Reproduced::Gain {
                cones,
                la,
                threshold,
            } => {
                // At or below La the display shows a pixel at least as it
                // is (the gain falls with luminance): nothing glares, and
                // no power need be taken.
                if y <= la {
                    return y;
                }
                let g_la = cones.gain(la as f32);
                kept_by_gain(y as f32, &cones, g_la, threshold as f32) as f64
            }
            Reproduced::Reinhard { la, maximum } => {
                y * reinhard_scale(y, la, maximum) / reinhard_scale(la, la, maximum)
            }
        };
        if r.is_finite() {
            r.clamp(0.0, y)
        } else {
            y
        }
    }
}

/// What the multiscale model's response reproduces of luminance `y`:
/// v·G(v)/G(La) with v = min(y, threshold), `g_la` = G(La); branch-free
/// (a select), so a row of it vectorises.
#[inline(always)]
fn kept_by_gain(y: f32, cones: &GainFunction, g_la: f32, threshold: f32) -> f32 {
    let v = if y < threshold { y } else { threshold };
    v * (cones.gain_wide(v) / g_la)
}

/// How the glare is applied.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlareParams {
    /// Visual angle of one pixel, degrees.
    pub degrees_per_pixel: f64,
    /// Scotopic sensitivity s (1 photopic, 0 scotopic): the halo's weight.
    pub s: f64,
    /// Whose eye: its age and pigmentation shape the PSF.
    pub observer: Observer,
    /// What the display reproduces; the rest glares.
    pub reproduced: Reproduced,
}

/// What glare did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct GlareReport {
    /// Whether any light glared.
    pub applied: bool,
    /// The veiling luminance (Y, cd/m²) the scattered light adds at the
    /// image's centre (the line of sight, where a road lighting standard
    /// evaluates it) and on average over the image.
    pub veil_centre: f64,
    pub veil_mean: f64,
    /// The glared image's log-average luminance (as
    /// [`crate::mode::log_average`]; summed row by row in the pass that
    /// adds the veil).
    pub log_average: f64,
}

/// Adds glare to `pixels` ([X, Y, Z, V′] absolute, row-major, `width` ×
/// `height`) in place.
pub fn apply_glare(
    pixels: &mut [[f32; 4]],
    width: usize,
    height: usize,
    p: &GlareParams,
) -> GlareReport {
    // Split each pixel into what the display reproduces and the excess,
    // by the same factor on all channels so the excess keeps the pixel's
    // colour. The excess is recomputed from the pixel where needed rather
    // than stored: a full-size excess image is mostly zeros, and a fresh
    // process pays for each of its pages.
    let r = p.reproduced;
    let glares = pixels
        .par_chunks(width.max(1))
        .map_init(
            || vec![0.0f32; width],
            |f, row| {
                r.excess_factors(row, f);
                f.iter().any(|&v| v > 0.0)
            },
        )
        .any(|g| g);
    if !glares {
        return GlareReport::default();
    }
    // The PSF beyond its central pixel is smooth, so on large images it is
    // convolved on a grid coarser by `f` (block sums of the excess, so
    // nothing is lost) and brought back bilinearly; the share of the PSF
    // inside the central cell stays where it fell, at full resolution, so
    // lamps keep their sharp core.
    let f = coarse_factor(width, height);
    let (cw, ch) = (width.div_ceil(f), height.div_ceil(f));
    let mut coarse = vec![[0.0f32; 4]; cw * ch];
    coarse.par_chunks_mut(cw).enumerate().for_each_init(
        || vec![0.0f32; width],
        |factors, (cy, cells)| {
            for y in cy * f..((cy + 1) * f).min(height) {
                let row = &pixels[y * width..(y + 1) * width];
                r.excess_factors(row, factors);
                for (x, (px, k)) in row.iter().zip(factors.iter()).enumerate() {
                    let cell = &mut cells[x / f];
                    for c in 0..4 {
                        cell[c] += px[c] * k;
                    }
                }
            }
        },
    );
    // Padding to at least twice the image keeps the circular convolution
    // from wrapping light from one edge onto the other.
    let fft = Fft2::new(smooth_size(2 * cw), smooth_size(2 * ch));
    let psf = Psf::new(&p.observer, p.s);
    let kernels = KernelSpectra::shared(&fft, p.degrees_per_pixel * f as f64, &psf, true);
    let kept = kernels.centre;
    let glare = convolve(&coarse, cw, ch, &fft, &kernels);
    // Per pixel: what the display shows, the scattered light (per coarse
    // cell, so shared by its f² pixels) brought back up, plus the kept
    // central share.
    let up = Bilinear::new((cw, ch), (width, height));
    let scale = 1.0 / (f * f) as f32;
    let veils: Vec<(f64, f64, crate::mode::LogSum)> = pixels
        .par_chunks_mut(width)
        .enumerate()
        .map_init(
            || (vec![vec![0.0f32; width]; 4], vec![0.0f32; width]),
            |(veil, factors), (y, row)| {
                r.excess_factors(row, factors);
                for (c, v) in veil.iter_mut().enumerate() {
                    up.row(&glare[c], y, v);
                    v.iter_mut().for_each(|g| *g *= scale);
                }
                let veil: &[Vec<f32>] = veil;
                let factors: &[f32] = factors;
                // Each channel: less its excess e, plus the veil and the
                // kept central share of e; a wide loop over the row.
                wide_math::dispatch(
                    #[inline(always)]
                    || {
                        let factors = &factors[..row.len()];
                        let veil: [&[f32]; 4] = std::array::from_fn(|c| &veil[c][..row.len()]);
                        for (x, px) in row.iter_mut().enumerate() {
                            for c in 0..4 {
                                let e = px[c] * factors[x];
                                px[c] = (px[c] - e) + (veil[c][x] + kept[c] * e);
                            }
                        }
                    },
                );
                let sum = veil[1].iter().map(|&v| v as f64).sum::<f64>();
                let at_centre = if y == height / 2 {
                    veil[1][width / 2] as f64
                } else {
                    0.0
                };
                (sum, at_centre, crate::mode::log_sum_of(row))
            },
        )
        .collect();
    let n = (width * height).max(1) as f64;
    GlareReport {
        applied: true,
        veil_centre: veils.iter().map(|v| v.1).sum(),
        veil_mean: veils.iter().map(|v| v.0).sum::<f64>() / n,
        log_average: veils
            .iter()
            .fold(crate::mode::LogSum::default(), |a, v| a.join(v.2))
            .mean(),
    }
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
    use super::super::psf::GlareSpread;
    use super::*;

    fn params(reproduced: Reproduced, dpp: f64, s: f64) -> GlareParams {
        GlareParams {
            degrees_per_pixel: dpp,
            s,
            observer: Observer::default(),
            reproduced,
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
        let psf = Psf::new(&Observer::default(), 0.0);
        let kernels = KernelSpectra::new(&fft, 0.7, &psf, false);
        let got = convolve(&img, cw, ch, &fft, &kernels);
        let (k, _) = super::super::kernel::sample(pw, ph, 0.7, &psf);
        for c in 0..4 {
            for y in 0..ch {
                for x in 0..cw {
                    let mut sum = 0.0f64;
                    for (i, px) in img.iter().enumerate() {
                        let (sx, sy) = (i % cw, i / cw);
                        let kx = (x + pw - sx) % pw;
                        let ky = (y + ph - sy) % ph;
                        sum += px[c] as f64 * k[ky * pw + kx][c];
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
    fn an_image_the_display_reproduces_is_unchanged() {
        let mut px = vec![[50.0, 60.0, 70.0, 80.0]; 32 * 24];
        let before = px.clone();
        let r = apply_glare(
            &mut px,
            32,
            24,
            &params(Reproduced::Below(100.0), 0.05, 1.0),
        );
        assert!(!r.applied);
        assert_eq!(px, before);
        // And a field at the adaptation luminance, under the model's
        // response, reproduces itself.
        let gain = Reproduced::Gain {
            cones: GainFunction::CONES,
            la: 60.0,
            threshold: 1e4,
        };
        assert!(!apply_glare(&mut px, 32, 24, &params(gain, 0.05, 1.0)).applied);
        assert_eq!(px, before);
    }

    /// A `w` × `h` black image with a 2 × 2 lamp of luminance `y` at its
    /// centre.
    fn lamp(w: usize, h: usize, y: f32) -> Vec<[f32; 4]> {
        let mut px = vec![[0.0f32; 4]; w * h];
        for dy in 0..2 {
            for dx in 0..2 {
                px[(h / 2 - 1 + dy) * w + w / 2 - 1 + dx] = [0.95 * y, y, 1.09 * y, 2.4 * y];
            }
        }
        px
    }

    #[test]
    fn a_lamps_light_is_conserved_on_a_wide_field() {
        // 256 × 256 pixels of 0.75° (±96°) hold the whole PSF (0–90°):
        // the light after equals the light before, to the sampling's
        // accuracy (0.5 %), on the direct and on the coarse grid.
        for (n, dpp) in [(256usize, 0.75), (1024, 0.1875)] {
            let mut px = lamp(n, n, 1.0e6);
            let before: f64 = px.iter().map(|p| p[1] as f64).sum();
            let r = apply_glare(&mut px, n, n, &params(Reproduced::Nothing, dpp, 1.0));
            assert!(r.applied);
            let after: f64 = px.iter().map(|p| p[1] as f64).sum();
            assert!(
                (after / before - 1.0).abs() < 0.005,
                "{n}: {after} vs {before}"
            );
            // The lamp stays a point, far above its neighbours.
            let c = (n / 2) * n + n / 2;
            assert!(
                px[c][1] > 10.0 * px[c + 2][1],
                "{} {}",
                px[c][1],
                px[c + 2][1]
            );
        }
    }

    #[test]
    fn the_veil_follows_cie_146_at_2_5_10_and_20_degrees() {
        // A 2 × 2 lamp at the centre of 512 × 512 pixels of 0.1° (glare
        // on a 2× coarser grid, h = 0.2°). Illuminance at the eye E =
        // L·ω (4 pixels); the veil at θ must be E·L_veil/E_glare(θ) of
        // CIE 146's general equation. Discretisation error: sampling the
        // PSF at coarse cell centres and interpolating it bilinearly are
        // each second order in h/θ for a 1/θ² function, ≤ (h/θ)²; the
        // tolerance is 3(h/θ)² + 0.2 %.
        let (n, dpp) = (512, 0.1);
        let h = 2.0 * dpp;
        let lum = 1.0e7f32;
        let omega = (dpp * std::f64::consts::PI / 180.0).powi(2);
        let e = lum as f64 * 4.0 * omega;
        for age in [25.0, 70.0] {
            let mut px = lamp(n, n, lum);
            let mut p = params(Reproduced::Nothing, dpp, 1.0);
            p.observer = Observer::new(age, 0.5).unwrap();
            apply_glare(&mut px, n, n, &p);
            let g = GlareSpread::new(&p.observer);
            for deg in [2.0, 5.0, 10.0, 20.0] {
                // Pixel centres at (d + ½)·dpp from the lamp's centre.
                let d = (deg / dpp) as usize;
                let theta = (d as f64 + 0.5) * dpp;
                let got = px[(n / 2) * n + n / 2 + d][1] as f64;
                let want = e * g.general(theta);
                let tol = 3.0 * (h / theta).powi(2) + 0.002;
                assert!(
                    (got / want - 1.0).abs() < tol,
                    "{age} years, {deg}°: {got} vs {want} (tolerance {tol})"
                );
            }
        }
    }

    #[test]
    fn the_scotopic_halo_is_red_outside_blue_inside() {
        // A white (X = Z) lamp at 0.1° per pixel: around the 3° ring the
        // glare is redder (X/Z higher) at 3.4° than at 2.2°. Photopic
        // vision has no halo term, so there the ratio stays 1.
        let (w, h) = (128, 128);
        let c = 64;
        let ratio = |s: f64, r: usize| {
            let mut px = vec![[0.0f32; 4]; w * h];
            px[c * w + c] = [1.0e6; 4];
            apply_glare(&mut px, w, h, &params(Reproduced::Nothing, 0.1, s));
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

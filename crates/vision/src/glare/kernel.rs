//! The glare PSF sampled on the (padded, wrapped) convolution grid and
//! transformed: one real spectrum per channel. The PSF is real and even,
//! so its spectrum is real, and two kernels share one complex FFT (one in
//! the real part, one in the imaginary part).

use std::sync::{Arc, Mutex};

use rayon::prelude::*;
use rustfft::num_complex::Complex32;

use super::fft2::Fft2;
use super::psf::Psf;

/// Pixels within this distance of the PSF's centre (in pixels) are
/// integrated over their area (the core is 0.02° wide, often sub-pixel).
const SUPERSAMPLED_RADIUS: i64 = 4;
const SUBSAMPLES: usize = 16;

/// The PSF's transform on `fft`'s grid, per channel X, Y, Z, V′.
#[derive(Debug)]
pub struct KernelSpectra {
    /// Real spectra, column-major like `Fft2`'s; one when every channel
    /// has the same PSF (no halo), else four.
    spectra: Vec<Vec<f32>>,
    /// Each channel's PSF value at the centre (a share of the total 1).
    pub centre: [f32; 4],
}

/// What a [`KernelSpectra`] is made from, but the halo's weight: the
/// cache's key.
#[derive(Debug, Clone, Copy, PartialEq)]
struct KernelKey {
    size: (usize, usize),
    degrees_per_pixel: f64,
    spread: super::psf::GlareSpread,
    without_centre: bool,
}

/// The cached spectra of one key: without a halo, and the two parts a
/// haloed PSF mixes (the spread and the halo alone, both averaged out to
/// the halo's reach).
struct Cached {
    key: KernelKey,
    plain: Option<Arc<KernelSpectra>>,
    /// The first haloed spectra asked for, with their halo weight: a
    /// one-off call (`scotopia display`) computes only these.
    first: Option<(f64, Arc<KernelSpectra>)>,
    parts: Option<Arc<(KernelSpectra, KernelSpectra)>>,
}

impl KernelSpectra {
    /// [`KernelSpectra::new`], from spectra kept for the next call with the
    /// same grid, pixel size and observer: the viewer redraws an image
    /// for every control. The PSF is (1 − w)·spread + w·halo with w the
    /// halo's weight (which follows the light level), and sampling and
    /// transforming are linear, so once a second w > 0 is asked for, the
    /// spectra are mixed from the two parts' (8 MB at full HD) instead of
    /// computed again (5–12 ms).
    pub fn shared(
        fft: &Fft2,
        degrees_per_pixel: f64,
        psf: &Psf,
        without_centre: bool,
    ) -> Arc<Self> {
        static LAST: Mutex<Option<Cached>> = Mutex::new(None);
        let key = KernelKey {
            size: (fft.width, fft.height),
            degrees_per_pixel,
            spread: psf.spread,
            without_centre,
        };
        // (A poisoned lock only means another thread panicked while
        // storing: the spectra are then computed again.)
        let mut last = LAST.lock().ok();
        let slot = last.as_deref_mut();
        let cached = match slot {
            Some(Some(c)) if c.key == key => c,
            Some(slot) => slot.insert(Cached {
                key,
                plain: None,
                first: None,
                parts: None,
            }),
            None => return Arc::new(Self::new(fft, degrees_per_pixel, psf, without_centre)),
        };
        if psf.halo <= 0.0 {
            return cached
                .plain
                .get_or_insert_with(|| {
                    Arc::new(Self::new(fft, degrees_per_pixel, psf, without_centre))
                })
                .clone();
        }
        match &cached.first {
            Some((w, spectra)) if *w == psf.halo => return spectra.clone(),
            Some(_) => {}
            None => {
                let spectra = Arc::new(Self::new(fft, degrees_per_pixel, psf, without_centre));
                cached.first = Some((psf.halo, spectra.clone()));
                return spectra;
            }
        }
        // A second halo weight: from now on, mixed from the parts.
        let parts = cached.parts.get_or_insert_with(|| {
            let part = |halo: f64, reach| {
                let p = Psf { halo, ..*psf };
                Self::with_reach(fft, degrees_per_pixel, &p, without_centre, reach)
            };
            // The spread alone (w = 0, one spectrum), the halo alone (w = 1).
            Arc::new((part(0.0, true), part(1.0, true)))
        });
        let (spread, halo) = (&parts.0, &parts.1);
        let w = psf.halo as f32;
        Arc::new(Self {
            spectra: (0..4)
                .map(|c| {
                    spread
                        .channel(c)
                        .par_iter()
                        .zip(halo.channel(c))
                        .map(|(a, b)| (1.0 - w) * a + w * b)
                        .collect()
                })
                .collect(),
            centre: std::array::from_fn(|c| (1.0 - w) * spread.centre[c] + w * halo.centre[c]),
        })
    }

    /// The spectrum that filters channel `c`.
    pub fn channel(&self, c: usize) -> &[f32] {
        &self.spectra[c.min(self.spectra.len() - 1)]
    }

    /// The PSF `psf` at `degrees_per_pixel`, each sample the share of a
    /// point's light that lands in that pixel (the light beyond the grid
    /// is lost, as it lands outside the image); with `without_centre`,
    /// its centre sample is left out of the spectra (reported in
    /// `centre`) for the caller to apply at a finer resolution.
    pub fn new(fft: &Fft2, degrees_per_pixel: f64, psf: &Psf, without_centre: bool) -> Self {
        Self::with_reach(fft, degrees_per_pixel, psf, without_centre, psf.halo > 0.0)
    }

    /// [`KernelSpectra::new`] with pixels averaged out to the halo's reach
    /// (`halo_reach`) or the spread's.
    fn with_reach(
        fft: &Fft2,
        degrees_per_pixel: f64,
        psf: &Psf,
        without_centre: bool,
        halo_reach: bool,
    ) -> Self {
        let grid = Sampled::new(fft.width, fft.height, degrees_per_pixel, psf, halo_reach);
        let n = fft.width * fft.height;
        let k0 = grid.at(0);
        let centre: [f32; 4] = k0.map(|v| v as f32);
        // Channel pairs packed as real + i·imaginary; a real, even kernel's
        // spectrum is real, so the two come back as the real and the
        // imaginary parts.
        let pairs: &[(usize, usize)] = if grid.has_halo {
            &[(0, 1), (2, 3)]
        } else {
            &[(0, 0)]
        };
        let mut spectra = Vec::new();
        for &(a, b) in pairs {
            let mut packed: Vec<Complex32> = (0..n)
                .into_par_iter()
                .map(|i| {
                    let v = if without_centre && i == 0 {
                        [0.0; 4]
                    } else {
                        grid.at(i)
                    };
                    let im = if a == b { 0.0 } else { v[b] };
                    Complex32::new(v[a] as f32, im as f32)
                })
                .collect();
            let spectrum = fft.forward(&mut packed, fft.height);
            spectra.push(spectrum.iter().map(|z| z.re).collect());
            if a != b {
                spectra.push(spectrum.iter().map(|z| z.im).collect());
            }
        }
        Self { spectra, centre }
    }
}

/// The PSF (X, Y, Z, V′) on a `pw` × `ph` grid centred at index (0, 0) and
/// wrapped, pixels near the centre averaged over their area; and whether
/// the channels differ (a halo). (The whole grid, from [`Sampled`].)
#[cfg(test)]
pub(super) fn sample(
    pw: usize,
    ph: usize,
    degrees_per_pixel: f64,
    psf: &Psf,
) -> (Vec<[f64; 4]>, bool) {
    let grid = Sampled::new(pw, ph, degrees_per_pixel, psf, psf.halo > 0.0);
    ((0..pw * ph).map(|i| grid.at(i)).collect(), grid.has_halo)
}

/// The sampled PSF of a `pw` × `ph` wrapped grid, stored once per
/// distinct value: beyond the supersampled core the PSF depends on
/// dx² + dy² only, so one quadrant (|dx|, |dy|) holds every value, a
/// quarter of the evaluations and of the memory (a full-HD image's grid of
/// four f64 channels was 17 MB, which a fresh process pays for page by
/// page); the core's 9 × 9 pixels, averaged over sub-pixel samples, are
/// kept by signed offset. Every value is the one the whole grid had.
struct Sampled {
    pw: usize,
    ph: usize,
    /// Quadrant width, pw/2 + 1.
    qw: usize,
    quadrant: Vec<[f64; 4]>,
    core: Vec<[f64; 4]>,
    has_halo: bool,
}

/// Core side, 2·SUPERSAMPLED_RADIUS + 1.
const CORE: usize = 2 * SUPERSAMPLED_RADIUS as usize + 1;

/// Signed offset of grid index i on an n-long wrapped axis.
fn signed(i: usize, n: usize) -> i64 {
    if i <= n / 2 {
        i as i64
    } else {
        i as i64 - n as i64
    }
}

impl Sampled {
    fn new(pw: usize, ph: usize, degrees_per_pixel: f64, psf: &Psf, halo_reach: bool) -> Self {
        // A pixel's solid angle, sr (small-angle form, as the PSF's θ).
        let omega = (degrees_per_pixel * std::f64::consts::PI / 180.0).powi(2);
        let value = |dx: f64, dy: f64| -> [f64; 4] {
            let theta = (dx * dx + dy * dy).sqrt() * degrees_per_pixel;
            psf.eval(theta).map(|v| v * omega)
        };
        let (qw, qh) = (pw / 2 + 1, ph / 2 + 1);
        let averaged = averaged_radius(degrees_per_pixel, halo_reach);
        let mut quadrant = vec![[0.0f64; 4]; qw * qh];
        quadrant
            .par_chunks_mut(qw)
            .enumerate()
            .for_each(|(dy, row)| {
                for (dx, v) in row.iter_mut().enumerate() {
                    *v = if dx * dx + dy * dy <= averaged * averaged {
                        area_average(&value, dx as f64, dy as f64)
                    } else {
                        value(dx as f64, dy as f64)
                    };
                }
            });
        let r = SUPERSAMPLED_RADIUS;
        let mut core: Vec<[f64; 4]> = (-r..=r)
            .flat_map(|dy| (-r..=r).map(move |dx| (dx, dy)))
            .map(|(dx, dy)| supersampled(&value, dx, dy))
            .collect();
        // The central pixel holds the optics' core, far narrower than a
        // pixel: its disc (radius half a pixel) is integrated in closed
        // form, the four corners outside it by sub-samples.
        let half = 0.5 * degrees_per_pixel;
        let disc = (1.0 - psf.halo) * psf.spread.share_within(half);
        let corners = supersampled(
            &|dx: f64, dy: f64| {
                if dx * dx + dy * dy > 0.25 {
                    value(dx, dy)
                } else {
                    // Inside the disc: its halo part only (the halo is a
                    // ring far from the centre; its value here is ~0).
                    let theta = (dx * dx + dy * dy).sqrt() * degrees_per_pixel;
                    let shared = (1.0 - psf.halo) * psf.spread.eval(theta) * omega;
                    value(dx, dy).map(|v| v - shared)
                }
            },
            0,
            0,
        );
        core[(r * (2 * r + 1) + r) as usize] = corners.map(|v| v + disc);
        Self {
            pw,
            ph,
            qw,
            quadrant,
            core,
            has_halo: psf.halo > 0.0,
        }
    }

    /// The PSF at grid index `i` (row-major, `pw` wide).
    fn at(&self, i: usize) -> [f64; 4] {
        let (dx, dy) = (signed(i % self.pw, self.pw), signed(i / self.pw, self.ph));
        let r = SUPERSAMPLED_RADIUS;
        if dx.abs() <= r && dy.abs() <= r {
            self.core[(dy + r) as usize * CORE + (dx + r) as usize]
        } else {
            self.quadrant[dy.unsigned_abs() as usize * self.qw + dx.unsigned_abs() as usize]
        }
    }
}

/// Pixels (beyond the core) nearer the centre than this are averaged
/// over their area, not sampled at their centre: where the halo's ring
/// lies (it is 0.3° wide, narrower than a pixel of a wide image, so point
/// samples alias it: the ring's light then depended on pixels per degree),
/// and where 1/θ² bends fastest.
fn averaged_radius(degrees_per_pixel: f64, halo: bool) -> usize {
    let reach = if halo { 8.0 } else { 1.0 };
    (reach / degrees_per_pixel).ceil() as usize
}

/// Sub-samples per axis for [`area_average`].
const AREA_SUBSAMPLES: usize = 4;

/// The PSF averaged over pixel (dx, dy) on an AREA_SUBSAMPLES² grid.
fn area_average(value: &impl Fn(f64, f64) -> [f64; 4], dx: f64, dy: f64) -> [f64; 4] {
    let n = AREA_SUBSAMPLES as f64;
    let mut sum = [0.0; 4];
    for sy in 0..AREA_SUBSAMPLES {
        for sx in 0..AREA_SUBSAMPLES {
            let f = value(
                dx + (sx as f64 + 0.5) / n - 0.5,
                dy + (sy as f64 + 0.5) / n - 0.5,
            );
            for c in 0..4 {
                sum[c] += f[c] / (n * n);
            }
        }
    }
    sum
}

/// The PSF averaged over pixel (dx, dy) on a SUBSAMPLES² grid: the core,
/// where it changes too fast for one value per pixel.
fn supersampled(psf: &impl Fn(f64, f64) -> [f64; 4], dx: i64, dy: i64) -> [f64; 4] {
    let n = SUBSAMPLES as f64;
    let mut sum = [0.0; 4];
    for sy in 0..SUBSAMPLES {
        for sx in 0..SUBSAMPLES {
            let ox = (sx as f64 + 0.5) / n - 0.5;
            let oy = (sy as f64 + 0.5) / n - 0.5;
            let f = psf(dx as f64 + ox, dy as f64 + oy);
            for c in 0..4 {
                sum[c] += f[c] / (n * n);
            }
        }
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::*;

    use crate::observer::Observer;

    fn psf(s: f64) -> Psf {
        Psf::new(&Observer::default(), s)
    }

    #[test]
    fn the_shared_spectra_are_the_new_ones_and_follow_the_psf() {
        // Plain, a first halo weight, mixed at others, cached ones again.
        let fft = Fft2::new(64, 48);
        for s in [1.0, 0.3, 0.3, 0.0, 0.1, 1.0, 0.3] {
            let shared = KernelSpectra::shared(&fft, 0.2, &psf(s), true);
            let new = KernelSpectra::new(&fft, 0.2, &psf(s), true);
            // The mixture differs from a fresh transform by f32 rounding.
            let close = |a: f32, b: f32, scale: f32| (a - b).abs() <= 1e-6 * scale;
            for c in 0..4 {
                assert!(
                    close(shared.centre[c], new.centre[c], new.centre[c]),
                    "s = {s}"
                );
                let (a, b) = (shared.channel(c), new.channel(c));
                let scale = b.iter().fold(0.0f32, |m, v| m.max(v.abs()));
                assert!(
                    a.iter().zip(b).all(|(x, y)| close(*x, *y, scale)),
                    "s = {s}, channel {c}"
                );
            }
        }
    }

    #[test]
    fn the_quadrant_and_core_hold_every_value_of_the_whole_grid() {
        // Beyond the centre, the grid as it was sampled pixel by pixel:
        // the same bits.
        for (pw, ph, s) in [(40, 30, 0.0), (33, 17, 0.5), (64, 48, 1.0)] {
            let psf = psf(s);
            let omega = (0.2 * std::f64::consts::PI / 180.0).powi(2);
            let value = |dx: f64, dy: f64| -> [f64; 4] {
                psf.eval((dx * dx + dy * dy).sqrt() * 0.2)
                    .map(|v| v * omega)
            };
            let (k, _) = sample(pw, ph, 0.2, &psf);
            let averaged = averaged_radius(0.2, psf.halo > 0.0) as i64;
            for (i, v) in k.iter().enumerate().skip(1) {
                let (dx, dy) = (signed(i % pw, pw), signed(i / pw, ph));
                let want = if dx.abs() <= SUPERSAMPLED_RADIUS && dy.abs() <= SUPERSAMPLED_RADIUS {
                    supersampled(&value, dx, dy)
                } else if dx * dx + dy * dy <= averaged * averaged {
                    area_average(&value, dx.abs() as f64, dy.abs() as f64)
                } else {
                    value(dx as f64, dy as f64)
                };
                assert_eq!(
                    v.map(f64::to_bits),
                    want.map(f64::to_bits),
                    "{pw}×{ph} at {i}"
                );
            }
        }
    }

    #[test]
    fn the_samples_hold_the_light_that_lands_on_the_grid() {
        // A grid ±64° wide at 0.5° per pixel, and a fine one (0.01°,
        // ±1.28°): the samples sum to the share within the grid's reach
        // (the disc of its half-width, plus its corners), to 0.5 %.
        for (n, dpp) in [(256usize, 0.5), (256, 0.01)] {
            let psf = psf(1.0);
            let (k, _) = sample(n, n, dpp, &psf);
            let total: f64 = k.iter().map(|v| v[1]).sum();
            let half = n as f64 / 2.0 * dpp;
            let (inner, outer) = (
                psf.spread.share_within(half),
                psf.spread.share_within(half * std::f64::consts::SQRT_2),
            );
            assert!(
                total > inner * 0.995 && total < outer * 1.005,
                "{dpp}: {total} not in {inner}..{outer}"
            );
        }
    }

    #[test]
    fn packed_spectra_equal_each_kernel_transformed_alone() {
        let fft = Fft2::new(40, 30);
        let (k, has_halo) = sample(40, 30, 0.2, &psf(0.0));
        assert!(has_halo);
        let packed = KernelSpectra::new(&fft, 0.2, &psf(0.0), false);
        for c in 0..4 {
            let mut alone: Vec<Complex32> =
                k.iter().map(|v| Complex32::new(v[c] as f32, 0.0)).collect();
            let alone = fft.forward(&mut alone, 30);
            for (a, b) in alone.iter().zip(packed.channel(c)) {
                assert!((a.re - b).abs() < 1e-5 && a.im.abs() < 1e-5, "{c}: {a} {b}");
            }
        }
        assert!(
            packed.channel(0) != packed.channel(2),
            "the halo differs by channel"
        );
        // Without the centre, the zero frequency (the sum) drops by it.
        let cut = KernelSpectra::new(&fft, 0.2, &psf(0.0), true);
        for c in 0..4 {
            let dc = cut.channel(c)[0];
            let full = packed.channel(c)[0];
            assert!((dc - (full - cut.centre[c])).abs() < 1e-5, "{c}: {dc}");
            assert!(cut.centre[c] > 0.1);
        }
        // Photopic: no halo, one spectrum for all.
        let photopic = KernelSpectra::new(&fft, 0.2, &psf(1.0), false);
        assert_eq!(photopic.channel(0), photopic.channel(3));
    }
}

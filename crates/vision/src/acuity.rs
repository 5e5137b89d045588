//! Loss of visual acuity in the dark: the finest grating the eye resolves
//! falls from ~50 cycles/degree in daylight to a few under starlight.
//! Neither implementation of Jensen et al. 2001 read for this project has a
//! blur (../shared/vision-equations.md §3), so scotopia's is documented in
//! docs/vision.md: a Gaussian that removes what the scene's viewer could
//! not resolve but the display's viewer could.

use rayon::prelude::*;

use crate::wide_math;

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
/// the blur. Both passes work in place (a narrow blur needs no full-size
/// buffer: a fresh process pays for every page it touches).
pub fn gaussian_blur(pixels: &mut [[f32; 4]], width: usize, height: usize, sigma: f64) {
    if sigma.is_nan() || sigma < 0.3 || width == 0 || height == 0 {
        return;
    }
    let taps = Taps::new(sigma.min(MAX_BLUR_SIGMA));
    // Each column's edge weights, the same for every row: computed once.
    let edges: Vec<(f32, f32)> = (0..width as i64)
        .map(|x| taps.edge_weights(x, width as i64))
        .collect();
    // Horizontal pass, row by row: the pixels whose taps all fall inside
    // the row as one wide loop per tap over the row's channels, the few
    // near the ends tap by tap with their edge weights (the same sums in
    // the same order either way).
    let r = taps.radius as usize;
    let inner = (r + 1)..width.saturating_sub(r + 1).max(r + 1);
    pixels.par_chunks_mut(width).for_each_init(
        || Vec::with_capacity(width),
        |copy: &mut Vec<[f32; 4]>, row| {
            copy.clear();
            copy.extend_from_slice(row);
            let n = width as i64;
            for x in (0..width).filter(|x| !inner.contains(x)) {
                let (w0, w1) = edges[x];
                let mut acc = [0.0f32; 4];
                let mut add = |p: &[f32; 4], t: f32| axpy(&mut acc, p, t);
                // (An edge's weight is 0 away from it, and adding 0 · p
                // changes no finite sum: skipped.)
                if w0 != 0.0 {
                    add(&copy[0], w0);
                }
                for i in taps.interior(x as i64, n) {
                    add(&copy[i as usize], taps.weight(i - x as i64));
                }
                if n > 1 && w1 != 0.0 {
                    add(&copy[width - 1], w1);
                }
                row[x] = acc;
            }
            if inner.is_empty() {
                return;
            }
            let out = row[inner.clone()].as_flattened_mut();
            let source = copy.as_flattened();
            wide_math::dispatch(
                #[inline(always)]
                || {
                    out.fill(0.0);
                    for (k, &t) in taps.weights.iter().enumerate() {
                        // Tap offset k − r: the source starts k − r pixels
                        // from the output's first pixel.
                        let from = 4 * (inner.start + k - r);
                        let src = &source[from..from + out.len()];
                        for (o, s) in out.iter_mut().zip(src) {
                            *o += t * s;
                        }
                    }
                },
            );
        },
    );
    let radius = r;
    let row_of = |v: &[[f32; 4]], y: usize| v[y * width..(y + 1) * width].to_vec();
    if radius >= BAND_ROWS / 4 {
        // A wide blur reads far: from a full-size copy (the halos of the
        // bands below would outweigh it).
        let copy = pixels.to_vec();
        pixels
            .par_chunks_mut(width)
            .enumerate()
            .for_each(|(y, out)| taps.column(out, y, height, |yy| &copy[yy * width..][..width]));
        return;
    }
    // Vertical pass in bands of rows: a band keeps the rows it has
    // overwritten, while they are still needed, in a ring of `radius + 1`
    // rows, and reads its neighbours' rows next to it and the two edge
    // rows (onto which the taps beyond the image fold) from copies made
    // before any band starts.
    let (top, bottom) = (row_of(pixels, 0), row_of(pixels, height - 1));
    let bands: Vec<(usize, usize)> = (0..height)
        .step_by(BAND_ROWS)
        .map(|y0| (y0, (y0 + BAND_ROWS).min(height)))
        .collect();
    // Each band's rows above and below it.
    type Halo = (Vec<[f32; 4]>, Vec<[f32; 4]>);
    let halos: Vec<Halo> = bands
        .iter()
        .map(|&(y0, y1)| {
            let above = y0.saturating_sub(radius)..y0;
            let below = y1..(y1 + radius).min(height);
            (
                pixels[above.start * width..above.end * width].to_vec(),
                pixels[below.start * width..below.end * width].to_vec(),
            )
        })
        .collect();
    let ring_rows = radius + 1;
    pixels
        .par_chunks_mut(BAND_ROWS * width)
        .zip(bands.par_iter().zip(&halos))
        .for_each_init(
            || {
                (
                    vec![[0.0f32; 4]; ring_rows * width],
                    vec![[0.0f32; 4]; width],
                )
            },
            |(ring, out), (band, (&(y0, y1), (above, below)))| {
                let above_start = y0.saturating_sub(radius);
                for y in y0..y1 {
                    let own = (y - y0) * width;
                    let slot = (y % ring_rows) * width;
                    ring[slot..slot + width].copy_from_slice(&band[own..own + width]);
                    let ring: &[[f32; 4]] = ring;
                    let band_rows: &[[f32; 4]] = band;
                    // Row yy after the horizontal pass, as it was.
                    let source = |yy: usize| -> &[[f32; 4]] {
                        let (v, r) = if yy == 0 {
                            (top.as_slice(), 0)
                        } else if yy == height - 1 {
                            (bottom.as_slice(), 0)
                        } else if yy < y0 {
                            (above.as_slice(), yy - above_start)
                        } else if yy <= y {
                            (ring, yy % ring_rows)
                        } else if yy < y1 {
                            (band_rows, yy - y0)
                        } else {
                            (below.as_slice(), yy - y1)
                        };
                        &v[r * width..(r + 1) * width]
                    };
                    taps.column(out, y, height, source);
                    band[own..own + width].copy_from_slice(out);
                }
            },
        );
}

/// Rows per band of the in-place vertical pass.
const BAND_ROWS: usize = 64;

/// `acc += t · p`, channel by channel.
#[inline]
fn axpy(acc: &mut [f32; 4], p: &[f32; 4], t: f32) {
    for c in 0..4 {
        acc[c] += t * p[c];
    }
}

/// A Gaussian's normalised taps and the weights of the taps that fall
/// beyond an edge, folded onto it.
struct Taps {
    radius: i64,
    /// The taps, normalised; index d + radius for offset d.
    weights: Vec<f32>,
    /// prefix[k] = the sum of the first k taps (unnormalised).
    prefix: Vec<f64>,
    total: f64,
}

impl Taps {
    fn new(sigma: f64) -> Self {
        let radius = (3.0 * sigma).ceil() as i64;
        let taps: Vec<f64> = (-radius..=radius)
            .map(|d| (-(d * d) as f64 / (2.0 * sigma * sigma)).exp())
            .collect();
        let mut prefix = Vec::with_capacity(taps.len() + 1);
        prefix.push(0.0f64);
        for t in &taps {
            prefix.push(prefix.last().copied().unwrap_or(0.0) + t);
        }
        let total = prefix.last().copied().unwrap_or(1.0);
        Self {
            radius,
            weights: taps.iter().map(|t| (t / total) as f32).collect(),
            prefix,
            total,
        }
    }

    /// The weight of the tap at offset `d`.
    #[inline]
    fn weight(&self, d: i64) -> f32 {
        self.weights[(d + self.radius) as usize]
    }

    /// The weights sample `x` of an `n`-long axis gives the sources 0 and
    /// n-1: the taps at or beyond each edge.
    fn edge_weights(&self, x: i64, n: i64) -> (f32, f32) {
        if n == 1 {
            return (1.0, 0.0);
        }
        let r = self.radius;
        let low = (r - x).clamp(-1, 2 * r) + 1; // taps with x + d ≤ 0
        let high = (r + n - 1 - x).clamp(0, 2 * r + 1); // x + d ≥ n-1
        (
            (self.prefix[low as usize] / self.total) as f32,
            ((self.total - self.prefix[high as usize]) / self.total) as f32,
        )
    }

    /// The sources strictly between the edges that sample `x` reads.
    fn interior(&self, x: i64, n: i64) -> std::ops::RangeInclusive<i64> {
        (x - self.radius).max(1)..=(x + self.radius).min(n - 2)
    }

    /// Output row `y` of the vertical pass over `n` rows, `source(yy)`
    /// giving row yy: the same sums, in the same order, as the horizontal
    /// pass, a whole row at a time.
    fn column<'a>(
        &self,
        out: &mut [[f32; 4]],
        y: usize,
        n: usize,
        source: impl Fn(usize) -> &'a [[f32; 4]],
    ) {
        let (y, n) = (y as i64, n as i64);
        let (w0, w1) = self.edge_weights(y, n);
        let add = |out: &mut [[f32; 4]], yy: i64, t: f32| {
            let (out, src) = (out.as_flattened_mut(), source(yy as usize).as_flattened());
            wide_math::dispatch(
                #[inline(always)]
                || {
                    for (o, p) in out.iter_mut().zip(src) {
                        *o += t * p;
                    }
                },
            );
        };
        out.fill([0.0; 4]);
        if w0 != 0.0 {
            add(out, 0, w0);
        }
        for i in self.interior(y, n) {
            add(out, i, self.weight(i - y));
        }
        if n > 1 && w1 != 0.0 {
            add(out, n - 1, w1);
        }
    }
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
        // Taller than a band of the in-place vertical pass, narrow and
        // wide blurs: still the every-tap sums.
        let (w, h) = (7, 3 * BAND_ROWS + 5);
        let px: Vec<[f32; 4]> = (0..w * h)
            .map(|i| [(i % 13) as f32, (i * 7 % 11) as f32, (i / w) as f32, 1.0])
            .collect();
        for sigma in [0.4, 1.2, 4.9, 5.4, 20.0] {
            let mut fast = px.clone();
            gaussian_blur(&mut fast, w, h, sigma);
            let slow = blur_by_every_tap(&px, w, h, sigma);
            for (i, (a, b)) in fast.iter().zip(&slow).enumerate() {
                for c in 0..4 {
                    assert!(
                        (a[c] - b[c]).abs() < 1e-4 * (1.0 + b[c].abs()),
                        "σ {sigma}, pixel {i}: {a:?} {b:?}"
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

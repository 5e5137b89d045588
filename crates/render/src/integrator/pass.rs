//! One pass of camera samples over the film, splatted through the
//! reconstruction filter (`film::filter`).
//!
//! A sample lands in its own pixel and adds to every pixel within the
//! filter's reach, up to `reach` rows above and below. Rows are rendered in
//! parallel, yet no two threads may add to one pixel, and the sums must
//! not depend on the threads: so a pass runs in 2·reach + 1 phases. In
//! phase k the rows y ≡ k (mod 2·reach + 1) are rendered, each owning the
//! window of rows y − reach ..= y + reach, and these windows are disjoint.
//! Every pixel then receives its contributions in one fixed order (phase,
//! then row, pixel and sample), whatever the thread count. With the box
//! filter (reach 0) this is one phase of one-row windows: a pixel adds its
//! own samples alone, as before splatting.

use rayon::prelude::*;

use crate::film::{Bands, Film, SampleCounts};
use crate::guiding::{RowStats, Stats};
use crate::sampling::sobol::Sampler;

use super::renderer::{Renderer, Scratchpad};
use super::select::Integrator;
use super::{bdpt, wavefront, CameraSample, Splat, Tracer};

/// The part of the film one row's samples may add to: rows `first..` of
/// the pixels, band sums and moments.
struct Window<'a> {
    /// The row rendered.
    y: usize,
    /// The window's first row.
    first: usize,
    pixels: &'a mut [crate::film::PixelSum],
    spectral: &'a mut [f64],
    moments: &'a mut [[f64; 4]],
}

/// What one row's samples return besides their sums.
type RowOut<const K: usize> = (usize, SampleCounts, Vec<Splat<K>>, RowStats);

/// Splits `data` (rows of `row_len` values) into the windows of phase
/// `phase`: (first row, values) for each row y = phase, phase + period, …,
/// covering rows y − reach ..= y + reach within the film. Consecutive
/// windows abut, so they are disjoint.
fn windows<T>(
    data: &mut [T],
    row_len: usize,
    height: usize,
    phase: usize,
    reach: usize,
) -> Vec<(usize, usize, &mut [T])> {
    let period = 2 * reach + 1;
    let mut rest = data;
    let mut at = 0;
    let mut out = Vec::new();
    for y in (phase..height).step_by(period) {
        let (start, end) = (y.saturating_sub(reach), (y + reach + 1).min(height));
        let (_, tail) = std::mem::take(&mut rest).split_at_mut((start - at) * row_len);
        let (window, tail) = tail.split_at_mut((end - start) * row_len);
        out.push((y, start, window));
        rest = tail;
        at = end;
    }
    out
}

impl Renderer<'_> {
    /// How many rows and columns away a camera sample adds to: the
    /// filter's reach, or 0 for an irradiance meter, whose pixels are
    /// each a whole measurement, not part of an image.
    fn reach(&self) -> usize {
        match self.integrator {
            Integrator::Meter(_) => 0,
            _ => self.filter.reach(),
        }
    }

    /// Adds samples `first..first + count` to every pixel of the film,
    /// each weighing `weight` (1 but for the guide's first learning
    /// iterations, `learn.rs`); while the guide learns, their records to
    /// `stats`.
    pub(super) fn pass<const K: usize>(
        &self,
        seed: u32,
        film: &mut Film,
        (first, count, weight): (u32, u32, f32),
        stats: Option<&mut Stats>,
    ) -> SampleCounts {
        let learning = stats.is_some();
        let (width, height) = (film.width as usize, film.height as usize);
        let (stride, moment_stride) = (film.row_stride(), film.moment_stride());
        let moments_kept = film.kept_moments().is_some();
        let bands = film.bands;
        let reach = self.reach();
        let mut rows: Vec<RowOut<K>> = Vec::with_capacity(height);
        for phase in 0..(2 * reach + 1).min(height.max(1)) {
            let pixels = windows(&mut film.pixels, width, height, phase, reach);
            let spectral = windows(&mut film.spectral, stride, height, phase, reach);
            let moments = windows(&mut film.moments, moment_stride, height, phase, reach);
            let work: Vec<Window> = pixels
                .into_iter()
                .zip(spectral)
                .zip(moments)
                .map(
                    |(((y, first, pixels), (_, _, spectral)), (_, _, moments))| Window {
                        y,
                        first,
                        pixels,
                        spectral,
                        moments,
                    },
                )
                .collect();
            let job = RowJob {
                seed,
                first,
                count,
                width,
                height,
                reach,
                bands,
                moments_kept,
                learning,
                weight,
            };
            rows.par_extend(work.into_par_iter().map(|w| self.render_row::<K>(&job, w)));
        }
        // Light-tracing splats land on any pixel: added after the pass, row
        // by row in order, so the sums do not depend on the threads.
        // So are the guide's records.
        rows.sort_by_key(|r| r.0);
        let mut total = SampleCounts::default();
        let mut stats = stats;
        for (_, c, splats, row_stats) in rows {
            total += c;
            if let Some(stats) = stats.as_deref_mut() {
                stats.add(&row_stats);
            }
            for sp in &splats {
                // × 1 is exact: unweighted passes add the same bits.
                let xyzv = sp.xyzv.map(|v| v * weight);
                film.splat(
                    &self.filter,
                    sp.raster,
                    xyzv,
                    &(sp.radiance * weight),
                    &sp.wl,
                );
            }
        }
        total
    }

    /// The samples of row `w.y`, added into its window.
    fn render_row<const K: usize>(&self, job: &RowJob, w: Window<'_>) -> RowOut<K> {
        let y = w.y;
        if !self.rows.contains(&(y as u32)) || !(y as u32).is_multiple_of(self.row_step) {
            return (y, SampleCounts::default(), Vec::new(), RowStats::default());
        }
        let RowJob {
            seed,
            first,
            count,
            width,
            ..
        } = *job;
        let mut sampler = Sampler::new(seed);
        let mut lander = Sampler::new(seed);
        let mut counts = SampleCounts::default();
        let mut scratch = bdpt::Scratch::<K>::default();
        let mut splats = Vec::new();
        let mut records = Vec::new();
        let mut batch = matches!(self.integrator, Integrator::Path(Tracer::Wavefront)).then(|| {
            let work = wavefront::RowWork {
                seed,
                y: y as u32,
                width: width as u32,
                first,
                count,
            };
            wavefront::trace_row::<K>(self, work, &mut counts.rays).into_iter()
        });
        let mut sums = Sums {
            job,
            w,
            filter: &self.filter,
            wx: Vec::with_capacity(2 * job.reach + 1),
        };
        for x in 0..width {
            for i in first..first + count {
                let pixel = [x as u32, y as u32];
                let sample = match &mut batch {
                    Some(done) => done.next().flatten(),
                    None => {
                        let to = Scratchpad {
                            scratch: &mut scratch,
                            splats: &mut splats,
                            counts: &mut counts,
                            records: &mut records,
                        };
                        self.estimate::<K>(&mut sampler, pixel, i, to)
                    }
                };
                match sample {
                    Some(s) => {
                        counts.collapsed += s.collapsed as u64;
                        splats.extend(s.seen);
                        let offset = if job.reach == 0 {
                            [0.0; 2]
                        } else {
                            // Where it landed: the sample's first two numbers.
                            lander.start(pixel, i);
                            let [fx, fy, _, _] = lander.get_4d();
                            self.filter.sample([fx, fy])
                        };
                        sums.add(x, &s, offset);
                    }
                    None => counts.dropped += 1,
                }
            }
        }
        let stats = if job.learning {
            RowStats::of(records)
        } else {
            RowStats::default()
        };
        (y, counts, splats, stats)
    }
}

/// What every row of a pass shares.
struct RowJob {
    seed: u32,
    first: u32,
    count: u32,
    width: usize,
    height: usize,
    reach: usize,
    bands: Option<Bands>,
    moments_kept: bool,
    learning: bool,
    /// Each sample's weight in the pixels it reaches (and its splats').
    weight: f32,
}

/// A row's window and how to add a sample into it.
struct Sums<'a, 'w> {
    job: &'a RowJob,
    w: Window<'w>,
    filter: &'a crate::film::FilterSampler,
    /// The filter's weights along x for columns x − reach ..= x + reach
    /// (kept between samples, so a row allocates once).
    wx: Vec<f32>,
}

impl Sums<'_, '_> {
    /// Adds sample `s` of pixel (`x`, the window's row), which landed at
    /// `offset` from that pixel's centre, to every pixel the filter
    /// reaches from there.
    fn add<const K: usize>(&mut self, x: usize, s: &CameraSample<K>, offset: [f32; 2]) {
        let RowJob {
            width,
            height,
            reach,
            ..
        } = *self.job;
        let y = self.w.y;
        let own = (y - self.w.first) * width + x;
        self.w.pixels[own].samples += 1;
        if reach == 0 {
            self.add_to(own, x, s, self.job.weight);
            return;
        }
        let r = reach as isize;
        // Separable: the weights along x once, then each row's along y.
        let mut wx = std::mem::take(&mut self.wx);
        wx.clear();
        wx.extend((-r..=r).map(|dx| self.filter.axis_weight(offset[0] - dx as f32)));
        // The columns inside the image.
        let lo = (r - x as isize).max(0) as usize;
        let hi = (width as isize - x as isize + r).min(2 * r + 1) as usize;
        let plain = !self.job.moments_kept && self.job.bands.is_none();
        for dy in -r..=r {
            let row = y as isize + dy;
            if row < 0 || row >= height as isize {
                continue;
            }
            let fy = self.filter.axis_weight(offset[1] - dy as f32) * self.job.weight;
            if fy == 0.0 {
                continue;
            }
            let start = (row as usize - self.w.first) * width;
            for (i, &fx) in wx.iter().enumerate().take(hi).skip(lo) {
                let f = fy * fx;
                let col = x + i - reach;
                if plain {
                    // The common case, sums and weights alone.
                    self.w.pixels[start + col].add_weighted(s.xyzv, f);
                } else if f != 0.0 {
                    self.add_to(start + col, col, s, f);
                }
            }
        }
        self.wx = wx;
    }

    /// Adds `f` × sample `s` to the window's pixel `at` (column `col`).
    fn add_to<const K: usize>(&mut self, at: usize, col: usize, s: &CameraSample<K>, f: f32) {
        self.w.pixels[at].add_weighted(s.xyzv, f);
        let width = self.job.width;
        if self.job.moments_kept {
            for (m, v) in self.w.moments[at].iter_mut().zip(s.xyzv) {
                *m += f64::from(f) * f64::from(v) * f64::from(v);
            }
        }
        if let Some(b) = self.job.bands {
            let row = at / width;
            let start = row * b.0 * width + col * b.0;
            let sums = &mut self.w.spectral[start..start + b.0];
            if f == 1.0 {
                b.add(sums, &s.radiance, &s.wl);
            } else {
                b.add(sums, &(s.radiance * f), &s.wl);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::{windows, CameraSample, RowJob, Sums, Window};
    use crate::film::{Film, Filter, FilterSampler};
    use scotopia_color::{SampledSpectrum, SampledWavelengths};

    /// The Gaussian of σ ½ truncated at 2, along one axis, integrated
    /// over [a, b] by the midpoint rule (not the filter's own table).
    fn gauss_integral(a: f64, b: f64) -> f64 {
        let n = 20_000;
        let h = (b - a) / n as f64;
        (0..n)
            .map(|i| {
                let x = a + (i as f64 + 0.5) * h;
                if x.abs() < 2.0 {
                    (-x * x / 0.5).exp() * h
                } else {
                    0.0
                }
            })
            .sum()
    }

    /// A film lit by a vertical edge (radiance 1 right of x = 3.25, 0 left
    /// of it, between two columns of samples), 16 × 16 stratified samples
    /// a pixel, splatted phase by phase as a pass does: each pixel is the
    /// edge seen through the Gaussian, renormalised to the film at the
    /// borders (no dark frame).
    #[test]
    fn a_splatted_edge_is_the_edge_through_the_filter() {
        let (width, height, n) = (8usize, 6usize, 16usize);
        let filter = FilterSampler::new(Filter::Gaussian { stddev: 0.5 });
        let reach = filter.reach();
        let mut film = Film::new(width as u32, height as u32, None);
        let job = RowJob {
            seed: 0,
            first: 0,
            count: (n * n) as u32,
            width,
            height,
            reach,
            bands: None,
            moments_kept: false,
            learning: false,
            weight: 1.0,
        };
        let wl = SampledWavelengths::<4>::new([550.0; 4], [1.0; 4]);
        for phase in 0..2 * reach + 1 {
            let pixels = windows(&mut film.pixels, width, height, phase, reach);
            let spectral = windows(&mut film.spectral, 1, height, phase, reach);
            let moments = windows(&mut film.moments, 1, height, phase, reach);
            for (((y, first, pixels), (_, _, spectral)), (_, _, moments)) in
                pixels.into_iter().zip(spectral).zip(moments)
            {
                let w = Window {
                    y,
                    first,
                    pixels,
                    spectral,
                    moments,
                };
                let mut sums = Sums {
                    job: &job,
                    w,
                    filter: &filter,
                    wx: Vec::new(),
                };
                for x in 0..width {
                    for i in 0..n * n {
                        let u = [
                            ((i % n) as f32 + 0.5) / n as f32,
                            ((i / n) as f32 + 0.5) / n as f32,
                        ];
                        let offset = filter.sample(u);
                        let at = x as f32 + 0.5 + offset[0];
                        let l = if at > 3.25 { 1.0 } else { 0.0 };
                        let s = CameraSample {
                            xyzv: [l; 4],
                            radiance: SampledSpectrum::splat(l),
                            wl,
                            collapsed: false,
                            seen: None,
                        };
                        sums.add(x, &s, offset);
                    }
                }
            }
        }
        for y in 0..height {
            for x in 0..width {
                let p = film.pixels[y * width + x];
                assert_eq!(p.samples, (n * n) as u32);
                let c = x as f64 + 0.5;
                // ∫ over the film of f(t − c)·L(t) / ∫ over the film of f.
                let want = gauss_integral(3.25 - c, width as f64 - c)
                    / gauss_integral(-c, width as f64 - c);
                let got = f64::from(p.mean()[1]);
                assert!(
                    (got - want).abs() < 4e-3,
                    "({x}, {y}): {got} against {want}"
                );
            }
        }
        // The edge's pixel is between, the far ones are 0 and 1 (borders
        // renormalised, not darkened).
        assert!(film.pixels[3].mean()[1] > 0.1 && film.pixels[3].mean()[1] < 0.9);
        assert_eq!(film.pixels[0].mean()[1], 0.0);
        assert!((film.pixels[width - 1].mean()[1] - 1.0).abs() < 1e-6);
    }

    #[test]
    fn each_phase_s_windows_are_disjoint_and_every_row_is_rendered_once() {
        for (height, reach) in [(1, 0), (5, 0), (1, 2), (3, 2), (7, 2), (12, 2), (10, 1)] {
            let mut rendered = vec![0; height];
            for phase in 0..(2 * reach + 1).min(height) {
                let mut data: Vec<usize> = (0..height * 3).collect();
                let ws = windows(&mut data, 3, height, phase, reach);
                let mut covered = vec![false; height];
                for (y, first, w) in ws {
                    rendered[y] += 1;
                    assert_eq!(first, y.saturating_sub(reach));
                    assert_eq!(w[0], first * 3, "the window starts at its first row");
                    let rows = w.len() / 3;
                    assert_eq!(first + rows, (y + reach + 1).min(height));
                    for (r, c) in covered.iter_mut().enumerate().skip(first).take(rows) {
                        assert!(!*c, "row {r} in two windows");
                        *c = true;
                    }
                }
            }
            assert!(
                rendered.iter().all(|&n| n == 1),
                "{height} {reach}: {rendered:?}"
            );
        }
    }
}

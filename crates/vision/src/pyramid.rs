//! Gaussian and Laplacian (band-pass) pyramids (Burt & Adelson 1983, "The
//! Laplacian Pyramid as a Compact Image Code"): each level is the one above
//! blurred by the 5-tap binomial kernel [1 4 6 4 1]/16 and halved; a band is
//! a level minus the next coarser level brought back up to its size. The
//! bands and the coarsest level sum back to the image exactly, whatever is
//! done to them in between — which is what the multiscale model needs.

use rayon::prelude::*;

/// One channel of an image, row-major, top row first.
#[derive(Debug, Clone, PartialEq)]
pub struct Plane {
    pub width: usize,
    pub height: usize,
    pub data: Vec<f32>,
}

impl Plane {
    pub fn new(width: usize, height: usize, data: Vec<f32>) -> Self {
        debug_assert_eq!(data.len(), width * height);
        Self {
            width,
            height,
            data,
        }
    }

    pub fn filled(width: usize, height: usize, value: f32) -> Self {
        Self::new(width, height, vec![value; width * height])
    }
}

/// `n` zeros, written in parallel: a buffer about to be filled by
/// parallel passes. (`vec![0.0; n]` zeroes reused heap memory on the
/// calling thread alone.)
pub fn zeroed<T: Default + Clone + Send + Sync>(n: usize) -> Vec<T> {
    let mut v = Vec::with_capacity(n);
    v.par_extend(rayon::iter::repeat_n(T::default(), n));
    v
}

/// The binomial kernel [1 4 6 4 1]/16.
const TAPS: [f32; 5] = [1.0 / 16.0, 4.0 / 16.0, 6.0 / 16.0, 4.0 / 16.0, 1.0 / 16.0];

/// Blurs with the binomial kernel (edges clamped) and keeps every second
/// sample: the next Gaussian level, of size ⌈w/2⌉ × ⌈h/2⌉.
pub fn reduce(p: &Plane) -> Plane {
    let (w, h) = (p.width, p.height);
    let (nw, nh) = (w.div_ceil(2), h.div_ceil(2));
    // Horizontal pass on every row, keeping even columns.
    let mut rows = vec![0.0f32; nw * h];
    rows.par_chunks_mut(nw)
        .zip(p.data.par_chunks(w))
        .for_each(|(out, row)| reduce_row(row, out));
    // Vertical pass, keeping even rows.
    let mut data = vec![0.0f32; nw * nh];
    data.par_chunks_mut(nw).enumerate().for_each(|(j, out)| {
        let r = taps_rows(j, h).map(|yy| &rows[yy * nw..(yy + 1) * nw]);
        reduce_column(r, out);
    });
    Plane::new(nw, nh, data)
}

/// The horizontal half of [`reduce`] on one row: blurred, even columns
/// kept; the taps are clamped only near the ends.
fn reduce_row(row: &[f32], out: &mut [f32]) {
    let w = row.len();
    let clamp = |i: i64| i.clamp(0, w as i64 - 1) as usize;
    for (i, o) in out.iter_mut().enumerate() {
        let x = 2 * i;
        *o = if x >= 2 && x + 2 < w {
            let t = &row[x - 2..x + 3];
            TAPS[0] * (t[0] + t[4]) + TAPS[1] * (t[1] + t[3]) + TAPS[2] * t[2]
        } else {
            (0..5)
                .map(|k| TAPS[k] * row[clamp(x as i64 + k as i64 - 2)])
                .sum()
        };
    }
}

/// The rows (clamped to `h`) whose horizontal passes make output row `j`.
fn taps_rows(j: usize, h: usize) -> [usize; 5] {
    std::array::from_fn(|k| (2 * j as i64 + k as i64 - 2).clamp(0, h as i64 - 1) as usize)
}

/// The vertical half of [`reduce`]: five horizontally reduced rows
/// combined into one output row.
fn reduce_column(r: [&[f32]; 5], out: &mut [f32]) {
    for (x, o) in out.iter_mut().enumerate() {
        *o = TAPS[0] * (r[0][x] + r[4][x]) + TAPS[1] * (r[1][x] + r[3][x]) + TAPS[2] * r[2][x];
    }
}

/// [`reduce`] of four planes that are never stored: `fill(y, rows)`
/// writes row y (`width` values) of each into `rows`. Bands of output rows
/// are made from their own horizontal passes (the two rows at a band's
/// edge are passed twice), so neither the full-size planes nor their
/// half-width horizontal passes are ever allocated — a fresh process
/// pays for every page it touches. The result equals `reduce` of each
/// plane exactly.
pub fn reduce4(
    width: usize,
    height: usize,
    fill: impl Fn(usize, &mut [Vec<f32>; 4]) + Sync,
) -> [Plane; 4] {
    const BAND: usize = 16;
    let (nw, nh) = (width.div_ceil(2), height.div_ceil(2));
    let mut out: [Vec<f32>; 4] = std::array::from_fn(|_| zeroed(nw * nh));
    let [a, b, c, d] = &mut out;
    a.par_chunks_mut(BAND * nw)
        .zip(b.par_chunks_mut(BAND * nw))
        .zip(c.par_chunks_mut(BAND * nw))
        .zip(d.par_chunks_mut(BAND * nw))
        .enumerate()
        .for_each_init(
            || {
                let rows = (2 * BAND + 3) * nw;
                let source: [Vec<f32>; 4] = std::array::from_fn(|_| vec![0.0; width]);
                (source, std::array::from_fn(|_| vec![0.0f32; rows]))
            },
            |(source, passed): &mut ([Vec<f32>; 4], [Vec<f32>; 4]), (band, (((a, b), c), d))| {
                let j0 = band * BAND;
                let j1 = j0 + a.len() / nw;
                let first = taps_rows(j0, height)[0];
                let last = taps_rows(j1 - 1, height)[4];
                for y in first..=last {
                    fill(y, source);
                    let at = (y - first) * nw;
                    for (src, pass) in source.iter().zip(passed.iter_mut()) {
                        reduce_row(src, &mut pass[at..at + nw]);
                    }
                }
                for (plane, pass) in [a, b, c, d].into_iter().zip(passed.iter()) {
                    for (j, out) in (j0..j1).zip(plane.chunks_mut(nw)) {
                        let r = taps_rows(j, height).map(|yy| &pass[(yy - first) * nw..][..nw]);
                        reduce_column(r, out);
                    }
                }
            },
        );
    out.map(|data| Plane::new(nw, nh, data))
}

/// Bilinear resampling between two grid sizes, sample centres aligned
/// (destination pixel x sits at source coordinate (x + ½)·w_src/w_dst − ½,
/// clamped at the edges), row by row so callers can fuse it with their own
/// per-pixel work instead of holding whole expanded planes.
pub struct Bilinear {
    src_width: usize,
    /// Per destination column, the two source columns and the weight of
    /// the second, as separate arrays (u32: the wide loop gathers by them).
    cols: Columns,
    rows: Vec<(usize, usize, f32)>,
}

impl Bilinear {
    pub fn new(src: (usize, usize), dst: (usize, usize)) -> Self {
        let taps = |n_src: usize, n_dst: usize| -> Vec<(usize, usize, f32)> {
            let s = n_src as f32 / n_dst as f32;
            (0..n_dst)
                .map(|i| {
                    let c = ((i as f32 + 0.5) * s - 0.5).clamp(0.0, (n_src - 1) as f32);
                    let i0 = c.floor() as usize;
                    (i0, (i0 + 1).min(n_src - 1), c - i0 as f32)
                })
                .collect()
        };
        Self {
            src_width: src.0,
            cols: Columns::of(&taps(src.0, dst.0)),
            rows: taps(src.1, dst.1),
        }
    }

    /// Row `y` of the resampled `src` (row-major, the source size) into
    /// `out` (the destination width): the two source rows blended
    /// vertically, each source column once (an enlargement reads each
    /// about twice), then interpolated across. It runs once per row of
    /// every band, so the blended row lives in a per-thread buffer.
    pub fn row(&self, src: &[f32], y: usize, out: &mut [f32]) {
        thread_local! {
            static BLENDED: std::cell::RefCell<Vec<f32>> = const { std::cell::RefCell::new(Vec::new()) };
        }
        let (y0, y1, fy) = self.rows[y];
        let w = self.src_width;
        let top = &src[y0 * w..(y0 + 1) * w];
        let bottom = &src[y1 * w..(y1 + 1) * w];
        BLENDED.with_borrow_mut(|blended| {
            blended.resize(w, 0.0);
            let cols = &self.cols;
            crate::wide_math::dispatch(
                #[inline(always)]
                || blend_row(top, bottom, fy, cols, blended, out),
            );
        });
    }
}

/// [`Bilinear::row`]'s arithmetic: rows `top` and `bottom` blended by
/// `fy` into `blended`, then interpolated across by `cols` into `out`.
#[inline(always)]
fn blend_row(
    top: &[f32],
    bottom: &[f32],
    fy: f32,
    cols: &Columns,
    blended: &mut [f32],
    out: &mut [f32],
) {
    for ((m, &t), &b) in blended.iter_mut().zip(top).zip(bottom) {
        *m = t + fy * (b - t);
    }
    let blended = &*blended;
    let n = out.len().min(cols.first.len());
    let (out, first, second, weight) = (
        &mut out[..n],
        &cols.first[..n],
        &cols.second[..n],
        &cols.weight[..n],
    );
    for x in 0..n {
        // (Every index is inside the source row: `get` only keeps the
        // loop free of a panic branch.)
        let a = blended.get(first[x] as usize).copied().unwrap_or(0.0);
        let b = blended.get(second[x] as usize).copied().unwrap_or(0.0);
        out[x] = a + weight[x] * (b - a);
    }
}

/// [`Bilinear`]'s column taps.
struct Columns {
    first: Vec<u32>,
    second: Vec<u32>,
    weight: Vec<f32>,
}

impl Columns {
    fn of(taps: &[(usize, usize, f32)]) -> Self {
        Self {
            first: taps.iter().map(|t| t.0 as u32).collect(),
            second: taps.iter().map(|t| t.1 as u32).collect(),
            weight: taps.iter().map(|t| t.2).collect(),
        }
    }
}

/// Brings a coarser level up to `width` × `height` by bilinear
/// interpolation ([`Bilinear`]).
pub fn expand(p: &Plane, width: usize, height: usize) -> Plane {
    let b = Bilinear::new((p.width, p.height), (width, height));
    let mut data = vec![0.0f32; width * height];
    data.par_chunks_mut(width)
        .enumerate()
        .for_each(|(y, out)| b.row(&p.data, y, out));
    Plane::new(width, height, data)
}

/// The Gaussian pyramid: `levels` planes, the image first, each next one
/// reduced, stopping early when a level would be smaller than 2 × 2.
pub fn gaussian(image: Plane, levels: usize) -> Vec<Plane> {
    let mut out = vec![image];
    while out.len() < levels.max(1) {
        let last = out.last().expect("the pyramid starts with the image");
        if last.width < 4 || last.height < 4 {
            break;
        }
        out.push(reduce(last));
    }
    out
}

/// For each Gaussian level but the last: the next coarser level expanded
/// to its size (the local mean around each pixel at that scale).
pub fn expanded_coarser(levels: &[Plane]) -> Vec<Plane> {
    levels
        .windows(2)
        .map(|pair| expand(&pair[1], pair[0].width, pair[0].height))
        .collect()
}

/// Sums band-pass planes (finest first) onto the coarsest level: the
/// inverse of taking bands `G_n − expand(G_{n+1})`.
pub fn collapse(bands: &[Plane], coarsest: Plane) -> Plane {
    collapse_with(bands, coarsest, |up, band| up + band)
}

/// Collapses with `combine(expanded coarser level, band)` in place of the
/// sum, for models that add a band as a contrast on the local mean.
pub fn collapse_with(
    bands: &[Plane],
    coarsest: Plane,
    combine: impl Fn(f32, f32) -> f32 + Sync,
) -> Plane {
    let mut acc = coarsest;
    for band in bands.iter().rev() {
        let (w, h) = (band.width, band.height);
        let up = Bilinear::new((acc.width, acc.height), (w, h));
        let mut data = zeroed(w * h);
        data.par_chunks_mut(w)
            .zip(band.data.par_chunks(w))
            .enumerate()
            .for_each(|(y, (out, b))| {
                up.row(&acc.data, y, out);
                for (o, &b) in out.iter_mut().zip(b) {
                    *o = combine(*o, b);
                }
            });
        acc = Plane::new(w, h, data);
    }
    acc
}

#[cfg(test)]
mod tests {
    use super::*;

    fn ramp(w: usize, h: usize) -> Plane {
        let data = (0..w * h)
            .map(|i| ((i % w) as f32 * 0.7 + (i / w) as f32 * 1.3).sin() + 2.0)
            .collect();
        Plane::new(w, h, data)
    }

    #[test]
    fn reduce_halves_and_keeps_a_constant() {
        let p = reduce(&Plane::filled(9, 6, 3.5));
        assert_eq!((p.width, p.height), (5, 3));
        assert!(p.data.iter().all(|&v| (v - 3.5).abs() < 1e-6));
    }

    #[test]
    fn the_fused_reduction_of_four_planes_is_reduce_of_each() {
        // Sizes odd and even, under one band and over several.
        for (w, h) in [(37, 23), (64, 70), (5, 4), (9, 131)] {
            let planes: Vec<Plane> = (0..4)
                .map(|c| {
                    let mut p = ramp(w, h);
                    p.data.iter_mut().for_each(|v| *v *= 1.0 + c as f32);
                    p
                })
                .collect();
            let fused = reduce4(w, h, |y, rows| {
                for (row, p) in rows.iter_mut().zip(&planes) {
                    row.copy_from_slice(&p.data[y * w..(y + 1) * w]);
                }
            });
            for (f, p) in fused.iter().zip(&planes) {
                assert_eq!(*f, reduce(p), "{w}×{h}");
            }
        }
    }

    #[test]
    fn reduce_preserves_the_mean_of_a_smooth_image() {
        let img = ramp(64, 48);
        let mean = |p: &Plane| p.data.iter().sum::<f32>() / p.data.len() as f32;
        assert!((mean(&reduce(&img)) - mean(&img)).abs() < 0.02);
    }

    #[test]
    fn bands_and_the_coarsest_level_rebuild_the_image() {
        let img = ramp(37, 23);
        let g = gaussian(img.clone(), 5);
        assert_eq!(g.len(), 4, "stops before a level under 2×2");
        let up = expanded_coarser(&g);
        let bands: Vec<Plane> = g
            .iter()
            .zip(&up)
            .map(|(level, u)| {
                Plane::new(
                    level.width,
                    level.height,
                    level.data.iter().zip(&u.data).map(|(a, b)| a - b).collect(),
                )
            })
            .collect();
        let back = collapse(&bands, g.last().unwrap().clone());
        let err = back
            .data
            .iter()
            .zip(&img.data)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f32::max);
        assert!(err < 1e-5, "{err}");
    }
}

//! Resampling helpers of the vision stages: bilinear rows between two
//! grid sizes (the glare's coarse grid back to the image) and buffers
//! zeroed in parallel.

use rayon::prelude::*;

/// `n` zeros, written in parallel: a buffer about to be filled by
/// parallel passes. (`vec![0.0; n]` zeroes reused heap memory on the
/// calling thread alone.)
pub fn zeroed<T: Default + Clone + Send + Sync>(n: usize) -> Vec<T> {
    let mut v = Vec::with_capacity(n);
    v.par_extend(rayon::iter::repeat_n(T::default(), n));
    v
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bilinear_rows_keep_constants_and_ramps() {
        // 4 × 3 → 8 × 6: a constant stays constant; a ramp in x stays a
        // ramp between the first and last source centres.
        let (sw, sh, dw, dh) = (4, 3, 8, 6);
        let up = Bilinear::new((sw, sh), (dw, dh));
        let constant = vec![2.5f32; sw * sh];
        let ramp: Vec<f32> = (0..sw * sh).map(|i| (i % sw) as f32).collect();
        let mut out = vec![0.0f32; dw];
        for y in 0..dh {
            up.row(&constant, y, &mut out);
            assert!(out.iter().all(|&v| (v - 2.5).abs() < 1e-6), "{out:?}");
            up.row(&ramp, y, &mut out);
            // Destination x sits at source (x + ½)/2 − ½, clamped.
            for (x, v) in out.iter().enumerate() {
                let want = ((x as f32 + 0.5) * 0.5 - 0.5).clamp(0.0, 3.0);
                assert!((v - want).abs() < 1e-6, "{x}: {v} vs {want}");
            }
        }
    }

    #[test]
    fn zeroed_is_zeros() {
        assert_eq!(zeroed::<f32>(5), vec![0.0; 5]);
    }
}

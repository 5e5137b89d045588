//! Two-dimensional FFTs for the glare convolution, planned once per grid.
//! A spectrum is kept column-major (index kx·height + ky): the forward
//! transform ends with the column pass and the inverse starts with it, so
//! each direction transposes once. Rows known to be zero (the padding
//! below the image) are not transformed, and the inverse transforms only
//! the rows the caller keeps.

use std::sync::Arc;

use rayon::prelude::*;
use rustfft::num_complex::Complex32;
use rustfft::{Fft, FftPlanner};

pub struct Fft2 {
    pub width: usize,
    pub height: usize,
    rows: Arc<dyn Fft<f32>>,
    cols: Arc<dyn Fft<f32>>,
    rows_inverse: Arc<dyn Fft<f32>>,
    cols_inverse: Arc<dyn Fft<f32>>,
}

impl Fft2 {
    pub fn new(width: usize, height: usize) -> Self {
        let mut planner = FftPlanner::<f32>::new();
        Self {
            width,
            height,
            rows: planner.plan_fft_forward(width),
            cols: planner.plan_fft_forward(height),
            rows_inverse: planner.plan_fft_inverse(width),
            cols_inverse: planner.plan_fft_inverse(height),
        }
    }

    /// The spectrum (column-major) of the row-major `data`, whose rows from
    /// `filled_rows` on are zero. `data` is used as scratch.
    pub fn forward(&self, data: &mut [Complex32], filled_rows: usize) -> Vec<Complex32> {
        let (w, h) = (self.width, self.height);
        run(&self.rows, &mut data[..filled_rows * w], w);
        // Transposed as it is made, in parallel (not zeroed first on one
        // thread).
        let data = &*data;
        let mut spectrum = Vec::with_capacity(w * h);
        spectrum.par_extend((0..w * h).into_par_iter().map(|i| {
            let (x, y) = (i / h, i % h);
            if y < filled_rows {
                data[y * w + x]
            } else {
                Complex32::new(0.0, 0.0)
            }
        }));
        run(&self.cols, &mut spectrum, h);
        spectrum
    }

    /// The first `rows` rows (row-major, unnormalised: times width·height)
    /// of the inverse transform of a column-major `spectrum`, which is used
    /// as scratch.
    pub fn inverse(&self, spectrum: &mut [Complex32], rows: usize) -> Vec<Complex32> {
        let (w, h) = (self.width, self.height);
        run(&self.cols_inverse, spectrum, h);
        let spectrum = &*spectrum;
        let mut out = Vec::with_capacity(w * rows);
        out.par_extend(
            (0..w * rows)
                .into_par_iter()
                .map(|i| spectrum[(i % w) * h + i / w]),
        );
        run(&self.rows_inverse, &mut out, w);
        out
    }
}

/// Transforms each `len`-long chunk of `data`, in parallel.
fn run(fft: &Arc<dyn Fft<f32>>, data: &mut [Complex32], len: usize) {
    let scratch = fft.get_inplace_scratch_len();
    data.par_chunks_mut(len).for_each_init(
        || vec![Complex32::new(0.0, 0.0); scratch],
        |s, chunk| fft.process_with_scratch(chunk, s),
    );
}

/// The smallest n ≥ `min` whose only prime factors are 2, 3 and 5, where
/// FFTs are fastest.
pub fn smooth_size(min: usize) -> usize {
    (min.max(1)..)
        .find(|&n| {
            let mut m = n;
            for p in [2, 3, 5] {
                while m % p == 0 {
                    m /= p;
                }
            }
            m == 1
        })
        .expect("5-smooth numbers are unbounded")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_a_delta_transforms_to_ones() {
        let (w, h) = (6, 4);
        let fft = Fft2::new(w, h);
        // The last row is zero: the forward transform may skip it.
        let orig: Vec<Complex32> = (0..w * h)
            .map(|i| Complex32::new(if i < w * 3 { i as f32 } else { 0.0 }, 0.5))
            .map(|v| {
                if v.re == 0.0 {
                    Complex32::new(0.0, 0.0)
                } else {
                    v
                }
            })
            .collect();
        let mut d = orig.clone();
        let mut spectrum = fft.forward(&mut d, 3);
        let back = fft.inverse(&mut spectrum, 3);
        for (a, b) in back.iter().zip(&orig) {
            assert!((a / (w * h) as f32 - b).norm() < 1e-4, "{a} {b}");
        }
        let mut delta = vec![Complex32::new(0.0, 0.0); w * h];
        delta[0] = Complex32::new(1.0, 0.0);
        let spectrum = fft.forward(&mut delta, 1);
        assert!(spectrum
            .iter()
            .all(|v| (v.re - 1.0).abs() < 1e-6 && v.im.abs() < 1e-6));
    }

    #[test]
    fn the_spectrum_is_column_major() {
        // A wave along x only: energy at (kx = 1, ky = 0) and its mirror.
        let (w, h) = (8, 4);
        let fft = Fft2::new(w, h);
        let mut d: Vec<Complex32> = (0..w * h)
            .map(|i| {
                let x = (i % w) as f32;
                Complex32::new((std::f32::consts::TAU * x / w as f32).cos(), 0.0)
            })
            .collect();
        let s = fft.forward(&mut d, h);
        assert!((s[h].re - (w * h) as f32 / 2.0).abs() < 1e-3);
        assert!(s[1].norm() < 1e-3, "ky = 1 must be empty");
    }

    #[test]
    fn smooth_sizes() {
        assert_eq!(smooth_size(960), 960);
        assert_eq!(smooth_size(961), 972);
        assert_eq!(smooth_size(7), 8);
        assert_eq!(smooth_size(0), 1);
    }
}

//! Two-dimensional FFTs of row-major complex buffers (rows, then columns
//! through a transpose), for the glare convolution.

use rayon::prelude::*;
use rustfft::num_complex::Complex32;
use rustfft::{FftDirection, FftPlanner};

/// Transforms the `width` × `height` buffer in place.
pub fn fft2(data: &mut [Complex32], width: usize, height: usize, direction: FftDirection) {
    let mut planner = FftPlanner::<f32>::new();
    let rows = planner.plan_fft(width, direction);
    let cols = planner.plan_fft(height, direction);
    data.par_chunks_mut(width).for_each(|row| rows.process(row));
    let mut t = transpose(data, width, height);
    t.par_chunks_mut(height).for_each(|col| cols.process(col));
    data.copy_from_slice(&transpose(&t, height, width));
}

/// The transpose of a `width` × `height` row-major buffer.
fn transpose(data: &[Complex32], width: usize, height: usize) -> Vec<Complex32> {
    let mut out = vec![Complex32::new(0.0, 0.0); data.len()];
    out.par_chunks_mut(height).enumerate().for_each(|(x, col)| {
        for (y, v) in col.iter_mut().enumerate() {
            *v = data[y * width + x];
        }
    });
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_and_a_delta_transforms_to_ones() {
        let (w, h) = (6, 4);
        let mut d: Vec<Complex32> = (0..w * h).map(|i| Complex32::new(i as f32, 0.0)).collect();
        let orig = d.clone();
        fft2(&mut d, w, h, FftDirection::Forward);
        fft2(&mut d, w, h, FftDirection::Inverse);
        for (a, b) in d.iter().zip(&orig) {
            assert!((a.re / (w * h) as f32 - b.re).abs() < 1e-4);
        }
        let mut delta = vec![Complex32::new(0.0, 0.0); w * h];
        delta[0] = Complex32::new(1.0, 0.0);
        fft2(&mut delta, w, h, FftDirection::Forward);
        assert!(delta
            .iter()
            .all(|v| (v.re - 1.0).abs() < 1e-6 && v.im.abs() < 1e-6));
    }
}

//! The accuracy of a method on reflectances: RGB → spectrum → XYZ under the
//! space's white illuminant → compared with the RGB's own XYZ by CIEDE2000.

use rayon::prelude::*;

use super::weights::ReflectanceWeights;
use super::{rgb_to_spectrum, SpectrumKind, UpsampleMethod};
use crate::error::ColorError;
use crate::space::{delta_e_2000, xyz_to_lab, RgbSpace};

/// Round-trip statistics over a grid of the RGB cube.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RoundTrip {
    /// Largest and mean CIEDE2000.
    pub max_de: f64,
    pub mean_de: f64,
    /// The colour with the largest error.
    pub worst_rgb: [f32; 3],
    /// How many spectra leave [0, 1] somewhere in 360–830 nm.
    pub out_of_range: usize,
    pub count: usize,
}

/// The n×n×n grid {i/(n−1)}³ of the RGB cube.
pub fn rgb_cube(n: usize) -> Vec<[f32; 3]> {
    (0..n * n * n)
        .map(|i| [i % n, (i / n) % n, i / (n * n)].map(|v| v as f32 / (n - 1) as f32))
        .collect()
}

/// The finest grid `round_trip` measures: 256³ ≈ 16.8 million colours
/// (each an upsampling and a spectral integral).
pub const MAX_ROUND_TRIP_GRID: usize = 256;

/// Measures `method` on the n×n×n grid of `space`'s RGB cube, 2 ≤ n ≤
/// `MAX_ROUND_TRIP_GRID`.
pub fn round_trip(
    method: UpsampleMethod,
    space: RgbSpace,
    n: usize,
) -> Result<RoundTrip, ColorError> {
    if !(2..=MAX_ROUND_TRIP_GRID).contains(&n) {
        return Err(ColorError::OutOfRange(format!(
            "round-trip grid n = {n}: must be from 2 to {MAX_ROUND_TRIP_GRID}"
        )));
    }
    round_trip_colours(method, space, &rgb_cube(n))
}

/// Measures `method` on reflectance colours `grid` (linear RGB in `space`, in [0, 1]³).
pub fn round_trip_colours(
    method: UpsampleMethod,
    space: RgbSpace,
    grid: &[[f32; 3]],
) -> Result<RoundTrip, ColorError> {
    let weights = ReflectanceWeights::of(space);
    let def = space.def();
    let white = def.white_xyz();
    let errors: Vec<(f64, bool)> = grid
        .par_iter()
        .map(|&rgb| {
            let s = rgb_to_spectrum(rgb, space, method, SpectrumKind::Reflectance)?;
            let mut bounded = true;
            let xyz = weights.xyz(|l| {
                let v = s.eval(l);
                bounded &= (0.0..=1.0).contains(&v);
                v
            });
            let target = def.rgb_to_xyz(rgb.map(|v| v as f64));
            let de = delta_e_2000(xyz_to_lab(target, white), xyz_to_lab(xyz, white));
            Ok((de, !bounded))
        })
        .collect::<Result<_, ColorError>>()?;
    let (worst, max_de) = errors
        .iter()
        .enumerate()
        .map(|(i, e)| (i, e.0))
        .fold((0, 0.0f64), |a, b| if b.1 > a.1 { b } else { a });
    Ok(RoundTrip {
        max_de,
        mean_de: errors.iter().map(|e| e.0).sum::<f64>() / errors.len() as f64,
        worst_rgb: grid[worst],
        out_of_range: errors.iter().filter(|e| e.1).count(),
        count: errors.len(),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grids_out_of_range_are_errors() {
        for n in [0, 1, 257, 1_000_000_000_000] {
            let e = round_trip(UpsampleMethod::Smits, RgbSpace::Srgb, n).unwrap_err();
            assert!(e.to_string().contains("from 2 to 256"), "{e}");
        }
        assert_eq!(
            round_trip(UpsampleMethod::Smits, RgbSpace::Srgb, 2)
                .unwrap()
                .count,
            8
        );
    }
}

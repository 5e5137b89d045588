//! The inverse for the display: each pixel's receptor signals times their
//! gains, the rods' share moved to the cones, over the display's gain, and
//! back to X, Y, Z in display cd/m²; a row at a time, wide.

use rayon::prelude::*;

use super::gain::GainFunction;
use super::model::Model;
use super::receptors::{apply, receptors_with};
use crate::wide_math;

/// The per-pixel transcendental function of the model's rows: the wide
/// polynomial of `wide_math` in the pipeline, libm's in the reference.
pub(crate) trait RowMath {
    /// The receptor gain `g` at adaptation `i`.
    fn gain(g: &GainFunction, i: f32) -> f32;
}

/// libm's `powf` ([`GainFunction::gain`]): the reference.
pub(crate) struct Libm;

impl RowMath for Libm {
    #[inline(always)]
    fn gain(g: &GainFunction, i: f32) -> f32 {
        g.gain(i)
    }
}

/// `wide_math`'s: the same formula, vectorised.
pub(crate) struct Wide;

impl RowMath for Wide {
    #[inline(always)]
    fn gain(g: &GainFunction, i: f32) -> f32 {
        g.gain_wide(i)
    }
}

impl Model<'_> {
    /// Display X, Y, Z of each pixel of `pixels` (the image the model was
    /// built from), given to `put` with the pixel to overwrite. Rows run
    /// wide (`wide_math::dispatch`).
    pub(super) fn display<M: RowMath>(
        &self,
        pixels: &mut [[f32; 4]],
        put: impl Fn(&mut [f32; 4], [f32; 3]) + Sync,
    ) {
        let width = self.width.max(1);
        let k = PixelGains {
            fixed: self.fixed_gains,
            cones: self.p.cones,
            rods: self.p.rods,
            ratio: self.chroma_ratio,
            rod_cones: self.m.rod_cones,
            display_gain: self.display_gain,
            lms: self.m.lms,
            xyz: self.m.xyz,
        };
        pixels.par_chunks_mut(width).enumerate().for_each_init(
            || vec![[0.0f32; 3]; width],
            |out, (y, row)| {
                let w = row.len();
                let adapt = self.map.as_ref().map(|m| {
                    (
                        &m.cones[y * width..y * width + w],
                        &m.rods[y * width..y * width + w],
                    )
                });
                let input: &[[f32; 4]] = row;
                let shown = &mut out[..w];
                wide_math::dispatch(
                    #[inline(always)]
                    move || display_row::<M>(k, input, adapt, shown),
                );
                for (px, xyz) in row.iter_mut().zip(out.iter()) {
                    put(px, *xyz);
                }
            },
        );
    }
}
/// What a row's per-pixel loop reads besides the rows, by value: nothing
/// it reads can then alias what it writes, and the loop vectorises.
#[derive(Clone, Copy)]
struct PixelGains {
    /// With a global adaptation, the four receptors' gains.
    fixed: Option<[f32; 4]>,
    cones: GainFunction,
    rods: GainFunction,
    ratio: [f32; 3],
    rod_cones: [f32; 3],
    display_gain: f32,
    lms: [[f32; 3]; 3],
    xyz: [[f32; 3]; 3],
}

/// A row's display X, Y, Z into `out`: each pixel's receptor signals
/// times their gains at the pixel's adaptation (`adapt`: cone and rod
/// adaptation luminances; `None`: the fixed gains), rods joined to the
/// cones' achromatic channel, over the display's gain, back to X, Y, Z.
#[inline(always)]
fn display_row<M: RowMath>(
    k: PixelGains,
    input: &[[f32; 4]],
    adapt: Option<(&[f32], &[f32])>,
    out: &mut [[f32; 3]],
) {
    let w = out.len();
    let input = &input[..w];
    let finish = |px: &[f32; 4], g: [f32; 4]| -> [f32; 3] {
        let r = receptors_with(&k.lms, px);
        let responses = std::array::from_fn(|c| r[c] * g[c]);
        let cones = to_display_cones(k.rod_cones, responses).map(|v| (v / k.display_gain).max(0.0));
        apply(&k.xyz, cones).map(|v| v.max(0.0))
    };
    match (k.fixed, adapt) {
        (None, Some((ac, ar))) => {
            let (ac, ar) = (&ac[..w], &ar[..w]);
            for x in 0..w {
                let gc = M::gain(&k.cones, ac[x]);
                let g = [
                    gc * k.ratio[0],
                    gc * k.ratio[1],
                    gc * k.ratio[2],
                    M::gain(&k.rods, ar[x]),
                ];
                out[x] = finish(&input[x], g);
            }
        }
        (fixed, _) => {
            // A model is built with fixed gains or with a map.
            let g = fixed.unwrap_or([1.0; 4]);
            for x in 0..w {
                out[x] = finish(&input[x], g);
            }
        }
    }
}

/// Gain-controlled receptor signals [L, M, S, R] → the cone signals a
/// photopic display must produce to give the same opponent responses (its
/// rods are saturated): the rods' share of the achromatic channel moves
/// to the cones.
#[inline(always)]
pub(super) fn to_display_cones(rod_cones: [f32; 3], x: [f32; 4]) -> [f32; 3] {
    std::array::from_fn(|c| x[c] + x[3] * rod_cones[c])
}

//! The multiscale model of adaptation and spatial vision (Pattanaik,
//! Ferwerda, Fairchild & Greenberg 1998, SIGGRAPH, pp. 287–298), used as a
//! tone operator:
//!
//! 1. X, Y, Z → cone signals L, M, S (Hunt–Pointer–Estévez, normalised so
//!    D65 gives L = M = S = Y); the rod signal is V′ (`receptors`).
//! 2. Each pixel's adaptation state (`adaptation`, `model`): its cone and rod
//!    signals pooled over about half a degree around it, edge-aware, so
//!    each side of an edge adapts to itself and small highlights to their
//!    surround.
//! 3. Gain control: the paper gain-controls each band of a Laplacian
//!    pyramid at the next coarser level. Here every band of a pixel is
//!    gain-controlled at that pixel's adaptation state, so the bands sum
//!    back to the pixel's signal times one gain per receptor (where bands
//!    of one pixel had different gains, they no longer cancelled: rings
//!    around lamps and blocks from the coarse levels; docs/vision.md).
//!    Rods adapt on their own signal. Cones (scotopia's reading): the gain
//!    at the local *luminance*, times each cone type's von Kries ratio
//!    G(L_c)/G(L_Y) for the whole image (its mean cone signals at its
//!    log-average luminance); a literal per-cone local gain painted
//!    complementary-coloured halos at every colour edge.
//! 4. Opponent channels: achromatic A (the cones' luminance plus the rods)
//!    and chromatic C1 = L − M, C2 = (L + M)/2 − S.
//! 5. The inverse for the display (`display`): the same responses, with the display's
//!    cone gain at its adaptation luminance (rods are saturated there), back
//!    to L, M, S and to X, Y, Z in display cd/m².
//!
//! The paper passes each band's opponent signals through contrast
//! transducers and the display inverse through the same transducers; the
//! composition is the identity, so it is not evaluated (docs/vision.md).
//!
//! 6. The display's limit (scotopia's addition): the brightness match puts
//!    a scene's adaptation luminance La at La·G(La)/G(La_display) on the
//!    display, which for daylight (La ≳ 2000 cd/m²) is at or above the
//!    peak, so everything brighter than the mean was lost to white. The
//!    display image is scaled so that this level stays below a ceiling
//!    (`mean_ceiling` of the peak), smoothly: unchanged well below it
//!    (`params`).

mod adaptation;
mod display;
mod gain;
mod model;
mod params;
mod receptors;

pub use adaptation::{adaptation_map, AdaptationMap, Pooling};
pub use gain::GainFunction;
pub use params::{GainAdaptation, MultiscaleParams};

use display::{Libm, RowMath, Wide};
use model::Model;

/// Runs the model on `pixels` ([X, Y, Z, V′] in cd/m² and scotopic cd/m²,
/// `width` × `height`) and returns display X, Y, Z in cd/m² (negative
/// values clamped to 0; values above the peak are left for the gamut
/// mapper to handle).
pub fn multiscale(
    pixels: &[[f32; 4]],
    width: usize,
    height: usize,
    p: &MultiscaleParams,
) -> Vec<[f32; 3]> {
    run_with::<Wide>(pixels, width, height, p)
}

/// [`multiscale`] with libm's `powf` per pixel: the reference the wide
/// rows are tested against (they differ from it by an f32 ulp here and
/// there, multiscale's tests).
pub fn multiscale_libm(
    pixels: &[[f32; 4]],
    width: usize,
    height: usize,
    p: &MultiscaleParams,
) -> Vec<[f32; 3]> {
    run_with::<Libm>(pixels, width, height, p)
}

fn run_with<M: RowMath>(
    pixels: &[[f32; 4]],
    width: usize,
    height: usize,
    p: &MultiscaleParams,
) -> Vec<[f32; 3]> {
    let mut out = pixels.to_vec();
    Model::new(pixels, width, height, p)
        .display::<M>(&mut out, |o, xyz| *o = [xyz[0], xyz[1], xyz[2], 0.0]);
    out.into_iter().map(|q| [q[0], q[1], q[2]]).collect()
}

/// As [`multiscale`], writing pixel i's result `finish(&pixels[i],
/// display X, Y, Z)` over `pixels[i]`: the pipeline's tone operator, with
/// no full-size output buffer.
pub fn multiscale_in_place(
    pixels: &mut [[f32; 4]],
    width: usize,
    height: usize,
    p: &MultiscaleParams,
    finish: impl Fn(&[f32; 4], [f32; 3]) -> [f32; 4] + Sync,
) {
    // The model keeps its adaptation map, not the pixels, so they can be
    // overwritten.
    let model = Model::new(pixels, width, height, p);
    model.display::<Wide>(pixels, |q, xyz| *q = finish(q, xyz));
}

#[cfg(test)]
mod tests;

//! The multiscale model of adaptation and spatial vision (Pattanaik,
//! Ferwerda, Fairchild & Greenberg 1998, SIGGRAPH, pp. 287–298), used as a
//! tone operator:
//!
//! 1. X, Y, Z → cone signals L, M, S (Hunt–Pointer–Estévez, normalised so
//!    D65 gives L = M = S = Y); the rod signal is V′.
//! 2. A Gaussian pyramid per signal; band-pass images B_n = G_n − ↑G_{n+1}.
//! 3. Gain control: each band times G(↑G_{n+1}), the receptor's gain at the
//!    local adaptation of the next coarser level. Rods adapt on their own.
//!    Cones (scotopia's reading, see docs/vision.md): the gain at the local
//!    *luminance* of that level, times each cone type's von Kries ratio
//!    G(L_c)/G(L_Y) taken at the coarsest level. Letting each cone type
//!    adapt per pixel at every scale, as a literal reading would, painted
//!    complementary-coloured halos at every colour edge (violet skies beside
//!    sodium-lit walls); this keeps chromatic adaptation and chroma
//!    consistent across scales.
//! 4. Opponent channels: achromatic A (the cones' luminance plus the rods)
//!    and chromatic C1 = L − M, C2 = (L + M)/2 − S.
//! 5. The inverse for the display: the same responses, with the display's
//!    cone gain at its adaptation luminance (rods are saturated there), back
//!    to L, M, S per band, collapsed, and to X, Y, Z in display cd/m².
//!
//! The paper passes each band's opponent signals through contrast
//! transducers and the display inverse through the same transducers; the
//! composition is the identity, so it is not evaluated (docs/vision.md).
//! The coarsest level is gain-controlled at its own luminance.

mod gain;

pub use gain::GainFunction;

use rayon::prelude::*;
use scotopia_color::space::Cat;
use scotopia_color::{Mat3, RgbSpace};

use crate::pyramid::{collapse_with, expand, expanded_coarser, gaussian, Plane};

/// What the eye adapts to in the model's gain control.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GainAdaptation {
    /// Per pixel and per scale, from the next coarser pyramid level (the
    /// paper's model).
    Local,
    /// One photopic luminance (cd/m²) for the whole image; cone and rod
    /// adaptation follow from the image's mean chromaticity and S/P ratio.
    Global(f64),
}

/// Every constant of the model, overridable.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MultiscaleParams {
    /// Pyramid levels (the image is level 0); fewer when the image is small.
    pub levels: usize,
    pub cones: GainFunction,
    pub rods: GainFunction,
    /// The display's peak luminance, cd/m².
    pub display_peak: f64,
    /// The luminance the viewer of the display is adapted to, cd/m²
    /// (`None`: half the peak).
    pub display_adaptation: Option<f64>,
    pub adaptation: GainAdaptation,
}

impl Default for MultiscaleParams {
    fn default() -> Self {
        Self {
            levels: 7,
            cones: GainFunction::CONES,
            rods: GainFunction::RODS,
            display_peak: 100.0,
            display_adaptation: None,
            adaptation: GainAdaptation::Local,
        }
    }
}

/// XYZ → LMS (Hunt–Pointer–Estévez rows scaled so D65 gives 1, 1, 1), its
/// inverse, and the opponent transform with its inverse.
struct Matrices {
    lms: Mat3,
    xyz: Mat3,
    opponent: Mat3,
    from_opponent: Mat3,
}

impl Matrices {
    fn new() -> Self {
        let hpe = Cat::VonKries.matrix();
        let white = hpe.apply(RgbSpace::Srgb.def().white_xyz());
        let lms = Mat3::diagonal(white.map(|w| 1.0 / w)) * hpe;
        let xyz = lms.inverse().expect("the cone matrix is invertible");
        // A is the cones' luminance: the Y row of LMS → XYZ.
        let opponent = Mat3([xyz.0[1], [1.0, -1.0, 0.0], [0.5, 0.5, -1.0]]);
        let from_opponent = opponent
            .inverse()
            .expect("the opponent matrix is invertible");
        Self {
            lms,
            xyz,
            opponent,
            from_opponent,
        }
    }
}

fn apply32(m: &Mat3, v: [f32; 3]) -> [f32; 3] {
    m.apply(v.map(f64::from)).map(|x| x as f32)
}

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
    let m = Matrices::new();
    // Receptor planes L, M, S, R.
    let mut planes: [Vec<f32>; 4] = Default::default();
    for plane in planes.iter_mut() {
        plane.reserve(pixels.len());
    }
    for px in pixels {
        let clean = px.map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 });
        let lms = apply32(&m.lms, [clean[0], clean[1], clean[2]]);
        for c in 0..3 {
            planes[c].push(lms[c]);
        }
        planes[3].push(clean[3]);
    }
    let pyramids: Vec<Vec<Plane>> = planes
        .into_iter()
        .map(|data| gaussian(Plane::new(width, height, data), p.levels))
        .collect();
    let global = match p.adaptation {
        GainAdaptation::Local => None,
        GainAdaptation::Global(la) => Some(global_adaptation(pixels, &m, la)),
    };
    let la_d = p.display_adaptation.unwrap_or(p.display_peak / 2.0) as f32;
    let display_gain = p.cones.gain(la_d);
    let gains = [p.cones, p.cones, p.cones, p.rods];

    let n = pyramids[0].len();
    let coarse: Vec<Vec<Plane>> = pyramids.iter().map(|g| expanded_coarser(g)).collect();
    // Display L, M, S per band.
    let mut bands: [Vec<Plane>; 3] = Default::default();
    let luminance = |lms: [f32; 3]| -> f32 {
        let y = m.xyz.0[1];
        (y[0] * lms[0] as f64 + y[1] * lms[1] as f64 + y[2] * lms[2] as f64) as f32
    };
    // Each cone type's von Kries ratio G(L_c)/G(L_Y) on the coarsest level
    // (one value per receptor with a global adaptation).
    let chroma_ratio: Vec<Plane> = {
        let last = &pyramids[0][n - 1];
        let cells = last.width * last.height;
        let mut planes: Vec<Vec<f32>> = (0..3).map(|_| Vec::with_capacity(cells)).collect();
        for i in 0..cells {
            let wide: [f32; 3] =
                std::array::from_fn(|c| global.map_or(pyramids[c][n - 1].data[i], |g| g[c]));
            let wide_y = p.cones.gain(luminance(wide));
            for c in 0..3 {
                planes[c].push(p.cones.gain(wide[c]) / wide_y);
            }
        }
        planes
            .into_iter()
            .map(|d| Plane::new(last.width, last.height, d))
            .collect()
    };
    for level in 0..n - 1 {
        let (w, h) = (pyramids[0][level].width, pyramids[0][level].height);
        let ratio: Vec<Plane> = chroma_ratio.iter().map(|r| expand(r, w, h)).collect();
        let mut out = [
            vec![0.0f32; w * h],
            vec![0.0f32; w * h],
            vec![0.0f32; w * h],
        ];
        let [o0, o1, o2] = &mut out;
        o0.par_iter_mut()
            .zip(o1.par_iter_mut())
            .zip(o2.par_iter_mut())
            .enumerate()
            .for_each(|(i, ((l, mm), s))| {
                let adapt: [f32; 4] =
                    std::array::from_fn(|c| global.map_or(coarse[c][level].data[i], |g| g[c]));
                // Cones: luminance gain at this scale's local adaptation,
                // times each cone's chromatic gain ratio at the widest
                // scale (see the module notes).
                let local = p.cones.gain(luminance([adapt[0], adapt[1], adapt[2]]));
                let x: [f32; 4] = std::array::from_fn(|c| {
                    let gain = if c == 3 {
                        p.rods.gain(adapt[3])
                    } else {
                        local * ratio[c].data[i]
                    };
                    (pyramids[c][level].data[i] - coarse[c][level].data[i]) * gain
                });
                let lms = to_display_cones(&m, x);
                [*l, *mm, *s] = lms.map(|v| v / display_gain);
            });
        for (c, o) in out.into_iter().enumerate() {
            bands[c].push(Plane::new(w, h, o));
        }
    }
    // The coarsest level: gain at its own luminance, rods added linearly.
    let last = n - 1;
    let (w, h) = (pyramids[0][last].width, pyramids[0][last].height);
    let mut residual: [Vec<f32>; 3] = Default::default();
    for i in 0..w * h {
        let x: [f32; 4] = std::array::from_fn(|c| {
            let v = pyramids[c][last].data[i];
            v * gains[c].gain(global.map_or(v, |g| g[c]))
        });
        let lms = to_display_cones(&m, x);
        for c in 0..3 {
            residual[c].push(lms[c] / display_gain);
        }
    }
    let lms: Vec<Plane> = residual
        .into_iter()
        .zip(bands)
        .map(|(r, b)| {
            let coarsest = Plane::new(w, h, r);
            // One gain per receptor scales bands and mean alike: a plain
            // sum is exact and cannot undershoot.
            match global {
                Some(_) => collapse_with(&b, coarsest, |m, b| m + b),
                None => collapse_with(&b, coarsest, add_contrast),
            }
        })
        .collect();
    (0..width * height)
        .into_par_iter()
        .map(|i| {
            // Cone signals cannot be negative (a band's undershoot next
            // to a bright edge); clamping there, not in XYZ, keeps hues.
            let cones = [lms[0].data[i], lms[1].data[i], lms[2].data[i]].map(|v| v.max(0.0));
            apply32(&m.xyz, cones).map(|c| c.max(0.0))
        })
        .collect()
}

/// Adds a display band to the display's local mean `mean` as a contrast,
/// with negative contrasts rolled off smoothly, c → e^c − 1, so no band
/// can take a cone signal below zero. Where the coarser levels were
/// compressed more than this band (a dark patch beside a bright one, each
/// band gain-controlled at its own local adaptation), a plain sum would
/// undershoot into negative light; the roll-off keeps the slope 1 at zero
/// contrast, so small contrasts are untouched. (scotopia's addition; the
/// paper sums bands.)
fn add_contrast(mean: f32, band: f32) -> f32 {
    if band >= 0.0 || mean <= 0.0 {
        return (mean + band).max(0.0);
    }
    mean * (band / mean).exp()
}

/// Gain-controlled receptor signals [L, M, S, R] → opponent channels (the
/// rods join the achromatic one) → the cone signals a photopic display
/// must produce to give the same responses (its rods are saturated).
fn to_display_cones(m: &Matrices, x: [f32; 4]) -> [f32; 3] {
    let opp = apply32(&m.opponent, [x[0], x[1], x[2]]);
    apply32(&m.from_opponent, [opp[0] + x[3], opp[1], opp[2]])
}

/// Per-receptor adaptation for a global photopic luminance `la`: the
/// image's mean cone signals and S/P ratio scaled to it.
fn global_adaptation(pixels: &[[f32; 4]], m: &Matrices, la: f64) -> [f32; 4] {
    let mut sum = [0.0f64; 4];
    for px in pixels.iter().filter(|p| p.iter().all(|v| v.is_finite())) {
        for c in 0..4 {
            sum[c] += px[c].max(0.0) as f64;
        }
    }
    if sum[1] <= 0.0 {
        return [la as f32; 4];
    }
    let lms = m.lms.apply([sum[0], sum[1], sum[2]]);
    [
        (la * lms[0] / sum[1]) as f32,
        (la * lms[1] / sum[1]) as f32,
        (la * lms[2] / sum[1]) as f32,
        (la * sum[3] / sum[1]) as f32,
    ]
}

#[cfg(test)]
mod tests;

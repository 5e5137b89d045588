//! The multiscale model of adaptation and spatial vision (Pattanaik,
//! Ferwerda, Fairchild & Greenberg 1998, SIGGRAPH, pp. 287–298), used as a
//! tone operator:
//!
//! 1. X, Y, Z → cone signals L, M, S (Hunt–Pointer–Estévez, normalised so
//!    D65 gives L = M = S = Y); the rod signal is V′.
//! 2. Each pixel's adaptation state (`adaptation`): its cone and rod
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
//! 5. The inverse for the display: the same responses, with the display's
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
//!    (`mean_ceiling` of the peak), smoothly: unchanged well below it.

mod adaptation;
mod gain;

pub use adaptation::{adaptation_map, AdaptationMap, Pooling};
pub use gain::GainFunction;

use rayon::prelude::*;
use scotopia_color::space::Cat;
use scotopia_color::{Mat3, RgbSpace};

use crate::mode::log_average;
use crate::wide_math;

/// What the eye adapts to in the model's gain control.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum GainAdaptation {
    /// Per pixel, from the light around it ([`Pooling`]).
    Local,
    /// One photopic luminance (cd/m²) for the whole image; cone and rod
    /// adaptation follow from the image's mean chromaticity and S/P ratio.
    Global(f64),
}

/// Every constant of the model, overridable.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MultiscaleParams {
    /// Visual angle of one pixel, degrees: the pooling field is in
    /// degrees.
    pub degrees_per_pixel: f64,
    /// How the eye pools light for its local adaptation.
    pub pooling: Pooling,
    /// The image's log-average luminance when the caller has it already
    /// (`None`: computed).
    pub log_average: Option<f64>,
    pub cones: GainFunction,
    pub rods: GainFunction,
    /// The display's peak luminance, cd/m².
    pub display_peak: f64,
    /// The luminance the viewer of the display is adapted to, cd/m²
    /// (`None`: half the peak).
    pub display_adaptation: Option<f64>,
    pub adaptation: GainAdaptation,
    /// The highest display level, as a fraction of the peak, the scene's
    /// adaptation luminance is shown at (see `display_scale`).
    pub mean_ceiling: f64,
}

impl Default for MultiscaleParams {
    fn default() -> Self {
        Self {
            degrees_per_pixel: 40.0 / 1024.0,
            pooling: Pooling::default(),
            log_average: None,
            cones: GainFunction::CONES,
            rods: GainFunction::RODS,
            display_peak: 100.0,
            display_adaptation: None,
            adaptation: GainAdaptation::Local,
            mean_ceiling: 0.25,
        }
    }
}

impl MultiscaleParams {
    /// The luminance the viewer of the display is adapted to, cd/m².
    pub fn display_adaptation(&self) -> f64 {
        self.display_adaptation.unwrap_or(self.display_peak / 2.0)
    }

    /// The factor the display image is scaled by for a scene adapted to
    /// `la` cd/m²: the brightness match shows `la` at
    /// m = la·G(la)/G(La_display); with the ceiling c = `mean_ceiling` ×
    /// peak the factor is (1 + (m/c)⁴)^(−1/4), so m·factor rises with m,
    /// stays below c, and is within 1 % of m up to m = c/2. A dusk scene
    /// (m ≈ 0.16 of the peak) moves by 4 %; daylight scenes, which the
    /// plain match put at 60–140 % of the peak, sit near a quarter of it.
    /// (scotopia's choice: the display cannot match daylight's brightness,
    /// so it keeps the contrasts instead.)
    pub fn display_scale(&self, la: f64) -> f64 {
        let cones = self.cones;
        let m =
            la * cones.gain(la as f32) as f64 / cones.gain(self.display_adaptation() as f32) as f64;
        let c = self.mean_ceiling * self.display_peak;
        if !(m > 0.0 && m.is_finite() && c > 0.0) {
            return 1.0;
        }
        (1.0 + (m / c).powi(4)).powf(-0.25)
    }
}

/// XYZ → LMS (Hunt–Pointer–Estévez rows scaled so D65 gives 1, 1, 1), its
/// inverse, the cones' luminance, and the display cones a unit of rod
/// signal asks for.
struct Matrices {
    lms: [[f32; 3]; 3],
    xyz: [[f32; 3]; 3],
    /// The Y row of LMS → XYZ: the achromatic channel A of the cones.
    luminance: [f32; 3],
    /// Rods join the achromatic channel: A += R, C1 and C2 unchanged. Back
    /// through the inverse opponent transform that is the cone signals plus
    /// R times the inverse's first column (the cones of unit A and no
    /// chroma), so the opponent round trip itself is never evaluated.
    rod_cones: [f32; 3],
}

impl Matrices {
    fn new() -> Self {
        let hpe = Cat::VonKries.matrix();
        let white = hpe.apply(RgbSpace::Srgb.def().white_xyz());
        let lms = Mat3::diagonal(white.map(|w| 1.0 / w)) * hpe;
        let xyz = lms.inverse().expect("the cone matrix is invertible");
        // Opponent channels: A (the cones' luminance), C1 = L − M,
        // C2 = (L + M)/2 − S.
        let opponent = Mat3([xyz.0[1], [1.0, -1.0, 0.0], [0.5, 0.5, -1.0]]);
        let from_opponent = opponent
            .inverse()
            .expect("the opponent matrix is invertible");
        let f32s = |m: Mat3| m.0.map(|row| row.map(|v| v as f32));
        Self {
            lms: f32s(lms),
            xyz: f32s(xyz),
            luminance: xyz.0[1].map(|v| v as f32),
            rod_cones: from_opponent.apply([1.0, 0.0, 0.0]).map(|v| v as f32),
        }
    }
}

/// A pixel's receptor signals [L, M, S, R] through the cone matrix `lms`
/// (non-finite and negative values as 0; selects, so a row vectorises).
#[inline(always)]
fn receptors_with(lms: &[[f32; 3]; 3], px: &[f32; 4]) -> [f32; 4] {
    let clean = px.map(|v| {
        let v = if v > 0.0 { v } else { 0.0 };
        if v < f32::INFINITY {
            v
        } else {
            0.0
        }
    });
    let [l, mm, s] = apply(lms, [clean[0], clean[1], clean[2]]);
    [l, mm, s, clean[3]]
}

#[inline(always)]
fn apply(m: &[[f32; 3]; 3], v: [f32; 3]) -> [f32; 3] {
    m.map(|row| row[0] * v[0] + row[1] * v[1] + row[2] * v[2])
}

#[inline(always)]
fn dot(a: [f32; 3], b: [f32; 3]) -> f32 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
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

/// The model's state: what every pixel's gains depend on.
struct Model<'a> {
    p: &'a MultiscaleParams,
    m: Matrices,
    width: usize,
    /// With local adaptation, each pixel's adaptation luminances.
    map: Option<AdaptationMap>,
    /// Each cone type's von Kries ratio G(L_c)/G(L_Y) at the whole
    /// image's adaptation.
    chroma_ratio: [f32; 3],
    /// With a global adaptation, the four receptors' gains.
    fixed_gains: Option<[f32; 4]>,
    /// The display's cone gain over `MultiscaleParams::display_scale`:
    /// display cones are responses divided by it.
    display_gain: f32,
}

impl<'a> Model<'a> {
    fn new(pixels: &[[f32; 4]], width: usize, height: usize, p: &'a MultiscaleParams) -> Self {
        let m = Matrices::new();
        // The whole image's adaptation: stated, or its log-average.
        let la = match p.adaptation {
            GainAdaptation::Global(la) => la,
            GainAdaptation::Local => p.log_average.unwrap_or_else(|| log_average(pixels)),
        };
        let wide = global_adaptation(pixels, &m, la);
        let wide_y = p.cones.gain(dot(m.luminance, [wide[0], wide[1], wide[2]]));
        let chroma_ratio = std::array::from_fn(|c| p.cones.gain(wide[c]) / wide_y);
        let (fixed_gains, map) = match p.adaptation {
            GainAdaptation::Global(_) => (
                Some([
                    p.cones.gain(wide[0]),
                    p.cones.gain(wide[1]),
                    p.cones.gain(wide[2]),
                    p.rods.gain(wide[3]),
                ]),
                None,
            ),
            GainAdaptation::Local => {
                let clean = |v: f32| if v.is_finite() { v.max(0.0) } else { 0.0 };
                let global = (dot(m.luminance, [wide[0], wide[1], wide[2]]), wide[3]);
                let map = adaptation_map(
                    width,
                    height,
                    p.degrees_per_pixel,
                    &p.pooling,
                    global,
                    |i| {
                        let q = &pixels[i];
                        (clean(q[1]), clean(q[3]))
                    },
                );
                (None, Some(map))
            }
        };
        let display_gain = p.cones.gain(p.display_adaptation() as f32) / p.display_scale(la) as f32;
        Self {
            p,
            m,
            width,
            map,
            chroma_ratio,
            fixed_gains,
            display_gain,
        }
    }

    /// Display X, Y, Z of each pixel of `pixels` (the image the model was
    /// built from), given to `put` with the pixel to overwrite. Rows run
    /// wide (`wide_math::dispatch`).
    fn display<M: RowMath>(
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
fn to_display_cones(rod_cones: [f32; 3], x: [f32; 4]) -> [f32; 3] {
    std::array::from_fn(|c| x[c] + x[3] * rod_cones[c])
}

/// Per-receptor adaptation for a global photopic luminance `la`: the
/// image's mean cone signals and S/P ratio scaled to it.
fn global_adaptation(pixels: &[[f32; 4]], m: &Matrices, la: f64) -> [f32; 4] {
    let sum = pixels
        .par_iter()
        .filter(|p| p.iter().all(|v| v.is_finite()))
        .fold(
            || [0.0f64; 4],
            |mut a, px| {
                for c in 0..4 {
                    a[c] += px[c].max(0.0) as f64;
                }
                a
            },
        )
        .reduce(|| [0.0; 4], |a, b| std::array::from_fn(|c| a[c] + b[c]));
    if sum[1] <= 0.0 {
        return [la as f32; 4];
    }
    let lms = m.lms.map(|row| {
        row.iter()
            .zip(&sum)
            .map(|(a, b)| *a as f64 * b)
            .sum::<f64>()
    });
    [
        (la * lms[0] / sum[1]) as f32,
        (la * lms[1] / sum[1]) as f32,
        (la * lms[2] / sum[1]) as f32,
        (la * sum[3] / sum[1]) as f32,
    ]
}

#[cfg(test)]
mod tests;

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
//!    G(L_c)/G(L_Y) for the whole image (its mean cone signals at its
//!    log-average luminance). Letting each cone type adapt per pixel at
//!    every scale, as a literal reading would, painted complementary-
//!    coloured halos at every colour edge (violet skies beside sodium-lit
//!    walls); taking the ratio per pixel of the coarsest level still left
//!    a cyan fringe some 64 pixels wide beside a saturated red object (the
//!    field tied to the resolution, not to visual angle).
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
//!
//! 6. The display's limit (scotopia's addition): the brightness match puts
//!    a scene's adaptation luminance La at La·G(La)/G(La_display) on the
//!    display, which for daylight (La ≳ 2000 cd/m²) is at or above the
//!    peak, so everything brighter than the mean was lost to white. The
//!    display image is scaled so that this level stays below a ceiling
//!    (`mean_ceiling` of the peak), smoothly: unchanged well below it.

mod gain;

pub use gain::GainFunction;

use rayon::prelude::*;
use scotopia_color::space::Cat;
use scotopia_color::{Mat3, RgbSpace};

use crate::mode::log_average;
use crate::pyramid::{collapse_with, gaussian, reduce4, zeroed, Bilinear, Plane};
use crate::wide_math;

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
    /// The highest display level, as a fraction of the peak, the scene's
    /// adaptation luminance is shown at (see `display_scale`).
    pub mean_ceiling: f64,
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

/// A pixel's receptor signals [L, M, S, R] (non-finite and negative
/// values as 0).
fn receptors(m: &Matrices, px: &[f32; 4]) -> [f32; 4] {
    let clean = px.map(|v| if v.is_finite() { v.max(0.0) } else { 0.0 });
    let [l, mm, s] = apply(&m.lms, [clean[0], clean[1], clean[2]]);
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

/// [`multiscale`] with libm's `powf` and `expf` per pixel: the model as
/// it was computed before the rows went wide, kept as the reference the
/// wide rows are tested against (they differ from it by an f32 ulp here
/// and there, multiscale's tests).
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

/// The per-pixel transcendental functions of the model's rows: the wide
/// polynomials of `wide_math` in the pipeline, libm's in the reference.
pub(crate) trait RowMath {
    /// The receptor gain `g` at adaptation `i`.
    fn gain(g: &GainFunction, i: f32) -> f32;
    fn exp(x: f32) -> f32;
}

/// libm's `powf` and `expf` ([`GainFunction::gain`]): the reference.
pub(crate) struct Libm;

impl RowMath for Libm {
    #[inline(always)]
    fn gain(g: &GainFunction, i: f32) -> f32 {
        g.gain(i)
    }
    #[inline(always)]
    fn exp(x: f32) -> f32 {
        x.exp()
    }
}

/// `wide_math`'s: the same formulas, vectorised.
pub(crate) struct Wide;

impl RowMath for Wide {
    #[inline(always)]
    fn gain(g: &GainFunction, i: f32) -> f32 {
        g.gain_wide(i)
    }
    #[inline(always)]
    fn exp(x: f32) -> f32 {
        wide_math::expf(x)
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
    // The model keeps no reference to the pixels once its pyramids are
    // built, so they can be overwritten.
    let model = Model::new(pixels, width, height, p);
    model.display::<Wide>(pixels, |q, xyz| *q = finish(q, xyz));
}

/// The model's state: receptor pyramids and the gains that depend on them.
struct Model<'a> {
    p: &'a MultiscaleParams,
    m: Matrices,
    /// Gaussian pyramids of L, M, S, R.
    pyramids: Vec<Vec<Plane>>,
    /// Per level but the last, the expansion of the next coarser level
    /// to it.
    up: Vec<Bilinear>,
    /// Each cone type's von Kries ratio G(L_c)/G(L_Y) at the whole
    /// image's adaptation.
    chroma_ratio: [f32; 3],
    /// With a global adaptation, every band's four gains.
    fixed_gains: Option<[f32; 4]>,
    /// The display's cone gain over `MultiscaleParams::display_scale`:
    /// display cones are responses divided by it.
    display_gain: f32,
}

/// Per-thread rows: a level's receptor signals, the expanded local
/// means of the next coarser level, and the band's display cones.
struct Scratch {
    fine: [Vec<f32>; 4],
    mean: [Vec<f32>; 4],
    cones: [Vec<f32>; 3],
}

impl Scratch {
    fn new(width: usize) -> Self {
        Self {
            fine: std::array::from_fn(|_| vec![0.0; width]),
            mean: std::array::from_fn(|_| vec![0.0; width]),
            cones: std::array::from_fn(|_| vec![0.0; width]),
        }
    }
}

impl<'a> Model<'a> {
    fn new(pixels: &[[f32; 4]], width: usize, height: usize, p: &'a MultiscaleParams) -> Self {
        let m = Matrices::new();
        // Level 0 is the pixels themselves, read again where a band needs
        // them; only its shape is kept, unless it is the only level.
        let levels = p.levels.max(1);
        let pyramids: Vec<Vec<Plane>> = if levels > 1 && width >= 4 && height >= 4 {
            let finer = reduce4(width, height, |y, rows| {
                for (x, px) in pixels[y * width..(y + 1) * width].iter().enumerate() {
                    let r = receptors(&m, px);
                    for c in 0..4 {
                        rows[c][x] = r[c];
                    }
                }
            });
            finer
                .into_par_iter()
                .map(|level1| {
                    let shape = Plane {
                        width,
                        height,
                        data: Vec::new(),
                    };
                    let mut pyramid = vec![shape];
                    pyramid.extend(gaussian(level1, levels - 1));
                    pyramid
                })
                .collect()
        } else {
            (0..4)
                .map(|c| {
                    let data = pixels.iter().map(|px| receptors(&m, px)[c]).collect();
                    vec![Plane::new(width, height, data)]
                })
                .collect()
        };
        let n = pyramids[0].len();
        let size = |l: usize| (pyramids[0][l].width, pyramids[0][l].height);
        let up = (0..n - 1)
            .map(|l| Bilinear::new(size(l + 1), size(l)))
            .collect();
        // The whole image's adaptation: stated, or its log-average.
        let la = match p.adaptation {
            GainAdaptation::Global(la) => la,
            GainAdaptation::Local => log_average(pixels),
        };
        let wide = global_adaptation(pixels, &m, la);
        let wide_y = p.cones.gain(dot(m.luminance, [wide[0], wide[1], wide[2]]));
        let chroma_ratio = std::array::from_fn(|c| p.cones.gain(wide[c]) / wide_y);
        let fixed_gains = match p.adaptation {
            GainAdaptation::Local => None,
            GainAdaptation::Global(_) => Some([
                p.cones.gain(wide[0]),
                p.cones.gain(wide[1]),
                p.cones.gain(wide[2]),
                p.rods.gain(wide[3]),
            ]),
        };
        let display_gain = p.cones.gain(p.display_adaptation() as f32) / p.display_scale(la) as f32;
        Self {
            p,
            m,
            pyramids,
            up,
            chroma_ratio,
            fixed_gains,
            display_gain,
        }
    }

    /// The four receptors' gains at local adaptation `local` ([L, M, S, R]):
    /// the cones' at its luminance times their von Kries ratios, the rods'
    /// at their own signal; with a global adaptation, the fixed gains.
    fn gains(&self, local: [f32; 4]) -> [f32; 4] {
        self.fixed_gains
            .unwrap_or_else(|| self.local_gains::<Libm>(local))
    }

    /// The gains at a local adaptation (no fixed gains), through `M`.
    #[inline(always)]
    fn local_gains<M: RowMath>(&self, local: [f32; 4]) -> [f32; 4] {
        let g = M::gain(
            &self.p.cones,
            dot(self.m.luminance, [local[0], local[1], local[2]]),
        );
        [
            g * self.chroma_ratio[0],
            g * self.chroma_ratio[1],
            g * self.chroma_ratio[2],
            M::gain(&self.p.rods, local[3]),
        ]
    }

    fn size(&self, level: usize) -> (usize, usize) {
        let g = &self.pyramids[0][level];
        (g.width, g.height)
    }

    /// Display cones of pixel `i` of the coarsest level: gain at its own
    /// value, rods added.
    fn coarsest(&self, i: usize) -> [f32; 3] {
        let n = self.pyramids[0].len();
        let v: [f32; 4] = std::array::from_fn(|c| self.pyramids[c][n - 1].data[i]);
        let gains = self.gains(v);
        let x: [f32; 4] = std::array::from_fn(|c| v[c] * gains[c]);
        to_display_cones(&self.m, x).map(|v| v / self.display_gain)
    }

    /// Row `y` of band `level` as display cones, into `scratch.cones`:
    /// each receptor's band (the level, whose row the caller has put in
    /// `scratch.fine`, minus the next coarser one expanded) gain-controlled
    /// at that local mean, rods joined, over the display's gain. The
    /// per-pixel loop runs wide (`wide_math::dispatch`).
    fn band_cones<M: RowMath>(&self, level: usize, y: usize, scratch: &mut Scratch) {
        let (w, _) = self.size(level);
        for (c, row) in scratch.mean.iter_mut().enumerate() {
            self.up[level].row(&self.pyramids[c][level + 1].data, y, &mut row[..w]);
        }
        let k = BandRow {
            fixed: self.fixed_gains,
            cones: self.p.cones,
            rods: self.p.rods,
            luminance: self.m.luminance,
            ratio: self.chroma_ratio,
            rod_cones: self.m.rod_cones,
            display_gain: self.display_gain,
        };
        let fine: [&[f32]; 4] = std::array::from_fn(|c| &scratch.fine[c][..w]);
        let mean: [&[f32]; 4] = std::array::from_fn(|c| &scratch.mean[c][..w]);
        let [l, m, s] = &mut scratch.cones;
        let out = [&mut l[..w], &mut m[..w], &mut s[..w]];
        wide_math::dispatch(
            #[inline(always)]
            move || band_row::<M>(k, fine, mean, out),
        );
    }

    /// Display X, Y, Z of each pixel of `pixels` (the image the model was
    /// built from), given to `put` with the pixel to overwrite.
    fn display<M: RowMath>(
        &self,
        pixels: &mut [[f32; 4]],
        put: impl Fn(&mut [f32; 4], [f32; 3]) + Sync,
    ) {
        // Combining a display band with the collapsed coarser levels: one
        // gain per receptor scales bands and mean alike, so a plain sum is
        // exact and cannot undershoot; local gains need the contrast
        // roll-off.
        match self.fixed_gains {
            Some(_) => self.display_with::<M>(|m, b| m + b, pixels, put),
            None => self.display_with::<M>(add_contrast::<M>, pixels, put),
        }
    }

    /// Display X, Y, Z: the coarsest level's display cones, every band
    /// but the finest collapsed onto it with `combine`, and the finest band
    /// fused with the last collapse step and the return to X, Y, Z so no
    /// full-size band plane is ever stored.
    fn display_with<M: RowMath>(
        &self,
        combine: impl Fn(f32, f32) -> f32 + Sync + Copy,
        out: &mut [[f32; 4]],
        put: impl Fn(&mut [f32; 4], [f32; 3]) + Sync,
    ) {
        let (width, height) = self.size(0);
        let n = self.pyramids[0].len();
        // The display cones of the coarsest level, then every band but the
        // finest collapsed onto it.
        let (cw, ch) = self.size(n - 1);
        let mut residual: [Vec<f32>; 3] = Default::default();
        for i in 0..cw * ch {
            let cones = self.coarsest(i);
            for c in 0..3 {
                residual[c].push(cones[c]);
            }
        }
        let mut bands: [Vec<Plane>; 3] = Default::default();
        for level in 1..n.max(1) - 1 {
            for (c, plane) in self.band_planes::<M>(level).into_iter().enumerate() {
                bands[c].push(plane);
            }
        }
        let coarser: Vec<Plane> = residual
            .into_par_iter()
            .zip(bands)
            .map(|(r, b)| collapse_with(&b, Plane::new(cw, ch, r), combine))
            .collect();
        let xyz = self.m.xyz;
        // Cone signals cannot be negative (a band's undershoot next to a
        // bright edge); clamping there, not in XYZ, keeps hues.
        let to_xyz =
            move |cones: [f32; 3]| apply(&xyz, cones.map(|v| v.max(0.0))).map(|c| c.max(0.0));
        if n == 1 {
            for (i, o) in out.iter_mut().enumerate() {
                put(o, to_xyz(std::array::from_fn(|c| coarser[c].data[i])));
            }
            return;
        }
        let up = Bilinear::new(self.size(1), (width, height));
        out.par_chunks_mut(width).enumerate().for_each_init(
            || (Scratch::new(width), vec![vec![0.0f32; width]; 3]),
            |(scratch, mean), (y, row)| {
                for (c, m) in mean.iter_mut().enumerate() {
                    up.row(&coarser[c].data, y, m);
                }
                // Level 0 is the row's own pixels, read before any of
                // them is overwritten.
                for (x, px) in row.iter().enumerate() {
                    let r = receptors(&self.m, px);
                    for (fine, v) in scratch.fine.iter_mut().zip(r) {
                        fine[x] = v;
                    }
                }
                self.band_cones::<M>(0, y, scratch);
                // The band on the collapsed coarser levels, back to X, Y,
                // Z in place of the band's cones (wide), then handed out.
                let [a, b, c] = &mut scratch.cones;
                let (a, b, c) = (&mut a[..width], &mut b[..width], &mut c[..width]);
                let m = [&mean[0][..width], &mean[1][..width], &mean[2][..width]];
                wide_math::dispatch(
                    #[inline(always)]
                    move || {
                        let (b, c) = (&mut b[..a.len()], &mut c[..a.len()]);
                        let [m0, m1, m2] = m.map(|r| &r[..a.len()]);
                        for x in 0..a.len() {
                            let v = [
                                combine(m0[x], a[x]),
                                combine(m1[x], b[x]),
                                combine(m2[x], c[x]),
                            ];
                            [a[x], b[x], c[x]] = to_xyz(v);
                        }
                    },
                );
                let (a, b, c) = (&scratch.cones[0], &scratch.cones[1], &scratch.cones[2]);
                for (x, px) in row.iter_mut().enumerate() {
                    put(px, [a[x], b[x], c[x]]);
                }
            },
        );
    }

    /// Band `level`'s display cone signals as three planes.
    fn band_planes<M: RowMath>(&self, level: usize) -> [Plane; 3] {
        let (w, h) = self.size(level);
        let mut out: [Vec<f32>; 3] = std::array::from_fn(|_| zeroed(w * h));
        let [l, m, s] = &mut out;
        l.par_chunks_mut(w)
            .zip(m.par_chunks_mut(w))
            .zip(s.par_chunks_mut(w))
            .enumerate()
            .for_each_init(
                || Scratch::new(w),
                |scratch, (y, ((l, m), s))| {
                    for (c, fine) in scratch.fine.iter_mut().enumerate() {
                        fine.copy_from_slice(&self.pyramids[c][level].data[y * w..(y + 1) * w]);
                    }
                    self.band_cones::<M>(level, y, scratch);
                    for (plane, cones) in [l, m, s].into_iter().zip(&scratch.cones) {
                        plane.copy_from_slice(&cones[..w]);
                    }
                },
            );
        out.map(|data| Plane::new(w, h, data))
    }
}

/// Adds a display band to the display's local mean `mean` as a contrast,
/// with negative contrasts rolled off smoothly, c → e^c − 1, so no band
/// can take a cone signal below zero. Where the coarser levels were
/// compressed more than this band (a dark patch beside a bright one, each
/// band gain-controlled at its own local adaptation), a plain sum would
/// undershoot into negative light; the roll-off keeps the slope 1 at zero
/// contrast, so small contrasts are untouched. (scotopia's addition; the
/// paper sums bands.) Both sides are computed and one chosen, so a row of
/// them vectorises.
#[inline(always)]
fn add_contrast<M: RowMath>(mean: f32, band: f32) -> f32 {
    let plain = (mean + band).max(0.0);
    let rolled = mean * M::exp(band / mean);
    if band >= 0.0 || mean <= 0.0 {
        plain
    } else {
        rolled
    }
}

/// What a band row's per-pixel loop reads besides the rows, by value:
/// nothing it reads can then alias what it writes, and the loop
/// vectorises.
#[derive(Clone, Copy)]
struct BandRow {
    /// With a global adaptation, every band's four gains.
    fixed: Option<[f32; 4]>,
    cones: GainFunction,
    rods: GainFunction,
    luminance: [f32; 3],
    ratio: [f32; 3],
    rod_cones: [f32; 3],
    display_gain: f32,
}

/// A band row's display cones into `out`: each receptor's band (`fine`
/// minus `mean`, the expanded next coarser level) times its gain at that
/// local mean ([`Model::gains`], through `M`), rods joined, over the
/// display's gain.
#[inline(always)]
fn band_row<M: RowMath>(k: BandRow, fine: [&[f32]; 4], mean: [&[f32]; 4], out: [&mut [f32]; 3]) {
    let [l, m, s] = out;
    let w = l.len();
    let (m, s) = (&mut m[..w], &mut s[..w]);
    let [f0, f1, f2, f3] = fine.map(|r| &r[..w]);
    let [m0, m1, m2, m3] = mean.map(|r| &r[..w]);
    let finish = |band: [f32; 4]| display_band(band, k.rod_cones, k.display_gain);
    match k.fixed {
        Some(g) => {
            for x in 0..w {
                let band = [
                    (f0[x] - m0[x]) * g[0],
                    (f1[x] - m1[x]) * g[1],
                    (f2[x] - m2[x]) * g[2],
                    (f3[x] - m3[x]) * g[3],
                ];
                [l[x], m[x], s[x]] = finish(band);
            }
        }
        None => {
            for x in 0..w {
                let gc = M::gain(&k.cones, dot(k.luminance, [m0[x], m1[x], m2[x]]));
                let band = [
                    (f0[x] - m0[x]) * (gc * k.ratio[0]),
                    (f1[x] - m1[x]) * (gc * k.ratio[1]),
                    (f2[x] - m2[x]) * (gc * k.ratio[2]),
                    (f3[x] - m3[x]) * M::gain(&k.rods, m3[x]),
                ];
                [l[x], m[x], s[x]] = finish(band);
            }
        }
    }
}

/// A gain-controlled band [L, M, S, R] as display cones over the
/// display's gain ([`to_display_cones`], for the wide loops).
#[inline(always)]
fn display_band(band: [f32; 4], rod_cones: [f32; 3], display_gain: f32) -> [f32; 3] {
    std::array::from_fn(|c| (band[c] + band[3] * rod_cones[c]) / display_gain)
}

/// Gain-controlled receptor signals [L, M, S, R] → the cone signals a
/// photopic display must produce to give the same opponent responses (its
/// rods are saturated): the rods' share of the achromatic channel moves
/// to the cones.
fn to_display_cones(m: &Matrices, x: [f32; 4]) -> [f32; 3] {
    std::array::from_fn(|c| x[c] + x[3] * m.rod_cones[c])
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

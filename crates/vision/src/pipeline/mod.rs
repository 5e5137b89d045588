//! The whole pipeline, stage by stage in the order of ../shared/DESIGN.md:
//! visual mode → glare → adaptation (tone mapping) → night shift and
//! scotopic acuity → gamut mapping. The result is display-referred linear
//! RGB in [0, 1] (1 = the display's peak), ready for `encode`.

use std::borrow::Cow;
use std::time::Instant;

use rayon::prelude::*;
use scotopia_color::RgbSpace;

use crate::acuity::{gaussian_blur, scotopic_blur_degrees};
use crate::gamut::map_pixels_to_gamut;
use crate::glare::{apply_glare, GlareParams, GlareReport, Reproduced};
use crate::mode::{
    image_statistics, scotopic_sensitivity, Adaptation, ImageStatistics, VisualState,
};
use crate::multiscale::{
    adaptation_map, multiscale_in_place, GainAdaptation, MultiscaleParams, Pooling,
};
use crate::night::night_shift;
use crate::observer::Observer;
use crate::screen::{self, LeftOut};
use crate::tonemap::{exposure_scale, reinhard_scale};

/// The tone operator of stage 3.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ToneOperator {
    /// Pattanaik et al. 1998's multiscale model (the default).
    Multiscale,
    /// Reinhard et al. 2002's global operator, for comparison.
    Reinhard,
    /// A linear exposure (adaptation luminance at 18 % of peak).
    Exposure,
}

impl ToneOperator {
    pub fn from_name(name: &str) -> Option<Self> {
        match name.to_ascii_lowercase().as_str() {
            "multiscale" | "pattanaik" => Some(Self::Multiscale),
            "reinhard" => Some(Self::Reinhard),
            "exposure" | "linear" => Some(Self::Exposure),
            _ => None,
        }
    }
}

/// Every switch of the pipeline.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DisplayParams {
    /// Visual angle of one pixel, degrees (horizontal field of view over
    /// the width).
    pub degrees_per_pixel: f64,
    /// The display's peak luminance, cd/m².
    pub display_peak: f64,
    pub adaptation: Adaptation,
    pub glare: bool,
    /// The night-vision shift and the scotopic acuity blur (stage 4).
    pub night_shift: bool,
    pub tonemap: ToneOperator,
    pub gamut: RgbSpace,
    /// Whose eye: age and pigmentation (glare spread, lens density).
    pub observer: Observer,
    /// The multiscale model's constants (its display peak and adaptation
    /// are taken from this struct's).
    pub multiscale: MultiscaleParams,
}

impl Default for DisplayParams {
    fn default() -> Self {
        Self {
            degrees_per_pixel: 40.0 / 1024.0,
            display_peak: 100.0,
            adaptation: Adaptation::Global,
            glare: true,
            night_shift: true,
            tonemap: ToneOperator::Multiscale,
            gamut: RgbSpace::Srgb,
            observer: Observer::default(),
            multiscale: MultiscaleParams::default(),
        }
    }
}

/// The stages, for `--compare` and for callers that want to look inside.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Stage {
    /// The input at a plain exposure.
    Input,
    /// After glare, at the same exposure.
    Glare,
    /// After the tone operator.
    Adaptation,
    /// After the night shift and acuity blur.
    NightShift,
    /// After gamut mapping.
    Final,
}

impl Stage {
    pub const ALL: [Stage; 5] = [
        Stage::Input,
        Stage::Glare,
        Stage::Adaptation,
        Stage::NightShift,
        Stage::Final,
    ];

    pub fn label(self) -> &'static str {
        match self {
            Stage::Input => "input (exposure)",
            Stage::Glare => "glare",
            Stage::Adaptation => "adaptation",
            Stage::NightShift => "night shift",
            Stage::Final => "final",
        }
    }
}

/// What the pipeline found and did.
#[derive(Debug, Clone, PartialEq)]
pub struct Report {
    pub statistics: ImageStatistics,
    /// The visual state at the image's (global or stated) adaptation.
    pub state: VisualState,
    pub glare_applied: bool,
    /// The veiling luminance glare adds (cd/m², scene units) at the
    /// adaptation point (how much it raises the image's log-average, the
    /// global adaptation luminance) and at the image's centre (the line
    /// of sight, where road lighting evaluates it).
    pub veil_adaptation: f64,
    pub veil_centre: f64,
    /// The scotopic acuity blur's σ in pixels (0: none).
    pub blur_pixels: f64,
    /// Seconds per stage, in order.
    pub timings: Vec<(&'static str, f64)>,
}

/// The pipeline's output: display-referred linear RGB in the target gamut.
#[derive(Debug, Clone, PartialEq)]
pub struct Displayed {
    pub width: usize,
    pub height: usize,
    pub rgb: Vec<[f32; 3]>,
    pub report: Report,
}

/// What the pipeline holds per pixel at its peak, bytes, an upper
/// estimate: the input and its glare copy, the excess, the padded glare
/// FFT grids (complex, up to 4× the pixels), the tone-mapped, shown and
/// RGB images and the local-adaptation grid.
const PIPELINE_BYTES_PER_PIXEL: u64 = 256;

/// Whether a `width` × `height` image fits the memory budget for the
/// pipeline (`scotopia_image::limits`); the error names the limit.
pub fn check_size(width: usize, height: usize) -> Result<(), scotopia_image::TooLarge> {
    scotopia_image::check_image(
        "the vision pipeline on an image",
        width as u64,
        height as u64,
        PIPELINE_BYTES_PER_PIXEL,
    )
    .map(|_| ())
}

/// Runs the pipeline on `pixels` ([X, Y, Z, V′] absolute).
pub fn display(pixels: &[[f32; 4]], width: usize, height: usize, p: &DisplayParams) -> Displayed {
    run(Cow::Borrowed(pixels), width, height, p, None)
}

/// As [`display`], working in `pixels`' own memory: no full-size copy of
/// the image is made (every extra 33 MB buffer of a full-HD image costs a
/// fresh process ~8000 first-touch page faults), so the result is the same.
pub fn display_owned(
    pixels: Vec<[f32; 4]>,
    width: usize,
    height: usize,
    p: &DisplayParams,
) -> Displayed {
    run(Cow::Owned(pixels), width, height, p, None)
}

/// As [`display`], calling `observe` with each stage's image as
/// display-relative X, Y, Z (Y = 1 at the display's peak).
pub fn display_observed(
    pixels: &[[f32; 4]],
    width: usize,
    height: usize,
    p: &DisplayParams,
    observe: &mut dyn FnMut(Stage, &[[f32; 3]]),
) -> Displayed {
    run(Cow::Borrowed(pixels), width, height, p, Some(observe))
}

/// Receives each stage's image (display-relative X, Y, Z).
type StageObserver<'a> = dyn FnMut(Stage, &[[f32; 3]]) + 'a;

/// The pipeline; each stage's snapshot is made only when someone observes.
/// Every stage works in one image buffer (`pixels`, copied first only when
/// borrowed): glare, the tone operator, the night shift and the blur all
/// write in place.
fn run(
    pixels: Cow<[[f32; 4]]>,
    width: usize,
    height: usize,
    p: &DisplayParams,
    mut observer: Option<&mut StageObserver>,
) -> Displayed {
    let mut observe = |stage: Stage, snapshot: &dyn Fn() -> Vec<[f32; 3]>| {
        if let Some(o) = observer.as_mut() {
            o(stage, &snapshot());
        }
    };
    let mut timings = Vec::new();
    let mut clock = Instant::now();
    let mut lap = |name: &'static str, timings: &mut Vec<(&'static str, f64)>| {
        timings.push((name, clock.elapsed().as_secs_f64()));
        clock = Instant::now();
    };

    // 0. The observer's lens: an older eye lets less light, and least of
    // the blue, reach the retina (identity for the default observer).
    let pixels = through_lens(pixels, &p.observer);

    // 1. Visual mode, from the pixels that are finite and not absurd.
    let statistics = image_statistics(&pixels);
    // Where the left-out pixels are (usually nowhere), for stage 5.
    // (Listed only when the statistics counted some: a clean image is not
    // screened twice.)
    let left_out = if statistics.left_out.total() > 0 {
        screen::left_out_pixels(&pixels)
    } else {
        Vec::new()
    };
    let mut scene = pixels.into_owned();
    // The pixels left out take the others' mean colour at their
    // log-average luminance in the spatial stages, so they neither glare
    // nor darken or brighten their neighbourhood.
    if !left_out.is_empty() {
        let fill = fill_value(&statistics);
        for &(i, _) in &left_out {
            scene[i] = fill;
        }
    }
    let la = match p.adaptation {
        Adaptation::Fixed(l) => l,
        Adaptation::Global | Adaptation::Local => statistics.log_average,
    };
    let state = VisualState::new(la, statistics.sp_ratio);
    let local_s =
        (p.adaptation == Adaptation::Local).then(|| local_sensitivity(&scene, width, height, p));
    let exposure = exposure_scale(la) as f32;
    let xyz_at = |px: &[[f32; 4]], k: f32| -> Vec<[f32; 3]> {
        px.par_iter()
            .map(|q| [q[0] * k, q[1] * k, q[2] * k])
            .collect()
    };
    observe(Stage::Input, &|| xyz_at(&scene, exposure));
    lap("visual mode", &mut timings);

    // 2. Glare, from the scene in absolute units: the retinal image, less
    // what the viewer's own eye will scatter from the display.
    let glare = if p.glare {
        apply_glare(
            &mut scene,
            width,
            height,
            &GlareParams {
                degrees_per_pixel: p.degrees_per_pixel,
                s: state.s,
                observer: p.observer,
                reproduced: reproduced(p, la, &statistics),
            },
        )
    } else {
        GlareReport::default()
    };
    // The retinal image's log-average: the multiscale model's global
    // adaptation, and the veil at the adaptation point.
    let retinal_log_average = if glare.applied {
        glare.log_average
    } else {
        statistics.log_average
    };
    let veil_adaptation = (retinal_log_average - statistics.log_average).max(0.0);
    observe(Stage::Glare, &|| xyz_at(&scene, exposure));
    lap("glare", &mut timings);

    // 3. Adaptation: display-relative X, Y, Z and V′ on the same scale.
    tone_map(
        &mut scene,
        width,
        height,
        p,
        la,
        &statistics,
        retinal_log_average,
    );
    let mut shown = scene;
    observe(Stage::Adaptation, &|| xyz_of(&shown));
    lap("adaptation", &mut timings);

    // 4. Night shift and acuity.
    let mut blur_pixels = 0.0;
    if p.night_shift {
        shown.par_iter_mut().enumerate().for_each(|(i, q)| {
            let s = local_s.as_ref().map_or(state.s, |l| l[i] as f64);
            let [x, y, z] = night_shift(q.map(f64::from), s);
            *q = [x as f32, y as f32, z as f32, q[3]];
        });
        blur_pixels = scotopic_blur_degrees(la, display_adaptation(p)) / p.degrees_per_pixel;
        gaussian_blur(&mut shown, width, height, blur_pixels);
    }
    observe(Stage::NightShift, &|| xyz_of(&shown));
    lap("night shift", &mut timings);

    // 5. Gamut mapping.
    let space = p.gamut.def();
    // The CSS search for many pixels at once (gamut/wide.rs; the same
    // codes as the per-pixel reference, tested).
    let mut rgb: Vec<[f32; 3]> = map_pixels_to_gamut(&shown, space);
    for &(i, why) in &left_out {
        // Shown as what they are: no light, or more than the display has.
        rgb[i] = match why {
            LeftOut::NonFinite => [0.0; 3],
            LeftOut::Absurd => [1.0; 3],
        };
    }
    observe(Stage::Final, &|| {
        rgb.par_iter()
            .map(|c| space.rgb_to_xyz(c.map(f64::from)).map(|v| v as f32))
            .collect()
    });
    lap("gamut mapping", &mut timings);

    Displayed {
        width,
        height,
        rgb,
        report: Report {
            statistics,
            state,
            glare_applied: glare.applied,
            veil_adaptation,
            veil_centre: glare.veil_centre,
            blur_pixels,
            timings,
        },
    }
}

/// `pixels` as the observer's retina receives them: each channel scaled
/// by the lens's transmittance relative to the default observer's
/// (`Observer::lens_factors`); borrowed unchanged when that is 1.
fn through_lens<'a>(pixels: Cow<'a, [[f32; 4]]>, observer: &Observer) -> Cow<'a, [[f32; 4]]> {
    let f = observer.lens_factors().map(|v| v as f32);
    if f == [1.0; 4] {
        return pixels;
    }
    let mut owned = pixels.into_owned();
    owned.par_iter_mut().for_each(|q| {
        for c in 0..4 {
            q[c] *= f[c];
        }
    });
    Cow::Owned(owned)
}

/// What a left-out pixel is replaced by in the spatial stages: the used
/// pixels' mean colour at their log-average luminance.
fn fill_value(stats: &ImageStatistics) -> [f32; 4] {
    let y = stats.mean[1];
    if y > 0.0 {
        stats.mean.map(|v| (v * stats.log_average / y) as f32)
    } else {
        [0.0; 4]
    }
}

fn xyz_of(px: &[[f32; 4]]) -> Vec<[f32; 3]> {
    px.par_iter().map(|q| [q[0], q[1], q[2]]).collect()
}

fn display_adaptation(p: &DisplayParams) -> f64 {
    multiscale_params(p).display_adaptation()
}

/// The multiscale model's parameters as the pipeline runs it: the
/// display's peak, and one adaptation for the model only when one is
/// stated (`--adaptation CD`).
fn multiscale_params(p: &DisplayParams) -> MultiscaleParams {
    MultiscaleParams {
        degrees_per_pixel: p.degrees_per_pixel,
        display_peak: p.display_peak,
        adaptation: match p.adaptation {
            Adaptation::Fixed(l) => GainAdaptation::Global(l),
            Adaptation::Global | Adaptation::Local => GainAdaptation::Local,
        },
        ..p.multiscale
    }
}

/// What the display reproduces of each scene luminance, in scene units
/// at the adaptation luminance `la`, for the chosen tone operator: the
/// rest of each pixel's light glares (glare/apply.rs). Exposure shows
/// everything up to La/0.18 as it is; Reinhard's operator and the
/// multiscale model compress, so a pixel brighter than La is reproduced
/// as its display luminance over the display's luminance per cd/m² at La
/// (for the model: its global response y·G(y)/G(La), up to the luminance
/// the display shows at its peak, k·y·G(y) = peak·G(La_display)).
fn reproduced(p: &DisplayParams, la: f64, stats: &ImageStatistics) -> Reproduced {
    match p.tonemap {
        ToneOperator::Exposure => Reproduced::Below(la / 0.18),
        ToneOperator::Reinhard => Reproduced::Reinhard {
            la,
            maximum: stats.maximum,
        },
        ToneOperator::Multiscale => {
            let params = multiscale_params(p);
            let cones = params.cones;
            let k = params.display_scale(la);
            let response = |y: f64| k * y * cones.gain(y as f32) as f64;
            let target = p.display_peak * cones.gain(params.display_adaptation() as f32) as f64;
            let (mut lo, mut hi) = (-6.0f64, 12.0f64);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if response(10f64.powf(mid)) < target {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            Reproduced::Gain {
                cones,
                la,
                threshold: 10f64.powf(hi),
            }
        }
    }
}

/// Stage 3: the chosen operator, turning `scene` in place into X, Y, Z, V′
/// relative to the display's peak. For the exposure and Reinhard
/// operators V′ is scaled by each pixel's own luminance factor so the
/// night shift sees it on the display's scale; for the multiscale model,
/// whose luminance already holds the rods, V′ gives that luminance back.
fn tone_map(
    scene: &mut [[f32; 4]],
    width: usize,
    height: usize,
    p: &DisplayParams,
    la: f64,
    stats: &ImageStatistics,
    retinal_log_average: f64,
) {
    let scale = |scene: &mut [[f32; 4]], k: &(dyn Fn(f64) -> f64 + Sync)| {
        scene.par_iter_mut().for_each(|q| {
            let f = k(q[1] as f64) as f32;
            *q = q.map(|v| v * f);
        });
    };
    match p.tonemap {
        ToneOperator::Exposure => {
            let e = exposure_scale(la);
            scale(scene, &|_| e)
        }
        ToneOperator::Reinhard => scale(scene, &|y| reinhard_scale(y, la, stats.maximum)),
        ToneOperator::Multiscale => {
            let peak = p.display_peak as f32;
            // The model's display luminance already holds the rods'
            // response (they join its achromatic channel), so the night
            // shift's V′ is set to give that luminance back (0.4468·V′ =
            // Y): the shift then moves only chromaticity. Scaling V′ by
            // Y's factor instead counted the rods twice, and drew dark
            // rings where V′/Y changes (the halo's rings differ by
            // channel).
            let v_per_y = (1.0 / crate::night::V_TO_Y) as f32;
            let params = MultiscaleParams {
                log_average: Some(retinal_log_average),
                ..multiscale_params(p)
            };
            multiscale_in_place(scene, width, height, &params, |_, d| {
                [d[0] / peak, d[1] / peak, d[2] / peak, d[1] * v_per_y / peak]
            });
        }
    }
}

/// Per-pixel scotopic sensitivity for `--adaptation local`: s of each
/// pixel's local adaptation luminance (the multiscale model's pooling).
fn local_sensitivity(
    pixels: &[[f32; 4]],
    width: usize,
    height: usize,
    p: &DisplayParams,
) -> Vec<f32> {
    let clean = |v: f32| if v.is_finite() { v.max(0.0) } else { 0.0 };
    // Fully local: the night shift follows each region's own light.
    let pooling = Pooling {
        local: 1.0,
        ..p.multiscale.pooling
    };
    let map = adaptation_map(
        width,
        height,
        p.degrees_per_pixel,
        &pooling,
        (1.0, 1.0),
        |i| (clean(pixels[i][1]), clean(pixels[i][3])),
    );
    map.cones
        .par_iter()
        .map(|&l| scotopic_sensitivity(l as f64) as f32)
        .collect()
}

#[cfg(test)]
mod tests;

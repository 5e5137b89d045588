//! The model's state for one image: its adaptation (per pixel or one for
//! all), each cone type's von Kries ratio, and the display's gain.

use rayon::prelude::*;

use super::adaptation::{adaptation_map, AdaptationMap};
use super::params::{GainAdaptation, MultiscaleParams};
use super::receptors::{dot, Matrices};
use crate::mode::log_average;

/// The model's state: what every pixel's gains depend on.
pub(super) struct Model<'a> {
    pub(super) p: &'a MultiscaleParams,
    pub(super) m: Matrices,
    pub(super) width: usize,
    /// With local adaptation, each pixel's adaptation luminances.
    pub(super) map: Option<AdaptationMap>,
    /// Each cone type's von Kries ratio G(L_c)/G(L_Y) at the whole
    /// image's adaptation.
    pub(super) chroma_ratio: [f32; 3],
    /// With a global adaptation, the four receptors' gains.
    pub(super) fixed_gains: Option<[f32; 4]>,
    /// The display's cone gain over `MultiscaleParams::display_scale`:
    /// display cones are responses divided by it.
    pub(super) display_gain: f32,
}

impl<'a> Model<'a> {
    pub(super) fn new(
        pixels: &[[f32; 4]],
        width: usize,
        height: usize,
        p: &'a MultiscaleParams,
    ) -> Self {
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

//! False-colour maps of one photometric quantity (luminance or CIE 191
//! mesopic luminance in cd/m², illuminance in lx), with a labelled scale
//! bar below the image, as lighting designers read them (Radiance's
//! `falsecolor`).
//!
//! The palette is viridis (van der Walt & Smith, matplotlib 1.5, 2015):
//! perceptually uniform and readable by most colour-blind viewers; its
//! published sRGB values at nine evenly spaced stops, blended linearly in
//! sRGB between them.

use font8x8::{UnicodeFonts, BASIC_FONTS};
use rayon::prelude::*;

/// viridis at 0, 1/8, …, 1 (matplotlib's `_viridis_data` rows 0, 32, …,
/// 224, 255, rounded to 8 bits).
const VIRIDIS: [[u8; 3]; 9] = [
    [68, 1, 84],
    [71, 45, 123],
    [59, 82, 139],
    [44, 114, 142],
    [33, 145, 140],
    [40, 174, 128],
    [94, 201, 98],
    [173, 220, 48],
    [253, 231, 37],
];

const BAR: usize = 18;
const MARGIN: usize = 8;
const LABELS: usize = 20;
const BACKGROUND: [u8; 3] = [24, 24, 24];
const INK: [u8; 3] = [235, 235, 235];

/// What a map shows, from an X, Y, Z, V′ image.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Mapped {
    /// Y of a radiance image, cd/m².
    Luminance,
    /// CIE 191:2010's mesopic luminance of each pixel, at the adaptation
    /// coefficient of its own luminance and S/P (V′/Y), cd/m².
    Mesopic,
    /// Y of an illuminance image (`render --quantity illuminance` or
    /// `melanopic-edi`), lx.
    Illuminance,
    /// The melanopic equivalent daylight illuminance of a `render
    /// --quantity melanopic-edi` image (CIE S 026), lx.
    MelanopicEdi,
}

impl Mapped {
    pub const NAMES: &'static str = "luminance, mesopic, illuminance or melanopic-edi";

    pub fn from_name(name: &str) -> Option<Self> {
        match name.trim() {
            "luminance" => Some(Self::Luminance),
            "mesopic" => Some(Self::Mesopic),
            "illuminance" => Some(Self::Illuminance),
            "melanopic-edi" => Some(Self::MelanopicEdi),
            _ => None,
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Luminance => "luminance",
            Self::Mesopic => "mesopic",
            Self::Illuminance => "illuminance",
            Self::MelanopicEdi => "melanopic-edi",
        }
    }

    pub fn unit(self) -> &'static str {
        match self {
            Self::Illuminance | Self::MelanopicEdi => "lx",
            _ => "cd/m2",
        }
    }

    /// The quantity an image must hold (its EXR's `quantity`) to be
    /// mapped so: the one `render --quantity` makes.
    pub fn needs(self) -> &'static str {
        match self {
            Self::Illuminance => "illuminance",
            Self::MelanopicEdi => "melanopic-edi",
            _ => "radiance",
        }
    }

    /// Whether an image holding `quantity` can be mapped so: a melanopic
    /// image holds illuminance too.
    pub fn reads(self, quantity: &str) -> bool {
        quantity == self.needs() || (self == Self::Illuminance && quantity == "melanopic-edi")
    }

    /// The value of each pixel.
    pub fn values(self, pixels: &[[f32; 4]]) -> Vec<f32> {
        match self {
            // CIE 191's iteration per pixel: in parallel.
            Self::Mesopic => pixels
                .par_iter()
                .map(|p| {
                    let sp = if p[1] > 0.0 { p[3] / p[1] } else { 0.0 };
                    crate::mode::mesopic_luminance(p[1] as f64, sp as f64) as f32
                })
                .collect(),
            Self::MelanopicEdi => pixels.iter().map(|p| p[3]).collect(),
            _ => pixels.iter().map(|p| p[1]).collect(),
        }
    }
}

/// How values map onto the palette.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scale {
    pub lo: f64,
    pub hi: f64,
    /// Logarithmic (decades) rather than linear.
    pub log: bool,
}

impl Scale {
    /// The default range of `values` (finite ones): linear 0 to the 99th
    /// percentile, or logarithmic over three decades below it.
    pub fn auto(values: &[f32], log: bool) -> Self {
        let mut v: Vec<f32> = values
            .iter()
            .copied()
            .filter(|x| x.is_finite() && *x > 0.0)
            .collect();
        let hi = if v.is_empty() {
            1.0
        } else {
            let k = ((v.len() - 1) as f64 * 0.99) as usize;
            *v.select_nth_unstable_by(k, f32::total_cmp).1 as f64
        };
        let hi = if hi > 0.0 { hi } else { 1.0 };
        Self {
            lo: if log { hi * 1e-3 } else { 0.0 },
            hi,
            log,
        }
    }

    /// `LO:HI`, e.g. `0:50`; `None` if it is not two numbers.
    pub fn parse(text: &str, log: bool) -> Option<Self> {
        let (a, b) = text.split_once(':')?;
        Some(Self {
            lo: a.trim().parse().ok()?,
            hi: b.trim().parse().ok()?,
            log,
        })
    }

    /// Where `v` falls in [0, 1].
    pub fn position(&self, v: f64) -> f64 {
        let t = if self.log {
            if v <= 0.0 {
                return 0.0;
            }
            (v.log10() - self.lo.log10()) / (self.hi.log10() - self.lo.log10())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        };
        if t.is_nan() {
            0.0
        } else {
            t.clamp(0.0, 1.0)
        }
    }

    /// The value at position `t` ∈ [0, 1].
    fn value(&self, t: f64) -> f64 {
        if self.log {
            10f64.powf(self.lo.log10() + t * (self.hi.log10() - self.lo.log10()))
        } else {
            self.lo + t * (self.hi - self.lo)
        }
    }

    /// Whether the range can be drawn: finite, lo < hi, and lo > 0 on a
    /// logarithmic scale.
    pub fn is_valid(&self) -> bool {
        self.lo.is_finite()
            && self.hi.is_finite()
            && self.lo < self.hi
            && (!self.log || self.lo > 0.0)
    }
}

/// The palette's colour at `t` ∈ [0, 1].
pub fn palette(t: f64) -> [u8; 3] {
    let x = t.clamp(0.0, 1.0) * (VIRIDIS.len() - 1) as f64;
    let i = (x as usize).min(VIRIDIS.len() - 2);
    let f = x - i as f64;
    let (a, b) = (VIRIDIS[i], VIRIDIS[i + 1]);
    [0, 1, 2].map(|c| (a[c] as f64 + f * (b[c] as f64 - a[c] as f64)).round() as u8)
}

/// The map of `values` (width × height, row-major) with a scale bar below
/// labelled in `unit`: (width, height, RGB bytes) of the whole picture.
pub fn false_colour(
    values: &[f32],
    width: usize,
    height: usize,
    scale: &Scale,
    unit: &str,
) -> (usize, usize, Vec<u8>) {
    let legend = MARGIN + BAR + 4 + LABELS;
    let h = height + legend;
    let mut px = BACKGROUND.repeat(width * h);
    for (i, v) in values.iter().enumerate().take(width * height) {
        let c = if v.is_finite() {
            palette(scale.position(*v as f64))
        } else {
            [255, 0, 255] // not a number: magenta, off the palette
        };
        px[i * 3..i * 3 + 3].copy_from_slice(&c);
    }
    // The bar, inset by the margin, and five labels under it.
    // (Without the inset on pictures too narrow for it, so the bar stays
    // in its rows.)
    let inset = if width > 2 * MARGIN + 1 { MARGIN } else { 0 };
    let (x0, x1) = (inset, width.saturating_sub(inset).max(inset + 1));
    for y in height + MARGIN..height + MARGIN + BAR {
        for x in x0..x1 {
            let t = (x - x0) as f64 / (x1 - x0 - 1).max(1) as f64;
            let i = (y * width + x) * 3;
            px[i..i + 3].copy_from_slice(&palette(t));
        }
    }
    let ticks = 5;
    for k in 0..ticks {
        let t = k as f64 / (ticks - 1) as f64;
        let mut label = number(scale.value(t));
        if k == ticks - 1 {
            label = format!("{label} {unit}");
        }
        let x = x0 + (t * (x1 - x0 - 1) as f64) as usize;
        let text_width = label.chars().count() * 8;
        let left = x
            .saturating_sub(text_width / 2)
            .min(width.saturating_sub(text_width));
        text(&mut px, width, left, height + MARGIN + BAR + 4, &label);
    }
    (width, h, px)
}

/// A label for `v`: three significant digits, no exponent below 10⁵.
fn number(v: f64) -> String {
    let a = v.abs();
    if a == 0.0 {
        "0".into()
    } else if !(1e-3..1e5).contains(&a) {
        format!("{v:.1e}")
    } else if a >= 100.0 {
        format!("{v:.0}")
    } else if a >= 10.0 {
        format!("{v:.1}")
    } else if a >= 1.0 {
        format!("{v:.2}")
    } else {
        format!("{v:.3}")
    }
}

/// Draws `label` in the 8 × 8 font at (x, y), clipped to the picture.
fn text(px: &mut [u8], w: usize, x: usize, y: usize, label: &str) {
    let h = px.len() / 3 / w.max(1);
    for (n, ch) in label.chars().enumerate() {
        let Some(rows) = BASIC_FONTS.get(ch) else {
            continue;
        };
        for (r, bits) in rows.iter().enumerate() {
            for b in 0..8 {
                let (gx, gy) = (x + n * 8 + b, y + r);
                if bits & (1 << b) != 0 && gx < w && gy < h {
                    let i = (gy * w + gx) * 3;
                    px[i..i + 3].copy_from_slice(&INK);
                }
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_palette_runs_from_dark_violet_to_yellow_and_brightens() {
        assert_eq!(palette(0.0), VIRIDIS[0]);
        assert_eq!(palette(1.0), VIRIDIS[8]);
        // Luma rises monotonically along the palette.
        let luma = |c: [u8; 3]| 0.2126 * c[0] as f64 + 0.7152 * c[1] as f64 + 0.0722 * c[2] as f64;
        let l: Vec<f64> = (0..=64).map(|k| luma(palette(k as f64 / 64.0))).collect();
        assert!(l.windows(2).all(|w| w[1] >= w[0] - 0.5), "{l:?}");
    }

    #[test]
    fn values_land_where_the_scale_puts_them_and_the_bar_is_labelled() {
        let scale = Scale {
            lo: 1.0,
            hi: 1000.0,
            log: true,
        };
        assert!((scale.position(31.622_776) - 0.5).abs() < 1e-6);
        let values = [1.0f32, 31.622_776, 1000.0, f32::NAN];
        let (w, h, px) = false_colour(&values, 4, 1, &scale, "lx");
        assert_eq!((w, h), (4, 1 + MARGIN + BAR + 4 + LABELS));
        assert_eq!(&px[0..3], &palette(0.0));
        assert_eq!(&px[3..6], &palette(0.5));
        assert_eq!(&px[6..9], &palette(1.0));
        assert_eq!(&px[9..12], &[255, 0, 255]);
        let linear = Scale::auto(&[0.0, 2.0, 4.0, 8.0], false);
        assert_eq!((linear.lo, linear.hi), (0.0, 4.0));
        assert_eq!(number(1234.5), "1234");
        assert_eq!(number(0.5), "0.500");
    }

    #[test]
    fn a_wide_picture_has_ink_in_its_labels() {
        let values = vec![5.0f32; 200 * 50];
        let scale = Scale::auto(&values, false);
        let (w, h, px) = false_colour(&values, 200, 50, &scale, "cd/m2");
        let ink = (50 + MARGIN + BAR..h).any(|y| (0..w).any(|x| px[(y * w + x) * 3..][..3] == INK));
        assert!(ink);
    }
    #[test]
    fn a_narrow_picture_keeps_its_bar_in_its_own_rows() {
        // 4 pixels wide: the bar spans the width from the first column.
        let (w, h, px) = false_colour(&[1.0; 8], 4, 2, &Scale::auto(&[1.0], false), "lx");
        let row = 2 + MARGIN;
        assert_eq!(&px[row * w * 3..][..3], &palette(0.0));
        assert_eq!(&px[(row * w + 3) * 3..][..3], &palette(1.0));
        assert_eq!(px.len(), w * h * 3);
    }

    #[test]
    fn mesopic_values_are_cie_191s_of_each_pixel() {
        let px = [[0.0, 0.1, 0.0, 0.25], [0.0, 100.0, 0.0, 250.0], [0.0; 4]];
        let v = Mapped::Mesopic.values(&px);
        assert_eq!(v[0], crate::mode::mesopic_luminance(0.1, 2.5) as f32);
        assert!(v[0] > 0.1); // blue-rich light, mesopic: brighter
        assert_eq!(v[1], 100.0); // photopic: L itself
        assert_eq!(v[2], 0.0);
        assert_eq!(Mapped::Luminance.values(&px)[1], 100.0);
        assert_eq!(Mapped::from_name("mesopic"), Some(Mapped::Mesopic));
        assert_eq!(Mapped::Illuminance.unit(), "lx");
    }
}

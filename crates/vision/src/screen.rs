//! Screening the input: pixels that are not finite numbers (NaN, ±∞) or
//! absurdly bright are left out of the image statistics (adaptation
//! luminance, maximum, S/P ratio, and through them exposure and the glare
//! threshold) and out of the spatial stages, so that a few broken pixels
//! cannot change the rest of the image. They are shown black (not finite)
//! or at the display's peak (absurd), and the pipeline says how many.

use rayon::prelude::*;

/// Above this absolute value in any channel (cd/m², or scotopic cd/m² for
/// V′) a pixel is absurd: 10¹⁰ cd/m² is about six times the luminance of
/// the sun's disc at noon (1.6·10⁹ cd/m², the brightest natural source;
/// CIE 2004, Kaufman & Christensen IES Lighting Handbook), so no scene a
/// person can look at reaches it. A fixed physical bound rather than a
/// percentile: an image of a small sun in a dim sky is rightly many orders
/// of magnitude above its own median.
pub const ABSURD_LUMINANCE: f32 = 1e10;

/// Why a pixel is left out.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LeftOut {
    /// A channel is NaN or ±∞.
    NonFinite,
    /// A channel's magnitude exceeds [`ABSURD_LUMINANCE`].
    Absurd,
}

/// Whether (and why) the pixel [X, Y, Z, V′] is left out.
#[inline]
pub fn left_out(p: &[f32; 4]) -> Option<LeftOut> {
    if p.iter().any(|v| !v.is_finite()) {
        Some(LeftOut::NonFinite)
    } else if p.iter().any(|v| v.abs() > ABSURD_LUMINANCE) {
        Some(LeftOut::Absurd)
    } else {
        None
    }
}

/// How many pixels were left out, by reason.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub struct LeftOutCount {
    pub non_finite: usize,
    pub absurd: usize,
}

impl LeftOutCount {
    pub fn of(pixels: &[[f32; 4]]) -> Self {
        pixels
            .par_iter()
            .map(|p| match left_out(p) {
                Some(LeftOut::NonFinite) => (1, 0),
                Some(LeftOut::Absurd) => (0, 1),
                None => (0, 0),
            })
            .reduce(|| (0, 0), |a, b| (a.0 + b.0, a.1 + b.1))
            .into()
    }

    pub fn total(&self) -> usize {
        self.non_finite + self.absurd
    }

    /// One sentence for the user, or `None` when every pixel was used.
    pub fn note(&self) -> Option<String> {
        if self.total() == 0 {
            return None;
        }
        let mut parts = Vec::new();
        if self.non_finite > 0 {
            parts.push(format!(
                "{} non-finite (NaN or ∞) pixel(s), shown black",
                self.non_finite
            ));
        }
        if self.absurd > 0 {
            parts.push(format!(
                "{} pixel(s) above {ABSURD_LUMINANCE:e} cd/m², shown at the display's peak",
                self.absurd
            ));
        }
        Some(format!(
            "{}: left out of the adaptation luminance, exposure, glare and local adaptation",
            parts.join("; ")
        ))
    }
}

impl From<(usize, usize)> for LeftOutCount {
    fn from((non_finite, absurd): (usize, usize)) -> Self {
        Self { non_finite, absurd }
    }
}

/// The index and reason of every pixel left out, in order (usually none:
/// a list, not a full-size mask, so a clean image costs no memory).
pub fn left_out_pixels(pixels: &[[f32; 4]]) -> Vec<(usize, LeftOut)> {
    pixels
        .par_iter()
        .enumerate()
        .filter_map(|(i, p)| left_out(p).map(|why| (i, why)))
        .collect()
}

/// The pixels with those left out replaced by `fill` (for the spatial
/// stages, which need a value everywhere); `None` when none is left out.
pub fn filled(pixels: &[[f32; 4]], fill: [f32; 4]) -> Option<Vec<[f32; 4]>> {
    if !pixels.par_iter().any(|p| left_out(p).is_some()) {
        return None;
    }
    Some(
        pixels
            .par_iter()
            .map(|p| if left_out(p).is_some() { fill } else { *p })
            .collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn non_finite_and_absurd_pixels_are_told_apart_and_counted() {
        let px = [
            [1.0, 1.0, 1.0, 1.0],
            [f32::NAN, 1.0, 1.0, 1.0],
            [1.0, 1.0, 1.0, f32::INFINITY],
            [1.0, 2e38, 1.0, 1.0],
            [1.0, 1e9, 1.0, 2e9],
            [-3e12, 1.0, 1.0, 1.0],
        ];
        let kinds: Vec<_> = px.iter().map(left_out).collect();
        use LeftOut::*;
        assert_eq!(
            kinds,
            [
                None,
                Some(NonFinite),
                Some(NonFinite),
                Some(Absurd),
                None,
                Some(Absurd)
            ]
        );
        let c = LeftOutCount::of(&px);
        assert_eq!((c.non_finite, c.absurd), (2, 2));
        let note = c.note().unwrap();
        assert!(note.contains("2 non-finite") && note.contains("2 pixel(s) above 1e10"));
        assert_eq!(LeftOutCount::of(&px[..1]).note(), None);
        let f = filled(&px, [7.0; 4]).unwrap();
        assert_eq!(f[0], px[0]);
        assert_eq!(f[1], [7.0; 4]);
        assert_eq!(f[4], px[4]);
        assert!(filled(&px[..1], [7.0; 4]).is_none());
        let listed: Vec<usize> = left_out_pixels(&px).iter().map(|l| l.0).collect();
        assert_eq!(listed, [1, 2, 3, 5]);
        assert_eq!(left_out_pixels(&px)[2].1, Absurd);
    }
}

//! The visual mode: how far vision has moved from cones to rods, from the
//! adaptation luminance. Two published measures:
//!
//! - Jensen et al. 2001 ("A Physically-Based Night Sky Model", SIGGRAPH):
//!   the scotopic sensitivity s ∈ [0, 1] that drives the night shift
//!   (../shared/vision-equations.md §3);
//! - CIE 191:2010 (MES2): the mesopic adaptation coefficient m ∈ [0, 1]
//!   from photopic luminance and the S/P ratio (§5), which also names the
//!   mode: photopic at m = 1 (≥ 5 cd/m²), scotopic at m = 0 (≤ 0.005).

use rayon::prelude::*;

use crate::screen::{left_out, LeftOut, LeftOutCount, ABSURD_LUMINANCE};

/// Jensen et al. 2001: s = 0 at log₁₀ L ≤ −2, 1 at log₁₀ L ≥ 0.6, and the
/// smoothstep 3t² − 2t³ of t = (log₁₀ L + 2) / 2.6 between. s = 1 is fully
/// photopic (no night shift), s = 0 fully scotopic.
pub fn scotopic_sensitivity(luminance: f64) -> f64 {
    if luminance.is_nan() || luminance <= 0.0 {
        return 0.0;
    }
    let t = ((luminance.log10() + 2.0) / 2.6).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// CIE 191:2010: m = a + b·log₁₀ L_mes (a = 0.7670, b = 0.3334), iterated
/// from m = 0.5 with L_mes = [m·L_p + (1−m)·L_s·V′(λ₀)] / [m + (1−m)·V′(λ₀)],
/// L_s = (S/P)·L_p, V′(λ₀) = 683/1699. The iteration can oscillate at high
/// L_p with very high S/P (Melgosa et al. 2017), so it is bounded.
pub fn mesopic_coefficient(photopic: f64, sp_ratio: f64) -> f64 {
    const A: f64 = 0.7670;
    const B: f64 = 0.3334;
    if photopic.is_nan() || photopic <= 0.0 {
        return 0.0;
    }
    let scotopic = sp_ratio.max(0.0) * photopic;
    let mut m = 0.5;
    for _ in 0..100 {
        let l_mes = mesopic_at(m, photopic, scotopic);
        let next = if l_mes > 0.0 {
            (A + B * l_mes.log10()).clamp(0.0, 1.0)
        } else {
            0.0
        };
        if (next - m).abs() < 1e-9 {
            return next;
        }
        m = next;
    }
    m
}

/// CIE 191:2010's V′(λ₀) = 683/1699: V′ at 555 nm, where V = 1.
const V_LAMBDA0: f64 = 683.0 / 1699.0;

/// CIE 191:2010's mesopic luminance at adaptation coefficient m, from
/// photopic luminance L_p (cd/m²) and scotopic L_s (scotopic cd/m²):
/// [m·L_p + (1−m)·L_s·V′(λ₀)] / [m + (1−m)·V′(λ₀)].
fn mesopic_at(m: f64, photopic: f64, scotopic: f64) -> f64 {
    (m * photopic + (1.0 - m) * scotopic * V_LAMBDA0) / (m + (1.0 - m) * V_LAMBDA0)
}

/// CIE 191:2010's mesopic luminance L_mes (cd/m²) of photopic luminance
/// `photopic` with S/P ratio `sp_ratio`: at the m of
/// [`mesopic_coefficient`]. L_p itself when photopic (m = 1), L_s when
/// scotopic (m = 0).
pub fn mesopic_luminance(photopic: f64, sp_ratio: f64) -> f64 {
    if photopic.is_nan() || photopic <= 0.0 {
        return 0.0;
    }
    let m = mesopic_coefficient(photopic, sp_ratio);
    mesopic_at(m, photopic, sp_ratio.max(0.0) * photopic)
}

/// CIE 191:2010's figures for a surface: its photopic luminance (cd/m²),
/// the adaptation coefficient m and the mesopic luminance (cd/m²).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Mesopic {
    pub luminance: f64,
    pub m: f64,
    pub mesopic: f64,
}

impl Mesopic {
    /// Of a Lambertian surface of `reflectance` under illuminance
    /// `illuminance_lx` with S/P ratio `sp_ratio`: L = ρE/π (a diffuser
    /// keeps the light's S/P), and m and L_mes from L as the eye adapted to
    /// it would see them.
    pub fn of_surface(illuminance_lx: f64, sp_ratio: f64, reflectance: f64) -> Self {
        let luminance = (reflectance * illuminance_lx / std::f64::consts::PI).max(0.0);
        Self {
            luminance,
            m: mesopic_coefficient(luminance, sp_ratio),
            mesopic: mesopic_luminance(luminance, sp_ratio),
        }
    }
}

/// A diffuse reflectance for `Mesopic::of_surface`, or why it is none:
/// it must lie in [0, 1].
pub fn reflectance(rho: f64) -> Result<f64, String> {
    if (0.0..=1.0).contains(&rho) {
        Ok(rho)
    } else {
        Err(format!("{rho}: give a reflectance from 0 to 1"))
    }
}

/// The visual mode's name, by CIE 191's range.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum VisualMode {
    Photopic,
    Mesopic,
    Scotopic,
}

impl VisualMode {
    pub fn from_mesopic(m: f64) -> Self {
        if m >= 1.0 {
            Self::Photopic
        } else if m <= 0.0 {
            Self::Scotopic
        } else {
            Self::Mesopic
        }
    }

    pub fn name(self) -> &'static str {
        match self {
            Self::Photopic => "photopic",
            Self::Mesopic => "mesopic",
            Self::Scotopic => "scotopic",
        }
    }
}

/// What the eye is adapted to.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Adaptation {
    /// One luminance for the whole image: its log-average (see
    /// `image_statistics`).
    Global,
    /// Per pixel, from the light pooled around it (`multiscale::adaptation`).
    Local,
    /// A stated luminance, cd/m².
    Fixed(f64),
}

impl Adaptation {
    /// Parses `global`, `local` or a luminance in cd/m² from
    /// [`f32::MIN_POSITIVE`] (the pipeline works in f32: smaller is 0 or
    /// subnormal there) to [`ABSURD_LUMINANCE`] (brighter than any scene a
    /// person can look at; 1e39 would be ∞ in f32).
    pub fn parse(text: &str) -> Option<Self> {
        match text.to_ascii_lowercase().as_str() {
            "global" => Some(Adaptation::Global),
            "local" => Some(Adaptation::Local),
            other => other
                .parse::<f64>()
                .ok()
                .filter(|&l| (l as f32).is_normal() && l > 0.0 && l <= f64::from(ABSURD_LUMINANCE))
                .map(Adaptation::Fixed),
        }
    }
}

/// Luminance statistics of an image.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ImageStatistics {
    /// exp(mean(ln(δ + Y))) with δ = 10⁻⁶ cd/m² (so black pixels count as
    /// very dark rather than as −∞): the global adaptation luminance.
    pub log_average: f64,
    pub maximum: f64,
    /// Mean V′ / mean Y: the scene's S/P ratio, for CIE 191.
    pub sp_ratio: f64,
    /// Mean X, Y, Z, V′ of the pixels used.
    pub mean: [f64; 4],
    /// Pixels left out of all of these (see [`crate::screen`]), except
    /// that absurd ones count in `log_average` at [`ABSURD_LUMINANCE`].
    pub left_out: LeftOutCount,
    /// Pixels used whose luminance Y is negative (counted as black): not
    /// an absolute X, Y, Z, V′ image, or a broken one.
    pub negative: usize,
}

impl ImageStatistics {
    /// A warning for the user when some pixels have negative luminance.
    pub fn negative_note(&self) -> Option<String> {
        (self.negative > 0).then(|| {
            format!(
                "{} pixel(s) have negative luminance (Y < 0), shown black: the input should be \
                 absolute X, Y, Z, V′ (cd/m²), which is never negative",
                self.negative
            )
        })
    }
}

/// Statistics of pixels given as [X, Y, Z, V′], over the pixels that are
/// finite and not absurd ([`crate::screen::left_out`]): the others count
/// neither as black nor at all; but an absurd pixel counts in the
/// log-average (the adaptation) at [`ABSURD_LUMINANCE`], as it is shown
/// (at the display's peak): one such pixel in N moves the log-average by
/// a factor (10¹⁰/L)^(1/N) at most, while an image that is mostly absurd
/// (a light level far too high) is reported photopic, as it looks, not
/// adapted to its few dark pixels. No pixel counted: black (δ).
pub fn image_statistics(pixels: &[[f32; 4]]) -> ImageStatistics {
    // In parallel over fixed blocks, each summed in order and the blocks'
    // sums added in order: the same figures on any number of threads.
    let Sums {
        used,
        log_sum,
        max,
        sum,
        left_out,
        negative,
    } = block_sums(pixels, Sums::of);
    let n = used.max(1) as f64;
    ImageStatistics {
        log_average: log_mean(log_sum, used + left_out.absurd, left_out.absurd),
        maximum: max,
        sp_ratio: if sum[1] > 0.0 { sum[3] / sum[1] } else { 0.0 },
        mean: sum.map(|s| s / n),
        left_out,
        negative,
    }
}

/// exp of the mean of the logs: `log_sum` over the pixels used, and
/// `absurd` more at [`ABSURD_LUMINANCE`]; δ when there are none.
fn log_mean(log_sum: f64, counted: usize, absurd: usize) -> f64 {
    if counted == 0 {
        return LOG_DELTA;
    }
    let absurd_log = (LOG_DELTA + f64::from(ABSURD_LUMINANCE)).ln();
    ((log_sum + absurd as f64 * absurd_log) / counted as f64).exp()
}

/// [`image_statistics`]`(pixels).log_average` alone, the same number
/// (the same sums in the same order) for a quarter of the work: the
/// multiscale model's adaptation, of an image whose statistics the
/// pipeline already has from before glare.
pub fn log_average(pixels: &[[f32; 4]]) -> f64 {
    let s = block_sums(pixels, Sums::of_log);
    log_mean(s.log_sum, s.used + s.left_out.absurd, s.left_out.absurd)
}

/// The parts of [`log_average`] over some pixels, for a caller that
/// visits every pixel anyway (glare adds these up row by row) and joins
/// the parts with [`LogSum::join`].
#[derive(Debug, Clone, Copy, Default)]
pub struct LogSum {
    used: usize,
    absurd: usize,
    log_sum: f64,
}

impl LogSum {
    /// The parts of `a` and then `b`.
    pub fn join(self, b: LogSum) -> LogSum {
        LogSum {
            used: self.used + b.used,
            absurd: self.absurd + b.absurd,
            log_sum: self.log_sum + b.log_sum,
        }
    }

    /// The log-average of the pixels summed, as [`log_average`].
    pub fn mean(&self) -> f64 {
        log_mean(self.log_sum, self.used + self.absurd, self.absurd)
    }
}

/// [`LogSum`] of `pixels`.
pub fn log_sum_of(pixels: &[[f32; 4]]) -> LogSum {
    let s = Sums::of_log(pixels);
    LogSum {
        used: s.used,
        absurd: s.left_out.absurd,
        log_sum: s.log_sum,
    }
}

/// `of` over fixed blocks of `pixels` in parallel, the blocks' sums added
/// in order.
fn block_sums(pixels: &[[f32; 4]], of: fn(&[[f32; 4]]) -> Sums) -> Sums {
    const BLOCK: usize = 1 << 16;
    let blocks: Vec<Sums> = pixels.par_chunks(BLOCK).map(of).collect();
    blocks.iter().fold(Sums::default(), |a, b| a.add(b))
}

/// Sums over some pixels for [`image_statistics`].
#[derive(Default)]
struct Sums {
    used: usize,
    /// Σ ln(δ + Y).
    log_sum: f64,
    max: f64,
    sum: [f64; 4],
    /// The pixels not used, by reason (counted in the same pass).
    left_out: LeftOutCount,
    /// Pixels used with Y < 0.
    negative: usize,
}

/// δ of the log-average: black pixels count as very dark, not as −∞.
const LOG_DELTA: f64 = 1e-6;

/// Pixels whose logs are taken in one wide loop.
const LOG_CHUNK: usize = 256;

/// Σ ln(δ + y) over the `used` entries of `ys`, in order; the logs as a
/// wide loop (`wide_math::log2` of δ + y rounded to f32: 6e-8 in each
/// log, against libm's `ln` per pixel at a third of the statistics' time).
fn log_sum(ys: &[f64], used: &[bool; LOG_CHUNK]) -> f64 {
    let mut logs = [0.0f64; LOG_CHUNK];
    let logs = &mut logs[..ys.len()];
    crate::wide_math::dispatch(
        #[inline(always)]
        || {
            for (l, y) in logs.iter_mut().zip(ys) {
                *l = crate::wide_math::log2((LOG_DELTA + y) as f32) * std::f64::consts::LN_2;
            }
        },
    );
    logs.iter()
        .zip(used)
        .filter(|(_, u)| **u)
        .map(|(l, _)| l)
        .sum()
}

impl Sums {
    fn of(pixels: &[[f32; 4]]) -> Self {
        let mut s = Sums::default();
        for chunk in pixels.chunks(LOG_CHUNK) {
            let mut ys = [0.0f64; LOG_CHUNK];
            let mut used = [false; LOG_CHUNK];
            for (i, p) in chunk.iter().enumerate() {
                match left_out(p) {
                    Some(LeftOut::NonFinite) => s.left_out.non_finite += 1,
                    Some(LeftOut::Absurd) => s.left_out.absurd += 1,
                    None => {
                        s.negative += usize::from(p[1] < 0.0);
                        let y = (p[1] as f64).max(0.0);
                        (ys[i], used[i]) = (y, true);
                        s.used += 1;
                        s.max = s.max.max(y);
                        for (s, v) in s.sum.iter_mut().zip(p) {
                            *s += (*v as f64).max(0.0);
                        }
                    }
                }
            }
            s.log_sum += log_sum(&ys[..chunk.len()], &used);
        }
        s
    }

    /// Only `used`, `log_sum` and the absurd count, as [`Sums::of`]
    /// computes them.
    fn of_log(pixels: &[[f32; 4]]) -> Self {
        let mut s = Sums::default();
        for chunk in pixels.chunks(LOG_CHUNK) {
            let mut ys = [0.0f64; LOG_CHUNK];
            let mut used = [false; LOG_CHUNK];
            for (i, p) in chunk.iter().enumerate() {
                match left_out(p) {
                    Some(LeftOut::Absurd) => s.left_out.absurd += 1,
                    Some(LeftOut::NonFinite) => {}
                    None => {
                        (ys[i], used[i]) = ((p[1] as f64).max(0.0), true);
                        s.used += 1;
                    }
                }
            }
            s.log_sum += log_sum(&ys[..chunk.len()], &used);
        }
        s
    }

    fn add(self, b: &Sums) -> Sums {
        Sums {
            used: self.used + b.used,
            log_sum: self.log_sum + b.log_sum,
            max: self.max.max(b.max),
            sum: std::array::from_fn(|c| self.sum[c] + b.sum[c]),
            left_out: LeftOutCount {
                non_finite: self.left_out.non_finite + b.left_out.non_finite,
                absurd: self.left_out.absurd + b.left_out.absurd,
            },
            negative: self.negative + b.negative,
        }
    }
}

/// The visual state at one adaptation luminance.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct VisualState {
    /// Adaptation luminance, cd/m².
    pub luminance: f64,
    /// Jensen et al.'s scotopic sensitivity (1 photopic, 0 scotopic).
    pub s: f64,
    /// CIE 191's mesopic coefficient.
    pub m: f64,
    pub mode: VisualMode,
}

impl VisualState {
    pub fn new(luminance: f64, sp_ratio: f64) -> Self {
        let m = mesopic_coefficient(luminance, sp_ratio);
        Self {
            luminance,
            s: scotopic_sensitivity(luminance),
            m,
            mode: VisualMode::from_mesopic(m),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sensitivity_follows_jensen() {
        assert_eq!(scotopic_sensitivity(0.0), 0.0);
        assert_eq!(scotopic_sensitivity(0.001), 0.0);
        assert_eq!(scotopic_sensitivity(0.01), 0.0);
        assert_eq!(scotopic_sensitivity(10f64.powf(0.6)), 1.0);
        assert_eq!(scotopic_sensitivity(100.0), 1.0);
        // Midpoint of the log range: t = ½ → s = ½.
        let mid = 10f64.powf(-2.0 + 1.3);
        assert!((scotopic_sensitivity(mid) - 0.5).abs() < 1e-12);
        // Monotonic between.
        let mut prev = 0.0;
        for i in 0..=300 {
            let s = scotopic_sensitivity(10f64.powf(-3.0 + i as f64 * 0.01));
            assert!(s >= prev);
            prev = s;
        }
    }

    #[test]
    fn mesopic_luminance_is_the_iterations_fixed_point() {
        // Photopic: L_p; scotopic: L_s = (S/P)·L_p; between, the fixed
        // point m = 0.7670 + 0.3334·log₁₀ L_mes of CIE 191:2010.
        assert!((mesopic_luminance(100.0, 2.0) - 100.0).abs() < 1e-9);
        assert!((mesopic_luminance(0.001, 2.0) - 0.002).abs() < 1e-12);
        for (lp, sp) in [(0.1, 1.5), (0.5, 0.25), (1.0, 2.5)] {
            let m = mesopic_coefficient(lp, sp);
            let l = mesopic_luminance(lp, sp);
            assert!(m > 0.0 && m < 1.0, "{lp} {sp}: m {m}");
            assert!(
                (m - (0.7670 + 0.3334 * l.log10())).abs() < 1e-6,
                "{lp} {sp}"
            );
            // Between L_p and L_s.
            assert!((l - lp) * (l - sp * lp) <= 0.0, "{lp} {sp}: {l}");
        }
    }

    #[test]
    fn a_reflectance_lies_in_0_to_1() {
        assert_eq!(reflectance(0.1), Ok(0.1));
        for bad in [-0.1, 1.5, f64::NAN, f64::INFINITY] {
            assert!(
                reflectance(bad).unwrap_err().contains("from 0 to 1"),
                "{bad}"
            );
        }
    }

    #[test]
    fn a_surfaces_mesopic_figures_come_from_its_luminance() {
        // 10 lx on a road of reflectance 0.1: L = 1/π cd/m², mesopic.
        let f = Mesopic::of_surface(10.0, 2.0, 0.1);
        let l = 1.0 / std::f64::consts::PI;
        assert!((f.luminance - l).abs() < 1e-12);
        assert_eq!(f.m, mesopic_coefficient(l, 2.0));
        assert_eq!(f.mesopic, mesopic_luminance(l, 2.0));
        assert!(f.m > 0.0 && f.m < 1.0, "{f:?}");
        // Rich in blue (S/P 2): brighter to the mesopic eye than photopic L.
        assert!(f.mesopic > f.luminance);
        // A dark point is scotopic and black.
        assert_eq!(Mesopic::of_surface(0.0, 2.0, 0.1).mesopic, 0.0);
    }

    #[test]
    fn mesopic_coefficient_spans_cie_191_range() {
        // At S/P = 1 photopic and scotopic luminances coincide (L_mes = L_p),
        // so m = a + b·log₁₀ L_p directly.
        assert_eq!(mesopic_coefficient(10.0, 1.0), 1.0);
        assert_eq!(mesopic_coefficient(0.001, 1.0), 0.0);
        let m = mesopic_coefficient(0.1, 1.0);
        // log₁₀ 0.1 = −1.
        assert!((m - (0.7670 - 0.3334)).abs() < 1e-6, "{m}");
        // A bluer source (higher S/P) at the same photopic luminance looks
        // brighter in mesopic vision: L_mes > L_p, so m is larger.
        assert!(mesopic_coefficient(0.1, 2.0) > m);
        assert_eq!(VisualMode::from_mesopic(1.0), VisualMode::Photopic);
        assert_eq!(VisualMode::from_mesopic(0.3), VisualMode::Mesopic);
        assert_eq!(VisualMode::from_mesopic(0.0), VisualMode::Scotopic);
    }

    #[test]
    fn statistics_of_a_two_level_image() {
        let px = [[0.0, 1.0, 0.0, 2.0], [0.0, 100.0, 0.0, 200.0]];
        let s = image_statistics(&px);
        assert!((s.log_average - 10.0).abs() < 1e-4, "{}", s.log_average);
        assert_eq!(s.maximum, 100.0);
        assert!((s.sp_ratio - 2.0).abs() < 1e-12);
    }
}

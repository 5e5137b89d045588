//! Glare ratings of the sources in a field of view, and road lighting's
//! threshold increment: the figures lighting designs are judged by
//! (`docs/lighting.md`). Each source is a luminance, a solid angle and a
//! direction from the eye; the line of sight and the vertical give the
//! angles the formulas take.
//!
//! - the position index P (Guth, as the IES Lighting Handbook fits it
//!   above the line of sight; Iwata's below it, as Radiance's evalglare
//!   takes it);
//! - UGR (CIE 117:1995): 8·log₁₀(0.25/L_b · Σ L²ω/P²);
//! - DGP (Wienold & Christoffersen 2006): 5.87·10⁻⁵·E_v + 9.18·10⁻²·
//!   log₁₀(1 + Σ L²ω/(E_v^1.87·P²)) + 0.16, times evalglare's low-light
//!   correction below 1000 lx;
//! - the veiling luminance of CIE 146:2002's general disability glare
//!   equation, for an observer's age and pigmentation (`glare::psf`);
//! - the threshold increment of EN 13201-3 / CIE 140: TI = 65·L_v/L_av^0.8 %,
//!   L_v = k·Σ E/θ², k = 9.86·(1 + (A/66.4)⁴), 1.5° ≤ θ ≤ 60°.

use crate::glare::psf::GlareSpread;
use crate::Observer;

mod evaluate;
pub mod fisheye;
#[cfg(test)]
mod tests;

pub use evaluate::{evaluate, neighbours, Figures, Found, FISHEYE_VIEW};
pub use fisheye::{Fisheye, Projection};

/// A direction from the eye, (x, y, z), any length but zero.
pub type Dir = [f64; 3];

/// A glare source: its mean luminance (cd/m²), its solid angle (sr) and
/// the direction of its centre from the eye.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Source {
    pub luminance: f64,
    pub solid_angle: f64,
    pub dir: Dir,
}

/// The eye's line of sight and the direction it calls up (any length but
/// zero, not parallel).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct View {
    pub sight: Dir,
    pub up: Dir,
}

fn dot(a: Dir, b: Dir) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn cross(a: Dir, b: Dir) -> Dir {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn unit(a: Dir) -> Dir {
    let l = dot(a, a).sqrt();
    a.map(|c| c / l)
}

impl View {
    /// The unit line of sight, the unit up across it, and the unit right.
    fn frame(&self) -> (Dir, Dir, Dir) {
        let f = unit(self.sight);
        let u = self.up;
        let u = unit([0, 1, 2].map(|i| u[i] - f[i] * dot(u, f)));
        (f, u, cross(f, u))
    }

    /// σ, the angle (degrees) between the line of sight and `d`.
    pub fn sigma(&self, d: Dir) -> f64 {
        let (f, _, _) = self.frame();
        dot(f, unit(d)).clamp(-1.0, 1.0).acos().to_degrees()
    }

    /// The position index P of a source in direction `d`: 1 on the line
    /// of sight, growing away from it (a source there glares less).
    /// Above the line of sight, Guth's, with σ and τ in degrees (τ the
    /// angle, seen along the line of sight, between up and the source):
    /// P = exp[(35.2 − 0.31889τ − 1.22e^(−2τ/9))·10⁻³σ + (21 + 0.26667τ −
    /// 0.002963τ²)·10⁻⁵σ²] (IES Lighting Handbook). Below it, Iwata's:
    /// P = 1 + 0.8R (R ≤ 0.6) or 1 + 1.2R, R = √(tan²φ + tan²θ) with φ and
    /// θ the angles below and beside the line of sight, R at most 3. At
    /// most 16. (Both as Radiance's evalglare computes them.)
    pub fn position_index(&self, d: Dir) -> f64 {
        let (f, u, r) = self.frame();
        let d = unit(d);
        let (x, y, z) = (dot(d, r), dot(d, u), dot(d, f));
        let p = if y < 0.0 {
            // Tangents of the angles below and beside the line of sight,
            // as evalglare takes them (from the horizontal and vertical
            // planes through it).
            let below = y.asin().tan();
            let beside = x.asin().tan();
            let big_r = (below * below + beside * beside).sqrt();
            let fact = if big_r > 0.6 { 1.2 } else { 0.8 };
            1.0 + fact * big_r.min(3.0)
        } else {
            let sigma = z.clamp(-1.0, 1.0).acos().to_degrees();
            let tau = x.atan2(y).abs().to_degrees();
            ((35.2 - 0.31889 * tau - 1.22 * (-2.0 * tau / 9.0).exp()) * 1e-3 * sigma
                + (21.0 + 0.26667 * tau - 0.002963 * tau * tau) * 1e-5 * sigma * sigma)
                .exp()
        };
        p.min(16.0)
    }

    /// UGR (CIE 117:1995) over a background of luminance `background`
    /// (cd/m²): 8·log₁₀(0.25/L_b · Σ L²ω/P²); `None` without sources or
    /// without a background to see them against.
    pub fn ugr(&self, sources: &[Source], background: f64) -> Option<f64> {
        let sum: f64 = sources
            .iter()
            .map(|s| (s.luminance / self.position_index(s.dir)).powi(2) * s.solid_angle)
            .sum();
        (sum > 0.0 && background > 0.0).then(|| 8.0 * (0.25 / background * sum).log10())
    }

    /// DGP (Wienold & Christoffersen 2006, Energy and Buildings 38:743,
    /// eq. 7) with the vertical illuminance at the eye `e_v` (lx), times
    /// evalglare's low-light correction e^(0.024E_v − 4)/(1 + e^(0.024E_v −
    /// 4)) below 1000 lx; at most 1. (evalglare's constants are 0.092 and
    /// 0.159, a DGP 0.001 apart.)
    pub fn dgp(&self, sources: &[Source], e_v: f64) -> f64 {
        if e_v.is_nan() || e_v <= 0.0 {
            return 0.0;
        }
        let sum: f64 = sources
            .iter()
            .map(|s| s.luminance.powi(2) * s.solid_angle / self.position_index(s.dir).powi(2))
            .sum();
        let dgp = 5.87e-5 * e_v + 9.18e-2 * (1.0 + sum / e_v.powf(1.87)).log10() + 0.16;
        let low = if e_v < 1000.0 {
            let t = (0.024 * e_v - 4.0).exp();
            t / (1.0 + t)
        } else {
            1.0
        };
        (dgp * low).min(1.0)
    }

    /// The veiling luminance (cd/m²) the sources cast for `observer`:
    /// Σ E·f(θ), E = Lω·cos σ the illuminance each gives at the eye, f CIE
    /// 146:2002's general disability glare equation at θ = σ (from 0.1°;
    /// a source nearer the line of sight counts at 0.1°).
    pub fn veiling(&self, sources: &[Source], observer: &Observer) -> f64 {
        let spread = GlareSpread::new(observer);
        sources
            .iter()
            .map(|s| {
                let sigma = self.sigma(s.dir);
                let e = s.luminance * s.solid_angle * sigma.to_radians().cos().max(0.0);
                e * spread.general(sigma.max(0.1))
            })
            .sum()
    }
}

/// EN 13201-3's age factor k of the veiling luminance, 9.86·(1 + (A/66.4)⁴)
/// (about 10 at 23 years, the standard's observer).
pub fn ti_age_factor(age: f64) -> f64 {
    9.86 * (1.0 + (age / 66.4).powi(4))
}

/// The standard's observer's age for TI, years: k ≈ 10.
pub const TI_AGE: f64 = 23.0;

/// The veiling luminance of EN 13201-3 / CIE 140 (cd/m²): k·Σ E_k/θ_k²
/// over luminaires giving E_k lx at the eye θ_k degrees from the line of
/// sight, those within 1.5°–60° only.
pub fn road_veiling(lamps: &[(f64, f64)], age: f64) -> f64 {
    ti_age_factor(age)
        * lamps
            .iter()
            .filter(|(_, theta)| (1.5..=60.0).contains(theta))
            .map(|(e, theta)| e / (theta * theta))
            .sum::<f64>()
}

/// The threshold increment TI (%) of a veiling luminance `l_v` over a road
/// of average luminance `l_av` (cd/m²): 65·L_v/L_av^0.8 (EN 13201-3, for
/// 0.05 < L_av < 5 cd/m²); `None` for a road without luminance.
pub fn threshold_increment(l_v: f64, l_av: f64) -> Option<f64> {
    (l_av > 0.0).then(|| 65.0 * l_v / l_av.powf(0.8))
}

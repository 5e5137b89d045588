//! The eye's point-spread function for glare. θ in degrees of visual
//! angle, λ in nm; values in sr⁻¹ (the veiling luminance per illuminance
//! at the eye, L_veil/E_glare).
//!
//! - The scatter: CIE 146:2002's General Disability Glare equation, for
//!   an observer of age A (years) and eye pigmentation p (0 dark, 0.5
//!   brown, 1 light blue), valid from 0.1° to 100°:
//!
//!   L_veil/E_glare = 10/θ³ + (5/θ² + 0.1·p/θ)·(1 + (A/62.5)⁴) + 0.0025·p
//!
//!   (Vos 2003, Clin. Exp. Optom. 86:363, restating the standard; the
//!   values 0.0677 sr⁻¹ at 25 years and 0.153 at 70 for θ = 10°, p = 0.5,
//!   are tested). It carries about a quarter of the light entering the
//!   eye; the rest lands within 0.1° of the image point, in the optics'
//!   core, which scotopia shapes as the core of the complete CIE glare
//!   spread function (Vos & van den Berg, CIE 135/1:1999:
//!   9.2·10⁶/(1 + (θ/0.0046)²)^1.5 + 1.5·10⁵/(1 + (θ/0.045)²)^1.5), scaled
//!   and raised by a constant so that it meets the general equation at
//!   0.1° and the whole PSF integrates to 1 over solid angle: every ray
//!   that enters the eye lands somewhere. The core is a fraction of a
//!   pixel wide at the usual fields of view, so its shape matters only for
//!   the sampling; its share of the light (1 less the general equation's
//!   integral: 0.72 at 25 years, 0.61 at 70) is the standard's.
//! - The lenticular halo of Spencer, Shirley, Zimmerman & Greenberg 1995
//!   ("Physically-Based Glare Effects for Digital Images", SIGGRAPH):
//!   f3 = 436.9·(568/λ)·exp(−19.75·(θ − 3λ/568)²), a ring of radius
//!   3λ/568 degrees (3° at 568 nm), so red rings lie outside blue ones;
//!   with the factor 19.75 it integrates to ≈ 1 (tested). It is seen with
//!   a dilated pupil: Spencer et al.'s weight for it is 0 photopic, 0.016
//!   mesopic and 0.033 scotopic (../shared/vision-equations.md §1,
//!   unverified against the paper), and the mixture is
//!   (1 − w)·GSF + w·f3.
//!
//! Angles are taken on the image plane as pixel distance × degrees per
//! pixel, and solid angles as (degrees per pixel)² in steradians: the
//! small-angle form, which the whole pipeline uses.

use rayon::prelude::*;
use scotopia_color::cie;

use crate::observer::Observer;

/// Degrees to radians, squared: a solid angle in sr per degree².
const SR_PER_DEG2: f64 = (std::f64::consts::PI / 180.0) * (std::f64::consts::PI / 180.0);

/// The widest angle the PSF reaches: scattered light stays within the
/// hemisphere in front of the eye (CIE's function holds to 100°).
pub const MAX_ANGLE: f64 = 90.0;

/// Where CIE 146's general equation begins, degrees; inside it, the core.
pub const CORE_ANGLE: f64 = 0.1;

/// The glare spread function for one observer.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GlareSpread {
    /// (1 + (A/62.5)⁴): the stray light's growth with age.
    age_factor: f64,
    pigmentation: f64,
    /// The core inside CORE_ANGLE: core_scale·shape(θ) + core_floor, so
    /// it meets the general equation at CORE_ANGLE (a PSF that stepped up
    /// there would draw a ring) and holds the rest of the light.
    core_scale: f64,
    core_floor: f64,
}

impl GlareSpread {
    pub fn new(observer: &Observer) -> Self {
        let mut g = Self {
            age_factor: 1.0 + (observer.age / 62.5).powi(4),
            pigmentation: observer.pigmentation,
            core_scale: 0.0,
            core_floor: 0.0,
        };
        // Two conditions, two unknowns: continuity at CORE_ANGLE, and the
        // whole integrating to 1 (the disc of the constant is π·r²).
        let edge = g.general(CORE_ANGLE);
        let disc = std::f64::consts::PI * CORE_ANGLE * CORE_ANGLE * SR_PER_DEG2;
        let shape_edge = Self::core_shape(CORE_ANGLE);
        let share = 1.0 - g.general_disc(MAX_ANGLE);
        g.core_scale =
            (share - edge * disc) / (Self::core_shape_disc(CORE_ANGLE) - shape_edge * disc);
        g.core_floor = edge - g.core_scale * shape_edge;
        g
    }

    /// CIE 146:2002's General Disability Glare equation, sr⁻¹: the veiling
    /// luminance (cd/m²) per lux at the eye from a point θ degrees away
    /// (valid from 0.1° to 100°).
    pub fn general(&self, theta: f64) -> f64 {
        let p = self.pigmentation;
        10.0 / theta.powi(3)
            + (5.0 / (theta * theta) + 0.1 * p / theta) * self.age_factor
            + 0.0025 * p
    }

    /// The core's shape, the complete CIE function's first two terms.
    fn core_shape(theta: f64) -> f64 {
        let q = |a: f64| 1.0 + (theta / a) * (theta / a);
        9.2e6 / q(0.0046).powf(1.5) + 1.5e5 / q(0.045).powf(1.5)
    }

    /// The PSF, sr⁻¹: the core inside CORE_ANGLE, the general equation
    /// outside, 0 beyond MAX_ANGLE; integral 1.
    pub fn eval(&self, theta: f64) -> f64 {
        if theta < CORE_ANGLE {
            self.core_scale * Self::core_shape(theta) + self.core_floor
        } else if theta <= MAX_ANGLE {
            self.general(theta)
        } else {
            0.0
        }
    }

    /// ∫ core_shape dΩ over θ ≤ r (sr·sr⁻¹), closed form: for
    /// (1 + (θ/a)²)^−1.5, ∫ 2πθ dθ = 2πa²·(1 − (1 + (r/a)²)^−½).
    fn core_shape_disc(r: f64) -> f64 {
        let term = |a: f64| {
            let q = 1.0 + (r / a) * (r / a);
            2.0 * std::f64::consts::PI * a * a * (1.0 - q.powf(-0.5))
        };
        (9.2e6 * term(0.0046) + 1.5e5 * term(0.045)) * SR_PER_DEG2
    }

    /// ∫ general dΩ over CORE_ANGLE ≤ θ ≤ r, closed form.
    fn general_disc(&self, r: f64) -> f64 {
        use std::f64::consts::PI;
        let (t0, p) = (CORE_ANGLE, self.pigmentation);
        if r <= t0 {
            return 0.0;
        }
        let sum = 2.0 * PI * 10.0 * (1.0 / t0 - 1.0 / r)
            + 2.0 * PI * self.age_factor * (5.0 * (r / t0).ln() + 0.1 * p * (r - t0))
            + PI * 0.0025 * p * (r * r - t0 * t0);
        sum * SR_PER_DEG2
    }

    /// The share of a point's light that lands within r degrees of it.
    pub fn share_within(&self, r: f64) -> f64 {
        let r = r.min(MAX_ANGLE);
        let inner = r.min(CORE_ANGLE);
        self.core_scale * Self::core_shape_disc(inner)
            + self.core_floor * std::f64::consts::PI * inner * inner * SR_PER_DEG2
            + self.general_disc(r)
    }

    /// The share of the light in the core (within CORE_ANGLE).
    pub fn core_share(&self) -> f64 {
        self.share_within(CORE_ANGLE)
    }
}

/// The lenticular halo f3 at θ degrees and λ nm.
pub fn halo_term(theta: f64, lambda: f64) -> f64 {
    let ring = 3.0 * lambda / 568.0;
    436.9 * (568.0 / lambda) * (-19.75 * (theta - ring).powi(2)).exp()
}

/// Spencer et al.'s halo weight for photopic, mesopic and scotopic vision.
pub const HALO_WEIGHTS: [f64; 3] = [0.0, 0.016, 0.033];

/// The halo's weight for scotopic sensitivity s (1 photopic, 0
/// scotopic): linear from scotopic (s = 0) to mesopic (½) to photopic (1).
pub fn halo_weight(s: f64) -> f64 {
    let s = s.clamp(0.0, 1.0);
    let [p, m, sc] = HALO_WEIGHTS;
    if s < 0.5 {
        sc + (m - sc) * s / 0.5
    } else {
        m + (p - m) * (s - 0.5) / 0.5
    }
}

/// The halo per output channel: f3 averaged over λ with the channel's
/// spectral response (x̄, ȳ, z̄, V′) as weight, tabulated in θ.
#[derive(Debug, Clone)]
pub struct Halo {
    /// Per channel, f3 at θ = i·STEP.
    table: [Vec<f64>; 4],
}

impl Halo {
    const STEP: f64 = 0.005;
    const MAX: f64 = 8.0;

    /// The table, computed once per process (1.3 M evaluations of f3).
    pub fn shared() -> &'static Self {
        static HALO: std::sync::OnceLock<Halo> = std::sync::OnceLock::new();
        HALO.get_or_init(Self::new)
    }

    pub fn new() -> Self {
        let n = (Self::MAX / Self::STEP) as usize + 1;
        let lambdas: Vec<f64> = (380..=780).step_by(2).map(|l| l as f64).collect();
        let weights: [Vec<f64>; 4] = std::array::from_fn(|c| {
            lambdas
                .iter()
                .map(|&l| cie::observers(l as f32)[c] as f64)
                .collect()
        });
        let totals: [f64; 4] = std::array::from_fn(|c| weights[c].iter().sum());
        // Each f3(θ, λ) once for the four channels (it does not depend on
        // the channel), each θ on its own, in parallel: it runs in every
        // fresh process that shows a dark scene.
        let rows: Vec<[f64; 4]> = (0..n)
            .into_par_iter()
            .map(|i| {
                let theta = i as f64 * Self::STEP;
                let mut sums = [0.0f64; 4];
                for (k, &l) in lambdas.iter().enumerate() {
                    let f = halo_term(theta, l);
                    for c in 0..4 {
                        sums[c] += weights[c][k] * f;
                    }
                }
                std::array::from_fn(|c| sums[c] / totals[c])
            })
            .collect();
        let table = std::array::from_fn(|c| rows.iter().map(|r| r[c]).collect());
        Self { table }
    }

    /// f3 for channel `c` (0 X, 1 Y, 2 Z, 3 V′) at θ degrees.
    pub fn eval(&self, c: usize, theta: f64) -> f64 {
        self.eval_all(theta)[c]
    }

    /// f3 for all four channels at θ degrees.
    pub fn eval_all(&self, theta: f64) -> [f64; 4] {
        let x = theta / Self::STEP;
        let n = self.table[0].len();
        if x.is_nan() || x < 0.0 || x >= (n - 1) as f64 {
            return [0.0; 4];
        }
        let i = x as usize;
        let f = x - i as f64;
        std::array::from_fn(|c| {
            let t = &self.table[c];
            t[i] + f * (t[i + 1] - t[i])
        })
    }
}

impl Default for Halo {
    fn default() -> Self {
        Self::new()
    }
}

/// The whole PSF for one observer and visual state: per channel
/// (X, Y, Z, V′), sr⁻¹, integrating to 1 (up to MAX_ANGLE).
#[derive(Debug, Clone, Copy)]
pub struct Psf {
    pub spread: GlareSpread,
    /// The halo's weight w (0: none).
    pub halo: f64,
}

impl Psf {
    pub fn new(observer: &Observer, s: f64) -> Self {
        Self {
            spread: GlareSpread::new(observer),
            halo: halo_weight(s),
        }
    }

    /// The PSF at θ degrees, per channel.
    pub fn eval(&self, theta: f64) -> [f64; 4] {
        let shared = (1.0 - self.halo) * self.spread.eval(theta);
        if self.halo > 0.0 {
            Halo::shared()
                .eval_all(theta)
                .map(|f| shared + self.halo * f)
        } else {
            [shared; 4]
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ f(θ) dΩ over 0 ≤ θ ≤ limit degrees, solid angle in steradians,
    /// small-angle form, by the midpoint rule on a log-spaced grid (the
    /// core is 0.0046° wide).
    fn solid_integral(f: impl Fn(f64) -> f64, limit: f64) -> f64 {
        let n = 400_000;
        let (lo, hi) = (1e-6f64.ln(), limit.ln());
        let h = (hi - lo) / n as f64;
        let mut sum = f(0.0) * std::f64::consts::PI * 1e-12;
        for i in 0..n {
            let t = (lo + (i as f64 + 0.5) * h).exp();
            // dθ = θ·d(ln θ).
            sum += f(t) * 2.0 * std::f64::consts::PI * t * t * h;
        }
        sum * SR_PER_DEG2
    }

    #[test]
    fn the_psf_integrates_to_one_and_its_shares_are_exact() {
        for (age, p) in [(25.0, 0.5), (70.0, 0.5), (25.0, 0.0), (80.0, 1.0)] {
            let g = GlareSpread::new(&Observer::new(age, p).unwrap());
            let numeric = solid_integral(|t| g.eval(t), MAX_ANGLE);
            assert!((numeric - 1.0).abs() < 1e-4, "{age} {p}: {numeric}");
            for r in [0.01, 0.1, 1.0, 10.0, 45.0] {
                let n = solid_integral(|t| g.eval(t), r);
                assert!((n / g.share_within(r) - 1.0).abs() < 1e-4, "{r}: {n}");
            }
            // The core's share: most light, less with age.
            let core = g.core_share();
            assert!(core > 0.4 && core < 0.8, "{age}: {core}");
        }
        let share = |age| GlareSpread::new(&Observer::new(age, 0.5).unwrap()).core_share();
        assert!(share(70.0) < share(25.0) - 0.1);
    }

    #[test]
    fn the_standard_values_at_ten_degrees() {
        // CIE 146's general equation (../shared/vision-equations.md §9):
        // 0.0677 sr⁻¹ at 25 years and 0.153 at 70 (p = 0.5, θ = 10°).
        for (age, want) in [(25.0, 0.0677), (70.0, 0.153)] {
            let g = GlareSpread::new(&Observer::new(age, 0.5).unwrap());
            let v = g.eval(10.0);
            assert!((v / want - 1.0).abs() < 0.005, "{age}: {v} vs {want}");
        }
    }

    #[test]
    fn the_psf_falls_monotonically() {
        for age in [25.0, 70.0] {
            let g = GlareSpread::new(&Observer::new(age, 0.5).unwrap());
            let mut last = f64::INFINITY;
            for i in 0..20_000 {
                let t = i as f64 * 0.0045;
                let v = g.eval(t);
                assert!(v < last || (v == 0.0 && last == 0.0), "{t}: {v} {last}");
                last = v;
            }
        }
    }

    #[test]
    fn the_halo_integrates_to_one_and_is_red_outside_blue_inside() {
        let f3 = solid_integral(|t| halo_term(t, 568.0), 8.0);
        assert!((f3 - 1.0).abs() < 0.01, "{f3}");
        let halo = Halo::new();
        let peak = |c: usize| {
            (0..1600)
                .map(|i| i as f64 * 0.005)
                .max_by(|a, b| halo.eval(c, *a).total_cmp(&halo.eval(c, *b)))
                .unwrap()
        };
        let (x, y, z) = (peak(0), peak(1), peak(2));
        assert!(z < y && y < x, "X {x}°, Y {y}°, Z {z}°");
        // Near 3° · λ/568: Z peaks near 450 nm (2.4°), Y near 556 nm (2.9°).
        assert!((z - 2.4).abs() < 0.15 && (y - 2.95).abs() < 0.1, "{y} {z}");
    }

    #[test]
    fn the_halo_weight_blends_the_three_states() {
        assert_eq!(halo_weight(1.0), 0.0);
        assert_eq!(halo_weight(0.5), 0.016);
        assert_eq!(halo_weight(0.0), 0.033);
        assert!(halo_weight(0.25) > 0.016 && halo_weight(0.25) < 0.033);
    }
}

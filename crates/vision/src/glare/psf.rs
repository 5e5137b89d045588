//! The point-spread function of the eye's glare, after Spencer, Shirley,
//! Zimmerman & Greenberg 1995 ("Physically-Based Glare Effects for Digital
//! Images", SIGGRAPH; ../shared/vision-equations.md §1). θ in degrees of
//! visual angle, λ in nm. Four components:
//!
//! - f0 = 2.61·10⁶·exp(−(θ/0.02)²): the core (the optics' own blur);
//! - f1 = 20.91/(θ + 0.02)³ and f2 = 72.37/(θ + 0.02)²: flare and bloom,
//!   light scattered in the cornea, lens and retina;
//! - f3 = 436.9·(568/λ)·exp(−19.75·(θ − 3λ/568)²): the lenticular halo, a
//!   ring of radius 3λ/568 degrees (3° at 568 nm), so red rings lie outside
//!   blue ones. The factor 19.75 is in one source and not another; with it
//!   every component integrates to ≈ 1 over solid angle in steradians
//!   (θ in degrees; tested), so it is kept.
//!
//! Mixture weights by visual state (photopic, mesopic, scotopic) from the
//! same sheet, marked unverified there (docs/vision.md).

use rayon::prelude::*;
use scotopia_color::cie;

/// The core, flare and bloom terms f0, f1, f2 at θ degrees.
pub fn scatter_terms(theta: f64) -> [f64; 3] {
    let t = theta + 0.02;
    // The core is below 1e-300 of its peak beyond 0.53°: not evaluated.
    let core = if theta < 0.53 {
        2.61e6 * (-(theta / 0.02).powi(2)).exp()
    } else {
        0.0
    };
    [core, 20.91 / (t * t * t), 72.37 / (t * t)]
}

/// The lenticular halo f3 at θ degrees and λ nm.
pub fn halo_term(theta: f64, lambda: f64) -> f64 {
    let ring = 3.0 * lambda / 568.0;
    436.9 * (568.0 / lambda) * (-19.75 * (theta - ring).powi(2)).exp()
}

/// f0…f3 at θ degrees (the halo at λ nm).
pub fn components(theta: f64, lambda: f64) -> [f64; 4] {
    let [f0, f1, f2] = scatter_terms(theta);
    [f0, f1, f2, halo_term(theta, lambda)]
}

/// Weights of f0…f3 for photopic, mesopic and scotopic vision.
pub const WEIGHTS: [[f64; 4]; 3] = [
    [0.384, 0.478, 0.138, 0.0],
    [0.368, 0.478, 0.138, 0.016],
    [0.282, 0.478, 0.207, 0.033],
];

/// The weights for scotopic sensitivity s (1 photopic, 0 scotopic):
/// linear from scotopic (s = 0) to mesopic (s = ½) to photopic (s = 1).
pub fn weights(s: f64) -> [f64; 4] {
    let s = s.clamp(0.0, 1.0);
    let (a, b, t) = if s < 0.5 {
        (WEIGHTS[2], WEIGHTS[1], s / 0.5)
    } else {
        (WEIGHTS[1], WEIGHTS[0], (s - 0.5) / 0.5)
    };
    std::array::from_fn(|k| a[k] + t * (b[k] - a[k]))
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

/// The widest angle the PSF reaches: scattered light stays within the
/// hemisphere in front of the eye (scotopia's bound; the 1/θ² bloom would
/// otherwise put 2 % of its light beyond 64° for ever wider grids).
pub const MAX_ANGLE: f64 = 90.0;

/// The part of the PSF every channel shares, w0·f0 + w1·f1 + w2·f2, at θ
/// degrees (0 beyond 90°); the halo, w3·f3, is `Halo::eval` per channel.
pub fn scatter(theta: f64, w: &[f64; 4]) -> f64 {
    if theta > MAX_ANGLE {
        return 0.0;
    }
    let [f0, f1, f2] = scatter_terms(theta);
    w[0] * f0 + w[1] * f1 + w[2] * f2
}

#[cfg(test)]
mod tests {
    use super::*;

    /// ∫ f(θ) dΩ over 0 ≤ θ ≤ limit degrees, solid angle in steradians
    /// (the constants' normalisation, θ in degrees), small-angle form.
    fn solid_integral(f: impl Fn(f64) -> f64, limit: f64) -> f64 {
        let n = 400_000;
        let h = limit / n as f64;
        (0..n)
            .map(|i| {
                let t = (i as f64 + 0.5) * h;
                f(t) * 2.0 * std::f64::consts::PI * t * h
            })
            .sum::<f64>()
            * (std::f64::consts::PI / 180.0).powi(2)
    }

    #[test]
    fn components_integrate_to_about_one() {
        let f0 = solid_integral(|t| components(t, 568.0)[0], 1.0);
        let f1 = solid_integral(|t| components(t, 568.0)[1], 90.0);
        let f3 = solid_integral(|t| components(t, 568.0)[3], 8.0);
        assert!((f0 - 1.0).abs() < 0.01, "{f0}");
        assert!((f1 - 1.0).abs() < 0.01, "{f1}");
        assert!((f3 - 1.0).abs() < 0.01, "{f3}");
    }

    #[test]
    fn weights_blend_the_three_states() {
        assert_eq!(weights(1.0), WEIGHTS[0]);
        assert_eq!(weights(0.5), WEIGHTS[1]);
        assert_eq!(weights(0.0), WEIGHTS[2]);
        for s in [0.0, 0.3, 0.7, 1.0] {
            assert!((weights(s).iter().sum::<f64>() - 1.0).abs() < 1e-9);
        }
    }

    #[test]
    fn the_halo_is_red_outside_blue_inside() {
        // The radius where each channel's halo peaks: X (with its long-
        // wavelength lobe) and Y outside Z (blue).
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
}

//! Phase functions: isotropic and Henyey–Greenstein (1941), Mitsuba's
//! `isotropic` and `hg`. Directions point away from the scattering point:
//! `wi` back towards where the path came from, `wo` onwards; the
//! scattering angle θ has cos θ = −wi·wo (0 for straight on).

use std::f32::consts::PI;

use crate::math::{Frame, Vec3};

const INV_4PI: f32 = 1.0 / (4.0 * PI);

#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Phase {
    Isotropic,
    /// Henyey–Greenstein with mean cosine `g` ∈ (−1, 1): forward
    /// scattering for g > 0 (fog droplets: 0.7–0.9).
    HenyeyGreenstein {
        g: f32,
    },
}

/// HG's density of the scattering cosine μ, per steradian:
/// (1 − g²) / (4π (1 + g² − 2gμ)^{3/2}) (Henyey & Greenstein 1941, eq. 3).
fn henyey_greenstein(g: f32, mu: f32) -> f32 {
    let d = 1.0 + g * g - 2.0 * g * mu;
    INV_4PI * (1.0 - g * g) / (d * d.max(0.0).sqrt())
}

impl Phase {
    /// The value (and density) of scattering from `wi` into `wo`, per sr.
    pub fn eval(&self, wi: Vec3, wo: Vec3) -> f32 {
        match *self {
            Phase::Isotropic => INV_4PI,
            Phase::HenyeyGreenstein { g } => henyey_greenstein(g, -wi.dot(wo)),
        }
    }

    /// A direction `wo` drawn by the phase function itself, with its
    /// density (equal to its value: the sampling is exact).
    pub fn sample(&self, wi: Vec3, u: [f32; 2]) -> (Vec3, f32) {
        let mu = match *self {
            Phase::Isotropic => 1.0 - 2.0 * u[0],
            Phase::HenyeyGreenstein { g } if g.abs() < 1e-3 => 1.0 - 2.0 * u[0],
            // The inverse of HG's cumulative distribution in μ.
            Phase::HenyeyGreenstein { g } => {
                let s = (1.0 - g * g) / (1.0 - g + 2.0 * g * u[0]);
                ((1.0 + g * g - s * s) / (2.0 * g)).clamp(-1.0, 1.0)
            }
        };
        let sin = (1.0 - mu * mu).max(0.0).sqrt();
        let phi = 2.0 * PI * u[1];
        // μ is measured from the direction of travel, −wi.
        let frame = Frame::from_normal(-wi);
        let wo = frame.to_world(Vec3::new(sin * phi.cos(), sin * phi.sin(), mu));
        (wo, self.eval(wi, wo))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::test_rng::uniforms;

    const PHASES: [Phase; 4] = [
        Phase::Isotropic,
        Phase::HenyeyGreenstein { g: 0.0 },
        Phase::HenyeyGreenstein { g: 0.85 },
        Phase::HenyeyGreenstein { g: -0.4 },
    ];

    #[test]
    fn each_phase_function_integrates_to_one() {
        // Midpoint rule in μ (the functions depend on μ only): 2π ∫ p dμ.
        let wi = Vec3::new(0.0, 0.0, 1.0);
        let n = 200_000;
        for p in PHASES {
            let sum: f64 = (0..n)
                .map(|k| {
                    let mu = -1.0 + 2.0 * (k as f64 + 0.5) / n as f64;
                    let s = (1.0 - mu * mu).sqrt();
                    p.eval(wi, Vec3::new(s as f32, 0.0, -mu as f32)) as f64
                })
                .sum::<f64>()
                * 2.0
                / n as f64
                * 2.0
                * std::f64::consts::PI;
            assert!((sum - 1.0).abs() < 1e-3, "{p:?}: {sum}");
        }
    }

    #[test]
    fn sampled_directions_follow_the_density_and_the_mean_cosine_is_g() {
        // χ² over 20 bins of μ against the density's integral per bin
        // (2π ∫ p dμ, by the midpoint rule), and the mean of μ against g
        // (4 standard errors).
        let wi = Vec3::new(0.3, -0.5, 0.8).normalize();
        let (bins, n) = (20usize, 200_000usize);
        for p in PHASES {
            let mut u = uniforms(11);
            let mut counts = vec![0f64; bins];
            let (mut sum, mut sum2) = (0.0f64, 0.0f64);
            for _ in 0..n {
                let (wo, pdf) = p.sample(wi, [u(), u()]);
                assert!((wo.length() - 1.0).abs() < 1e-4);
                assert!((pdf - p.eval(wi, wo)).abs() <= 1e-4 * pdf.max(1.0));
                let mu = -wi.dot(wo) as f64;
                counts[(((mu + 1.0) / 2.0 * bins as f64) as usize).min(bins - 1)] += 1.0;
                sum += mu;
                sum2 += mu * mu;
            }
            let mut chi2 = 0.0;
            for (b, c) in counts.iter().enumerate() {
                let m = 400;
                let mass: f64 = (0..m)
                    .map(|k| {
                        let mu =
                            -1.0 + (b as f64 + (k as f64 + 0.5) / m as f64) * 2.0 / bins as f64;
                        let s = (1.0 - mu * mu).sqrt();
                        let wo =
                            Frame::from_normal(-wi).to_world(Vec3::new(s as f32, 0.0, mu as f32));
                        p.eval(wi, wo) as f64
                    })
                    .sum::<f64>()
                    * (2.0 / bins as f64 / m as f64)
                    * 2.0
                    * std::f64::consts::PI;
                let expected = mass * n as f64;
                chi2 += (c - expected).powi(2) / expected;
            }
            let dof = (bins - 1) as f64;
            assert!(chi2 < dof + 5.0 * (2.0 * dof).sqrt(), "{p:?}: χ² {chi2}");
            let mean = sum / n as f64;
            let se = ((sum2 / n as f64 - mean * mean) / n as f64).sqrt();
            let g = match p {
                Phase::Isotropic => 0.0,
                Phase::HenyeyGreenstein { g } => g as f64,
            };
            assert!(
                (mean - g).abs() < 4.0 * se,
                "{p:?}: mean cosine {mean} ± {se}"
            );
        }
    }
}

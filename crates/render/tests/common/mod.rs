//! Statistical helpers for sampling tests: a seeded generator and the
//! chi-square goodness-of-fit test of sampled directions against a pdf
//! (the test Mitsuba's and Nori's `chi2test` perform).

#![allow(dead_code)]

pub mod bsdf_checks;
pub mod principled;

use scotopia_render::math::Vec3;

/// SplitMix64, seeded.
pub struct Rng(pub u64);

impl Rng {
    pub fn next(&mut self) -> f32 {
        self.0 = self.0.wrapping_add(0x9e37_79b9_7f4a_7c15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xbf58_476d_1ce4_e5b9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94d0_49bb_1331_11eb);
        ((z ^ (z >> 31)) >> 40) as f32 / (1u64 << 24) as f32
    }

    pub fn pair(&mut self) -> [f32; 2] {
        [self.next(), self.next()]
    }

    /// A point uniform in the cube [−half, half]³.
    pub fn point(&mut self, half: f32) -> Vec3 {
        Vec3::new(self.next() - 0.5, self.next() - 0.5, self.next() - 0.5) * (2.0 * half)
    }

    /// A unit direction, uniform over the sphere (by rejection).
    pub fn direction(&mut self) -> Vec3 {
        loop {
            let v = self.point(1.0);
            if v.length_squared() > 1e-4 && v.length_squared() <= 1.0 {
                return v.normalize();
            }
        }
    }
}

/// ln Γ(x), Lanczos approximation (g = 7, n = 9), accurate to ~1e-15.
fn ln_gamma(x: f64) -> f64 {
    const C: [f64; 9] = [
        0.999_999_999_999_809_9,
        676.520_368_121_885_1,
        -1_259.139_216_722_402_8,
        771.323_428_777_653_1,
        -176.615_029_162_140_6,
        12.507_343_278_686_905,
        -0.138_571_095_265_720_12,
        9.984_369_578_019_572e-6,
        1.505_632_735_149_311_6e-7,
    ];
    let x = x - 1.0;
    let t = x + 7.5;
    let mut a = C[0];
    for (i, c) in C.iter().enumerate().skip(1) {
        a += c / (x + i as f64);
    }
    0.5 * (2.0 * std::f64::consts::PI).ln() + (x + 0.5) * t.ln() - t + a.ln()
}

/// The regularised upper incomplete gamma function Q(a, x): series for
/// x < a + 1, Lentz's continued fraction otherwise.
pub fn gamma_q(a: f64, x: f64) -> f64 {
    if x <= 0.0 {
        return 1.0;
    }
    let lg = ln_gamma(a);
    if x < a + 1.0 {
        let (mut sum, mut term, mut n) = (1.0 / a, 1.0 / a, a);
        for _ in 0..10_000 {
            n += 1.0;
            term *= x / n;
            sum += term;
            if term.abs() < sum.abs() * 1e-15 {
                break;
            }
        }
        1.0 - sum * (-x + a * x.ln() - lg).exp()
    } else {
        let tiny = 1e-300;
        let mut b = x + 1.0 - a;
        let mut c = 1.0 / tiny;
        let mut d = 1.0 / b;
        let mut h = d;
        for i in 1..10_000 {
            let an = -(i as f64) * (i as f64 - a);
            b += 2.0;
            d = an * d + b;
            if d.abs() < tiny {
                d = tiny;
            }
            c = b + an / c;
            if c.abs() < tiny {
                c = tiny;
            }
            d = 1.0 / d;
            let delta = d * c;
            h *= delta;
            if (delta - 1.0).abs() < 1e-15 {
                break;
            }
        }
        (-x + a * x.ln() - lg).exp() * h
    }
}

/// Chi-square test that `sample` (None = no sample) draws directions with
/// density `pdf` over the sphere. Bins are uniform in (cos θ, φ), the
/// expected counts are integrated from `pdf` by a midpoint rule, bins
/// expecting fewer than 5 are pooled, and a missing probability mass is
/// compared with the count of failed samples. Returns the p-value.
pub fn chi2_directions(
    n: usize,
    rng: &mut Rng,
    mut sample: impl FnMut(&mut Rng) -> Option<Vec3>,
    pdf: impl Fn(Vec3) -> f64,
) -> f64 {
    const THETA: usize = 10;
    const PHI: usize = 20;
    // Midpoint sub-samples per bin in θ and in φ: narrow lobes (a rough
    // refraction at normal incidence) need the finer θ steps.
    const SUB_T: usize = 256;
    const SUB_P: usize = 16;
    let bin_of = |w: Vec3| {
        let c = ((w.z.clamp(-1.0, 1.0) + 1.0) * 0.5 * THETA as f32) as usize;
        let phi = w.y.atan2(w.x).rem_euclid(2.0 * std::f32::consts::PI);
        let p = (phi / (2.0 * std::f32::consts::PI) * PHI as f32) as usize;
        c.min(THETA - 1) * PHI + p.min(PHI - 1)
    };
    let mut observed = vec![0.0f64; THETA * PHI + 1];
    for _ in 0..n {
        match sample(rng) {
            Some(w) => observed[bin_of(w)] += 1.0,
            None => observed[THETA * PHI] += 1.0,
        }
    }
    let mut expected = vec![0.0f64; THETA * PHI + 1];
    let (dc, dp) = (2.0 / THETA as f64, 2.0 * std::f64::consts::PI / PHI as f64);
    for t in 0..THETA {
        // Integrate each bin in θ (dω = sin θ dθ dφ): uniform steps in cos θ
        // would miss a narrow lobe at a pole.
        let (th_hi, th_lo) = (
            (-1.0 + dc * (t + 1) as f64).acos(),
            (-1.0 + dc * t as f64).acos(),
        );
        let dth = (th_lo - th_hi) / SUB_T as f64;
        for p in 0..PHI {
            let mut sum = 0.0;
            for a in 0..SUB_T {
                let th = th_hi + dth * (a as f64 + 0.5);
                let (s, c) = th.sin_cos();
                for b in 0..SUB_P {
                    let phi = dp * (p as f64 + (b as f64 + 0.5) / SUB_P as f64);
                    let w = Vec3::new((s * phi.cos()) as f32, (s * phi.sin()) as f32, c as f32);
                    sum += pdf(w) * s;
                }
            }
            expected[t * PHI + p] = sum * dth * dp / SUB_P as f64 * n as f64;
        }
    }
    let total: f64 = expected[..THETA * PHI].iter().sum();
    expected[THETA * PHI] = (n as f64 - total).max(0.0);
    // Pool the bins that expect too few.
    if std::env::var("CHI2_DEBUG").is_ok() {
        for (i, (o, e)) in observed.iter().zip(&expected).enumerate() {
            if (o - e).abs() > 3.0 * e.sqrt().max(1.0) {
                eprintln!(
                    "bin {i} (θ row {}, φ {}): observed {o} expected {e:.1}",
                    i / PHI,
                    i % PHI
                );
            }
        }
    }
    chi2_p_value(&observed, &expected)
}

/// Pearson's chi-square p-value of `observed` counts against `expected`
/// ones, pooling the bins that expect fewer than 5.
pub fn chi2_p_value(observed: &[f64], expected: &[f64]) -> f64 {
    let (mut chi2, mut dof, mut pool_o, mut pool_e) = (0.0, 0usize, 0.0, 0.0);
    for (o, e) in observed.iter().zip(expected) {
        if *e < 5.0 {
            pool_o += o;
            pool_e += e;
        } else {
            chi2 += (o - e) * (o - e) / e;
            dof += 1;
        }
    }
    if pool_e >= 5.0 {
        chi2 += (pool_o - pool_e) * (pool_o - pool_e) / pool_e;
        dof += 1;
    } else if pool_o > pool_e {
        // Too few expected for Pearson's statistic: the exact Poisson tail
        // P(X ≥ pool_o) of samples where the pdf says there should be
        // (almost) none, combined with the chi-square by Bonferroni.
        let tail = poisson_upper_tail(pool_e, pool_o.round() as u64);
        let p = gamma_q((dof - 1) as f64 / 2.0, chi2 / 2.0);
        return (2.0 * p.min(tail)).min(1.0);
    }
    gamma_q((dof - 1) as f64 / 2.0, chi2 / 2.0)
}

/// P(X ≥ k) for X ~ Poisson(λ): 1 − Σ_{j<k} e^{−λ} λ^j / j!.
fn poisson_upper_tail(lambda: f64, k: u64) -> f64 {
    let (mut term, mut below) = ((-lambda).exp(), 0.0);
    for j in 0..k {
        below += term;
        term *= lambda / (j + 1) as f64;
    }
    (1.0 - below).max(0.0)
}

#[test]
fn poisson_tail_known_values() {
    // P(X ≥ 1) = 1 − e^{−λ}; P(X ≥ 0) = 1; P(X ≥ 6 | λ = 1.5) from the pmf.
    assert!((poisson_upper_tail(2.0, 1) - (1.0 - (-2.0f64).exp())).abs() < 1e-12);
    assert_eq!(poisson_upper_tail(2.0, 0), 1.0);
    assert!((poisson_upper_tail(1.5, 6) - 0.004_455_98).abs() < 1e-8);
}

#[test]
fn gamma_q_known_values() {
    // Q(1, x) = e^{−x}; Q(½, x) = erfc(√x); the others from SciPy's gammaincc.
    assert!((gamma_q(1.0, 2.0) - (-2.0f64).exp()).abs() < 1e-12);
    assert!((gamma_q(0.5, 1.0) - 0.157_299_207_050_285_1).abs() < 1e-10);
    assert!((gamma_q(10.0, 30.0) - 7.121_750_862_815_593e-6).abs() < 1e-12);
    assert!((gamma_q(50.0, 45.0) - 0.753_197_965_599_829_8).abs() < 1e-10);
}
